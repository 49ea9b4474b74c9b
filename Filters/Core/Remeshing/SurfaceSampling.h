// Beltrami core: exactly N sample points on a surface through its atlas
// (thesis sections 4.3.1-4.3.2).  The control map is the atlas texture
// (Maps/GeometryImages' PackedAtlas: all charts at one texel density): the
// area map (3D area per texel) times an importance per vertex, so a constant
// importance gives a uniform density on the surface.  The chart boundaries
// (seams and the surface's own boundary) are sampled first, once for both
// charts along a seam, by 1D error diffusion along the paths between the seam
// graph's corners with the square-root law (samples per unit length = the
// square root of samples per unit area); a band of half a sample spacing
// around them is left out of the image; the rest of the count goes to the
// halftone of the control map (Remeshing/ErrorDiffusion).
#pragma once

#include "Maps/Atlas.h"
#include "Maps/GeometryImages.h"
#include "Mesh/Laplacian.h"
#include "Mesh/SurfaceDistance.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace beltrami
{

/// What the remesher may keep between calls on the same surface and atlas
/// (interactive use): the surface's curvature (for MaximumSurfaceSag); for
/// the sampling, the packed atlas and, per control-map resolution, the
/// charts rasterized with their area map (the last four used, the last two
/// beyond 256 MiB; 12 bytes a texel: at 10k samples 1-4 MB each); for the
/// optimisation, the charts' locators.  A new sample count, importance or
/// transfer function then skips the curvature, the rasterization and the
/// locators' set-up.  The caller empties it when the surface or the atlas
/// changes.
/// The surface a kept value was computed for (its points and triangles).
struct SurfaceKey
{
  const double* Points = nullptr;
  const Index* Triangles = nullptr;
  Index Count = -1;
  /// True where the key is of another surface than (topology, points):
  /// the value is to be computed again, and the key is now this surface's.
  bool Renew(const MeshTopology& topology, const double* points);
};

struct RemeshCache
{
  struct Raster
  {
    ChartRaster Charts;
    LargeVector<double> AreaRatio; ///< AreaMap per texel
    std::uint64_t LastUse = 0;
  };
  std::uint64_t Clock = 0; ///< counts the rasters' uses
  std::unique_ptr<AtlasChart> Packed;
  std::map<int, Raster> Rasters;
  std::vector<double> MaximumCurvature; ///< max |kappa_i| per surface vertex (empty: not yet)
  GraphLaplacian SurfaceLaplacian;      ///< the surface's cotangent Laplacian, with MaximumCurvature
  /// One per chart of `atlas` (built on first use; again where the
  /// charts' triangles or maps are others: a filter that keeps its cache
  /// over a new count may remesh on another atlas with as many charts).
  const std::vector<ChartLocator>& Locators(const AtlasResult& atlas);
  /// The surface's triangles in a grid, for the distances to it of the
  /// remeshes' fidelity checks (built on first use; again where the
  /// points or triangles are others).
  const TriangleGrid& SurfaceGrid(const MeshTopology& topology, const double* points, int numThreads);
  /// The angle defect of every interior surface vertex (AngleDefect; 0 at
  /// the others), for the tips (computed on first use, on the threads;
  /// again where the points or triangles are others).
  const std::vector<double>& AngleDefects(const MeshTopology& topology, const double* points, int numThreads);
  /// The surface's figures the fidelity checks compare each remesh with
  /// (computed on first use; again where the points or triangles are others).
  struct SurfaceFigures
  {
    double Diagonal = 0.0;  ///< of the bounding box of the used points
    double Area = 0.0;
    Index Components = 0;
  };
  const SurfaceFigures& Figures(const MeshTopology& topology, const double* points, int numThreads);
  void Clear()
  {
    Packed.reset();
    Rasters.clear();
    MaximumCurvature.clear();
    SurfaceLaplacian = GraphLaplacian();
    ChartLocators.clear();
    LocatorsKey = 0;
    Grid.reset();
    Defects.clear();
    GridKey = DefectsKey = FiguresKey = SurfaceKey();
  }

private:
  std::vector<ChartLocator> ChartLocators;
  std::uint64_t LocatorsKey = 0; ///< AtlasKey of the atlas they were built for
  std::unique_ptr<TriangleGrid> Grid;
  std::vector<double> Defects;
  SurfaceFigures KeptFigures;
  SurfaceKey GridKey, DefectsKey, FiguresKey;
};

struct SamplingOptions
{
  std::int64_t NumberOfSamples = 10000;
  /// Texels per side of the control map; 0: automatic, about 8 texels of
  /// chart per sample (a mean density of 1/8, where error diffusion's
  /// blue noise is at its best).
  int Resolution = 0;
  /// One flag per edge of topology.Edges(): feature edges (null: none).
  /// Where a chart boundary passes from a feature edge (or the surface's
  /// boundary) to another edge, as where a crease fades out along a seam,
  /// the vertex is a corner (section 4.2.3's crease ends): it gets a sample,
  /// so the remesh follows the crease to its end.
  const std::uint8_t* FeatureEdges = nullptr;
  /// The most the chord between two samples of a feature line or of the
  /// surface's boundary may depart from the line where it bends, as a
  /// fraction of the spacing of the density there (0: no bound): where the
  /// density's spacing would depart more, the line gets more samples (the
  /// rest of the surface correspondingly fewer), so the remesh does not
  /// cut its bends.  At 0.025 the jagged creases of fandisk_large and rims
  /// of elephant-with-holes took so many samples that the triangles beside
  /// them were slivers (at 10k 0.66% and 0.78% of them below 30 degrees; at
  /// 0.05 0.06% and 0.32%), for Hausdorff distances over the corpus within
  /// 1% of the stricter bound's (geometric mean over CGAL's 0.838 -> 0.843;
  /// fandisk's small round crease at 10k 0.078% -> 0.105% of the diagonal
  /// from the remesh).  0.1 gave the same triangles and left that crease as
  /// the density's spacing cuts it at 5k too.
  double MaximumLineSag = 0.05;
  /// The anisotropic remesh's metric (6 per surface vertex; null: none):
  /// the chart boundaries are sampled at its lengths along them (a seam
  /// along the direction of short edges takes more samples than the
  /// density's mean spacing gives).
  const double* Metric = nullptr;
  /// Input vertices inside a chart whose angle defect (2 pi minus the sum
  /// of their corners' angles) exceeds this many radians - the tips of
  /// spikes, horns and fingers, cones narrower than about 57 degrees at 1 -
  /// each take the nearest interior sample of their chart (on a chart
  /// boundary: the nearest sample of its path), which stays there
  /// (SampleKind::Tip): a tip thinner than the spacing is neither cut off
  /// by the halftone nor pulled down by the relaxation (0: none).  Of tips
  /// closer than the spacing, the sharpest (two pinned samples that close
  /// would leave slivers beside their short edge).  1 rather than 2: the
  /// blunter cones of terrains' peaks and of animals' extremities kept too
  /// (over the corpus, the generated shapes and shapes from marching cubes,
  /// the two-sided deviation over CGAL's 4% lower in geometric mean).
  double TipAngleDefect = 1.0;
  /// Input vertices pinned as tips too, whatever their angle defect (one
  /// flag per surface vertex; null: none), or, on a feature line or the
  /// surface's boundary, as corners: where a remesh left the input
  /// farthest, the error-driven mode puts a vertex (RemeshToDeviation).
  const std::uint8_t* PinnedVertices = nullptr;
  /// Where the boundaries at the density take more samples than the count
  /// (the seams of a surface of many handles: a lattice of bars at a low
  /// count), its seams (no kept line) are sampled twice, then three times
  /// as sparsely (SurfaceSamples::SeamSpacing), until every chart has room
  /// for a sample inside (or as sparsely as that).
  bool SparserSeams = false;
  int NumberOfThreads = 0;
  RemeshCache* Cache = nullptr; ///< optional: kept between calls by the caller
};

enum class SampleKind : std::uint8_t
{
  Interior = 0, ///< from the halftone, inside one chart
  Boundary = 1, ///< on a chart boundary path (a seam or the surface's boundary)
  Corner = 2,   ///< where chart boundaries meet (or a boundary loop starts)
  Tip = 3       ///< pinned at a cone point of the input (SamplingOptions::TipAngleDefect): inside one chart, or on a path (Chart -1)
};

/// A chart boundary path (a seam, a stretch of the surface's boundary or of
/// a feature) and the samples on it.
struct SamplePath
{
  std::vector<Index> Vertices;     ///< surface vertices, corner to corner (first == last on a loop)
  std::vector<double> Arc;         ///< 3D arc length at each vertex (Arc[0] = 0)
  std::vector<Index> Samples;      ///< sample ids in order, the corner samples at both ends
  std::vector<double> SampleArc;   ///< arc length of each sample
  /// Per vertex: how many times more samples per length a kept line takes
  /// there than the density asks, where it turns (SamplingOptions::
  /// MaximumLineTurn; empty: 1 everywhere).
  std::vector<double> Refinement;
  int Charts[2] = { -1, -1 };      ///< the charts on its two sides (-1: none, on the surface's boundary)
};

struct SurfaceSamples
{
  std::string Error;               ///< non-empty: no samples
  std::vector<Index> Triangle;     ///< surface triangle per sample
  std::vector<double> Barycentric; ///< 3 per sample: weights of the triangle's corners
  std::vector<double> Positions;   ///< 3 per sample
  std::vector<SampleKind> Kind;
  std::vector<int> Chart;          ///< the chart of interior samples; -1 on boundaries
  int Resolution = 0;              ///< of the control map
  double Density = 0.0;            ///< samples per unit area where the importance is 1
  std::int64_t BoundarySamples = 0;///< samples on chart boundaries (corners included)
  /// The boundary samples and one inside each chart: with at least this
  /// many samples (at this density) every chart gets one inside.
  std::int64_t NeededSamples = 0;
  /// Of BoundarySamples, those on the surface's own boundary loops (the rims
  /// of its holes), which no other layout of the same surface makes fewer.
  std::int64_t RimSamples = 0;
  /// The seams' spacing over the density's (SamplingOptions::SparserSeams).
  double SeamSpacing = 1.0;
  /// Charts left without a sample inside (fewer interior samples than
  /// charts): each triangulates its boundary samples alone, and where a
  /// neighbour does too both can make the same triangles.
  std::int64_t ChartsWithoutSample = 0;
  std::vector<SamplePath> Paths;   ///< the chart boundaries with their samples
  LargeVector<double> ControlMap;  ///< expected samples per texel (Resolution^2, NaN outside the charts)
  std::vector<std::uint8_t> Halftone; ///< 1 per texel holding an interior sample
};

/// Whether edge e lies on the surface's boundary.
bool IsOpenEdge(const MeshTopology::EdgeTable& edges, std::int64_t e);

/// Whether edge e is kept as a line by the remesher (its samples stay on
/// it): the surface's boundary or a feature (`featureEdges`: one flag per
/// edge of topology.Edges(), may be null).
bool IsKeptEdge(const MeshTopology::EdgeTable& edges, std::int64_t e, const std::uint8_t* featureEdges);

/// The spacing of `density` samples per unit area where the importance is
/// 1, where it is `importance` (none at importance 0: a spacing beyond any).
inline double SpacingOf(double density, double importance)
{
  return 1.0 / std::sqrt(density * std::max(1e-300, importance));
}

/// SpacingOf at surface vertex v (importance: per vertex, or null: uniform).
double SpacingAt(const double* importance, double density, Index v);

/// The edge (its first vertex's index) of a polyline with cumulative arc
/// lengths `arcs` at arc length `arc`, and the fraction of the way along it.
std::pair<std::size_t, double> EdgeAtArc(const std::vector<double>& arcs, double arc);

/// The interior sample of `samples` (ids into `out`) nearest to x;
/// out.Kind.size() where none of them is one.
std::size_t NearestInterior(const std::vector<std::size_t>& samples, const Vec3& x, const SurfaceSamples& out);

/// Sample s moves to x (in `triangle` at barycentric weights w) as `kind`.
void MoveSample(std::size_t s, const Vec3& x, Index triangle, const double w[3], SampleKind kind, SurfaceSamples& out);

/// A sample in `triangle` at barycentric weights w (of its corners),
/// appended to `out`.
void AddSample(const MeshTopology& topology, const double* points, Index triangle, const double* w, SampleKind kind,
  int chart, SurfaceSamples& out);

/// The point at arc length `arc` along `path`: a surface triangle with the
/// path's edge there and the barycentric weights of its corners.
Index LocateOnPath(const MeshTopology& topology, const SamplePath& path, double arc, double barycentric[3]);

/// The arc length between lo and hi that halves the integral of the path's
/// Refinement over [lo, hi]: where a sample between neighbours at lo and hi
/// goes to keep the line's refined spacing (none where it is 1 throughout).
std::optional<double> RefinedMiddle(const SamplePath& path, double lo, double hi);

/// `importance`: one value >= 0 per surface vertex (null: uniform).
SurfaceSamples SampleSurface(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const SamplingOptions& options = {});

} // namespace beltrami
