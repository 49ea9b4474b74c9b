// Beltrami core: an atlas of a triangle surface of any genus, open or closed,
// with any number of components (thesis section 4.2): disk-like charts
// (Maps/ChartPartition), each mapped by the discrete conformal
// parameterization onto its own square (section 4.2.2: DCP with the chart's
// boundary on the square, spaced by arc length; the circle where the square
// would flip a triangle), charts whose map still flips split until none does, and all charts packed into [0, 1]^2 at one
// scale (texels per unit of surface length alike on every chart) with a
// margin between them.  Seams given as labels and sharp edges can be kept
// as chart boundaries.
#pragma once

#include "Maps/BoundaryPlacement.h"
#include "Mesh/MeshTopology.h"
#include "Support/Parallel.h"

#include <cstdint>
#include <string>
#include <vector>

namespace beltrami
{

/// The automatic chart count's triangles per chart.
constexpr int TrianglesPerChart = 2000;

struct AtlasOptions
{
  /// Charts to start from (splits add more); 0: automatic, about one per
  /// 2,000 triangles and at least one per component (closed components get
  /// two when they are split into disks).
  int NumberOfCharts = 0;
  /// The largest chart area (in the surface's units squared): larger charts
  /// are split until none is (a single triangle larger than that stays, with
  /// a warning).  0: no limit.
  double MaximumChartArea = 0.0;
  /// The area-balanced refinement of section 4.2.4 (BalanceChartAreas): far
  /// more even chart areas (the elephant's largest over smallest chart 164
  /// -> 7.6, bunny00's 4.1 -> 2.2), but longer charts (bunny00: mean angle
  /// distortion 13.6 -> 18.1 deg, packing 88.5% -> 77.0%); off by default.
  bool BalanceAreas = false;
  /// The boundary of every chart's map: the square of section 4.2.2, the
  /// circle, or free (Natural: the natural conformal map of section 5.4.2;
  /// a chart whose free boundary would overlap itself goes onto the circle).
  ParameterizationBoundary ChartBoundary = ParameterizationBoundary::Square;
  /// Sharp edges (dihedral angle above FeatureAngle degrees, section 4.2.3)
  /// as chart boundaries: charts never cross them (a feature that ends
  /// inside a chart splits it).  Off by default: coarse organic meshes have
  /// scattered sharp edges (the elephant 167 above 60 deg) that would cut
  /// their charts small.
  bool SplitAtFeatures = false;
  double FeatureAngle = 60.0;
  /// Sharp edges in dangling chains shorter than this (surface units) are
  /// not features (DropShortFeatureChains): a crease that the mesh's edges
  /// cross at a slant shows as fragments a few edges long, each of which
  /// would split a chart.  0: every sharp edge is one.
  double MinimumFeatureLength = 0.0;
  /// Feature lines continued where their crease fades out, along edges
  /// sharper than half the FeatureAngle that turn them by at most this many
  /// degrees (ExtendFeatureEnds; 0: not continued).
  double MostFeatureTurn = 0.0;
  /// Fragments of a crease joined (BridgeFeatureGaps: paths up to this long
  /// along edges sharper than half the FeatureAngle) before short chains
  /// are dropped.  0: none.
  double LongestFeatureGap = 0.0;
  /// User seams: one label per surface triangle (kept triangles, in the
  /// topology's order); edges between different labels are chart
  /// boundaries.  Empty: none.
  std::vector<int> SeamLabels;
  /// The margin between packed charts, in texels of a TextureSize^2 texture.
  int TextureSize = 1024;
  double MarginTexels = 2.0;
  /// Split a chart when more than this share of its 3D area is squeezed
  /// by its map to an eighth of the chart's mean area scale or less (0: never).  A
  /// conformal map shrinks protrusions (limbs, horns, a cactus's arms)
  /// exponentially; an image of the charts at one texel density then holds
  /// too few texels there for their samples (the remesher's control map),
  /// and those parts are lost.
  double MaximumSqueezedShare = 0.0;
  /// Split a chart when more than this share of its 3D area is stretched by
  /// its map three times more one way than the other (0: never).  Where a
  /// surface's triangles are long slivers (a decimated scan), a chart's
  /// free-boundary map can overlap itself, and the circle it then goes onto
  /// stretches a long chart like that; the remesher's samples, spread
  /// evenly on the map, would then lie in rows on the surface.
  double MaximumStretchedShare = 0.0;
  /// Split a chart whose map's bounding box is more than this many times
  /// longer than wide (0: never).  A strip narrower than the charts are
  /// long (a ribbon, a flat band) maps to one long thin box; packed into
  /// the atlas's square it leaves it nearly empty, and an image of the
  /// charts at the texel density the remesher needs then takes gigabytes.
  /// (Charts of fewer than 64 triangles are kept: a needle's few slivers
  /// can be that long on their own.)
  double MaximumChartAspect = 0.0;
  /// Each chart's mean angle and area distortion (AtlasChart); the remesher
  /// does without (a tenth of the charts' mapping time).
  bool MeasureDistortion = true;
  int NumberOfThreads = 0;
};

struct AtlasChart
{
  std::vector<Index> Triangles; ///< ids in the surface, ascending
  std::vector<Index> Vertices;  ///< chart vertex -> surface vertex, ascending
  IndexArray Corners;           ///< 3 per chart triangle (same order as Triangles), chart vertex ids
  std::vector<double> UV;       ///< 2 per chart vertex: the chart's map, in [0, 1]^2 (its own square)
  /// The boundary of the map: the requested one, or the circle where the
  /// square would have flipped a triangle.
  ParameterizationBoundary Boundary = ParameterizationBoundary::Square;
  double Area3D = 0.0;          ///< area of the chart on the surface
  double MeanAngleDistortion = 0.0, MeanAreaDistortion = 0.0; ///< of UV (Maps/Distortion; 0 unless measured)
  double Offset[2] = { 0.0, 0.0 }; ///< packed: atlas UV = Offset + Scale * UV
  double Scale = 1.0;
};

struct AtlasResult
{
  bool Completed = true; ///< false if the progress callback cancelled (then no charts)
  std::string Error;   ///< non-empty: no atlas
  std::string Warning; ///< non-fatal remarks
  std::vector<int> ChartOfTriangle; ///< per surface triangle
  std::vector<AtlasChart> Charts;
  int SplitsForFlips = 0;           ///< charts split because their map flipped a triangle (or squeezed or stretched too much of it: MaximumSqueezedShare, MaximumStretchedShare)
  std::int64_t CutEdges = 0;        ///< seam and feature edges kept as chart boundaries
  /// 1 per edge of the topology: the sharp edges kept as chart boundaries
  /// (SplitAtFeatures; empty without).
  std::vector<std::uint8_t> FeatureEdges;
  double PackingEfficiency = 0.0;   ///< area of the packed charts' maps / area of [0, 1]^2
};

/// The atlas of the surface (its kept triangles; 3 doubles per point).
/// `progress` is called between batches of charts while they are mapped (the
/// longest stage) and may cancel.
AtlasResult BuildAtlas(const MeshTopology& topology, const double* points, const AtlasOptions& options = {},
  const ProgressCallback& progress = {});

/// The packed position in [0, 1]^2 of chart vertex v of `chart`.
inline void AtlasUV(const AtlasChart& chart, Index v, double* uv)
{
  uv[0] = chart.Offset[0] + chart.Scale * chart.UV[2 * v];
  uv[1] = chart.Offset[1] + chart.Scale * chart.UV[2 * v + 1];
}

} // namespace beltrami
