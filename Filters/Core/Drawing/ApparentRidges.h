// Beltrami core: apparent ridges (Judd, Durand & Adelson 2007), the ridges
// of the surface as the viewer sees it.
//
// The view-dependent shape operator Q = S P^-1 maps a displacement in the
// image plane (the plane across the view direction v at the point) to the
// turn of the normal: S the shape operator, P the projection of the tangent
// plane onto the image plane.  Its largest singular value q1 is the maximum
// view-dependent curvature, reached along the image of the tangent
// direction t1: q1^2 = max over tangent t of |S t|^2 / |P t|^2, with
// |P t|^2 = |t|^2 - (t.w)^2, w the tangent part of v; that is the largest
// eigenvalue of (I - w w^T)^-1 S^2 = (I + w w^T / (n.v)^2) S^2 in the
// principal frame, t1 its eigenvector.  Apparent ridges are where q1 is a
// maximum along t1: D_t1 q1 = 0 with D_t1 q1 decreasing along t1, drawn
// where q1 * FeatureSize passes the threshold, on the side facing the
// viewer.  q1 at the vertices from the thesis' curvature tensor; D_t1 q1 from
// the gradient of q1's linear interpolation, averaged over each vertex's
// triangles by area.
#pragma once

#include "Drawing/LineDrawing.h"

#include <vector>

namespace beltrami
{

/// Per vertex, for one view: q1 (NaN where the surface does not face the
/// viewer or has no curvature), t1 (3 per vertex, unit), D_t1 q1 (split
/// runs: the owners' values on the ghost points; collective).
struct ApparentCurvature
{
  std::vector<double> Q1, T1, Derivative;
};

ApparentCurvature ComputeApparentCurvature(const LineDrawingGeometry& geometry, const LineView& view, int numThreads);

/// The apparent ridges of the faces this process draws, past the threshold
/// (its hysteresis fraction: options.HysteresisRatio) at feature size `size`.
SegmentList ApparentRidgeSegments(const LineDrawingGeometry& geometry, const ApparentCurvature& curvature,
  const LineDrawingOptions& options, double size);

} // namespace beltrami
