// Beltrami core: the geometry of an atlas chart as images (thesis sections
// 4.2.3 and 5.4: the surface replaced by a catalogue of 2D maps).  A chart's
// own square [0, 1]^2 (AtlasChart::UV) is sampled at the centres of an n x n
// pixel grid: every pixel inside the chart gets its triangle and its exact
// barycentric coordinates there, from which any per-vertex quantity is
// interpolated (the embedding map M_x, curvature maps M_H and M_K, point
// data) and the per-triangle area ratio gives the area map M_A (3D area per
// unit of map area).
#pragma once

#include "Maps/Atlas.h"
#include "Support/LargeBuffer.h"

#include <cstdint>
#include <vector>

namespace beltrami
{

/// Twice the signed area of the triangle (a, b, c) in the plane.
inline double Cross2(const double* a, const double* b, const double* c)
{
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/// Where the pixels of a chart's square fall: pixel (i, j) (row j, x
/// fastest) has its centre at ((i + 0.5) / n, (j + 0.5) / n).
struct ChartRaster
{
  int Resolution = 0;
  LargeVector<Index> Face;          ///< chart triangle index per pixel, -1 outside the chart
};

/// The weights of pixel p's centre in its triangle (raster.Face[p] >= 0), as
/// RasterizeChart found them (the same arithmetic: the same bits).  Not
/// stored per pixel: 24 bytes a pixel of fresh memory cost the remesher's
/// previews more than computing them again where they are read.
void PixelBarycentric(const AtlasChart& chart, const ChartRaster& raster, std::size_t p, double* w);

/// The whole atlas as one chart of [0, 1]^2: every chart's triangles (chart
/// after chart, so Triangles is not ascending) at their packed positions
/// (AtlasUV), Vertices the surface vertex of every chart vertex (a seam
/// vertex once per chart, as in the cut surface), Area3D the surface's area.
/// The functions below then sample the atlas texture itself: one map set for
/// the whole surface, at the texels of the packed UV.
AtlasChart PackedAtlas(const AtlasResult& atlas);

/// Finds the chart triangle that contains `uv` (a point of the chart's
/// square) and its barycentric coordinates; -1 when outside.  Points on an
/// edge shared by two triangles go to the first of them.
Index LocateInChart(const AtlasChart& chart, const double uv[2], double barycentric[3]);

/// LocateInChart for many points: the chart's triangles bucketed on a grid
/// of about one triangle per cell.  The chart must outlive the locator.
class ChartLocator
{
public:
  explicit ChartLocator(const AtlasChart& chart);
  /// As LocateInChart (the first triangle in the cell's list on shared edges).
  Index Locate(const double uv[2], double barycentric[3]) const;
  /// The triangle of the cell's 3 x 3 neighbourhood that uv is least far
  /// outside of (in barycentric terms), with its weights clamped to the
  /// triangle: for points pushed just off the chart by round-off.  -1 when
  /// no triangle is near.
  Index LocateNearest(const double uv[2], double barycentric[3]) const;

private:
  int CellOf(double u, int axis) const;
  const AtlasChart* Chart = nullptr;
  int Cells = 1;
  double Lower[2] = { 0.0, 0.0 }, Width[2] = { 1.0, 1.0 };
  std::vector<std::int64_t> Offsets; ///< CSR of the cells (x fastest)
  std::vector<Index> Items;          ///< chart triangles per cell
};

/// Samples the chart at every pixel centre of an n x n grid (threads: 0 all).
ChartRaster RasterizeChart(const AtlasChart& chart, int resolution, int numThreads = 0);
/// The same into `raster`, reusing its memory (one raster for many charts:
/// no new pages to clear for each).
void RasterizeChart(const AtlasChart& chart, int resolution, ChartRaster& raster, int numThreads = 0);

/// values (components per vertex: of the surface's vertices, or of the
/// chart's when `chartValues`) interpolated at every pixel into `out`:
/// `components` doubles per pixel, NaN outside.
void InterpolateOnRaster(const ChartRaster& raster, const AtlasChart& chart, const double* values, int components,
  double* out, bool chartValues = false, int numThreads = 0);

/// The area map into `out`: per pixel the 3D area of its triangle over the
/// triangle's area in the chart's square (NaN outside).  Summed over the
/// pixels and multiplied by the pixel area 1/n^2 it gives the chart's 3D area
/// (threads: 0 all).
void AreaMap(const ChartRaster& raster, const AtlasChart& chart, const double* points, double* out, int numThreads = 0);

} // namespace beltrami
