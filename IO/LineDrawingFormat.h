// Beltrami IO: line drawings laid out on a page and written as vectors
// (SVG, PDF through Cairo), free of VTK.
//
// The polylines of a drawing (vtkSurfaceLineDrawing's output) are
// projected with the drawing's camera, cut where they pass behind the eye,
// scaled so that the drawing's longer side fills the page less its
// margins, joined where two ends of one style meet, simplified to the
// page's resolution (Douglas & Peucker) and stroked per line type; with
// tapering, the curvature lines' widths follow their strength.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace beltrami
{

constexpr int NumberOfDrawingStyles = 9; ///< the 8 line types, then hidden lines
constexpr int HiddenStyle = 8;

struct LineStyle
{
  double Width = 1.0;                   ///< points (1/72 inch)
  double Color[3] = { 0.0, 0.0, 0.0 };  ///< RGB in [0, 1]
  double Dash = 0.0;                    ///< dash and gap length in points (0: solid)
};

struct LineDrawingPageOptions
{
  LineDrawingPageOptions();
  double PageSize = 504.0;  ///< the page's longer side, points (7 inches)
  double Margin = 18.0;     ///< points
  double Tolerance = 0.05;  ///< simplification and joining, points
  bool DrawHidden = false;  ///< draw lines marked hidden (dashed by default)
  bool TaperByStrength = false;
  LineStyle Styles[NumberOfDrawingStyles]; ///< by line type; HiddenStyle: hidden lines
};

/// The camera the lines were drawn for.
struct LineDrawingCamera
{
  bool Parallel = false;
  double Position[3] = { 0.0, 0.0, 1.0 };
  double Direction[3] = { 0.0, 0.0, -1.0 }; ///< the direction the camera looks along
  double Up[3] = { 0.0, 1.0, 0.0 };
};

/// A drawing's polylines: line l has the points Connectivity[Offsets[l] ..
/// Offsets[l + 1]) (a closed one repeats its first point at its end).
struct LineDrawingInput
{
  const double* Points = nullptr; ///< 3 per point
  std::vector<std::int64_t> Offsets{ 0 }, Connectivity;
  std::vector<std::uint8_t> Types;  ///< line type per line
  std::vector<std::uint8_t> Hidden; ///< per line (empty: none hidden)
  const double* PointStrength = nullptr; ///< per point (null: no tapering)
};

/// A stroked path on the page (points, y down).
struct PagePath
{
  int Style = 0;
  double Width = 1.0;
  bool Closed = false;
  std::vector<double> XY;
};

struct LineDrawingPage
{
  double Width = 0.0, Height = 0.0;
  std::vector<PagePath> Paths; ///< in drawing order
};

LineDrawingPage LayOutLineDrawing(const LineDrawingInput& lines, const LineDrawingCamera& camera,
  const LineDrawingPageOptions& options);

/// The page as an SVG document: a group per style and width (class: the
/// line type's name, "hidden" for hidden lines), a path per polyline.
std::string LineDrawingSvg(const LineDrawingPage& page, const LineDrawingPageOptions& options);

/// Writes the page as a PDF (Cairo); false with `error` set on failure.
bool WriteLineDrawingPdf(const LineDrawingPage& page, const LineDrawingPageOptions& options,
  const std::string& path, std::string& error);

/// The names of the styles ("contour", ..., "hidden").
const char* LineStyleName(int style);

} // namespace beltrami
