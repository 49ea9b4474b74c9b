// Beltrami core: the parts of a line drawing that the camera sees.
//
// A point of a line is hidden when the segment from it to the eye (along
// the view direction, orthographic) passes through a triangle of the
// surface, found by casting that segment through a bounding-volume tree of
// the triangles: exact against the triangulated surface, at any output
// resolution.  The two rings of triangles around the point's face are not
// tested: a contour lies where the surface turns away from the eye, and the
// piecewise-flat surface next to it may cross the grazing ray within a
// triangle or two of the point.  Each point of a line is tested, and each
// piece (within one face) at least every feature size between its ends;
// where two tests differ, the change of visibility is found by bisection
// to 2^-12 of the piece, and the line is split there.
#pragma once

#include "Drawing/LineDrawing.h"

namespace beltrami
{

struct VisibilityOptions
{
  /// Keep the hidden parts, as lines with Hidden = 1 (else they are dropped).
  bool KeepHidden = false;
  /// Parts shorter than this (a length) are dropped, but for boundaries and
  /// creases (the options' MinimumLength times the feature size: a contour
  /// that shows for a moment between two occluders is as short as noise).
  double MinimumLength = 0.0;
  int NumberOfThreads = 0;
};

/// `lines` (drawn on `geometry` for `view`: their EdgeFace known) split into
/// their visible and hidden parts.  The result's Hidden says which each line
/// is; a closed line that no other part of the surface hides stays closed.
/// Lines of unknown faces (EdgeFace -1) are kept as visible.  Split runs
/// (`geometry` split over the processes; collective): each process casts
/// every process' rays through its own triangles, with the stars of its
/// ghost vertices from their owners, so the surface is never gathered;
/// the lines are process 0's (DrawLines), the others pass none.
LineSet SplitByVisibility(const LineSet& lines, const LineDrawingGeometry& geometry, const LineView& view,
  const VisibilityOptions& options = {});

} // namespace beltrami
