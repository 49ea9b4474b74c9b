// Beltrami core, private to Remeshing/RemeshOptimization: the optimiser of
// a remesh (section 4.4), its edge swaps (RemeshSwaps.cxx), its vertex
// moves and stitching (RemeshOptimization.cxx), its corners on the
// surface's boundary (RemeshRims.cxx) and its measures in an anisotropic
// remesh's metric (RemeshOptimizerMetric.cxx).
#pragma once

#include "Remeshing/RemeshOptimization.h"

#include "Maps/GeometryImages.h"

#include <array>
#include <cstdint>
#include <initializer_list>
#include <unordered_set>
#include <utility>
#include <vector>

namespace beltrami::detail
{

using Mat3 = Eigen::Matrix3d;

/// A corner that a seam's end made on the surface's boundary, one of whose
/// triangles has an angle below this many degrees, slides along the
/// boundary to the place between its neighbours there where its triangles
/// are roundest (Optimizer::RoundRimCorners).  Two seams reaching a rim at
/// nearly one point left two corners a fiftieth of a spacing apart, fixed,
/// with triangles of 1-2 degrees beside them (isosurfaces' rims).
constexpr double RimCornerDegrees = 20.0;

/// Area / perimeter^2 of a 3D triangle, over its value for the equilateral
/// triangle (1: equilateral, 0: degenerate).
double Roundness(const Vec3& a, const Vec3& b, const Vec3& c);

/// The cosine of the smallest angle of a 3D triangle.
double LargestCosine(const Vec3& a, const Vec3& b, const Vec3& c);

/// A face (a, b, c) of the remesh is folded where its vertices' input
/// normals (na, nb, nc) agree (each two within 60 degrees: not across a part
/// thinner than the spacing, nor across a sharp edge, where a vertex on the
/// edge has either side's normal) and it faces against their sum, or has
/// no area.
bool Folded(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& na, const Vec3& nb, const Vec3& nc);

/// How a vertex may move while stitching.
enum Mobility : std::uint8_t
{
  Free = 0,   ///< anywhere on the surface
  OnPath = 1, ///< along its path (the surface's boundary or a feature)
  Fixed = 2   ///< a corner on the surface's boundary or a feature
};

class Optimizer
{
public:
  Optimizer(Remesh& remesh, const MeshTopology& topology, const double* points, const AtlasResult& atlas,
    const SurfaceSamples& samples, const double* importance, const double* metric, RemeshCache* cache)
    : R(remesh), M(remesh.Mesh), Topology(topology), Points(points), Atlas(atlas), Samples(samples),
      ImportanceValues(importance), MetricValues(metric), Locators((cache ? *cache : LocalCache).Locators(atlas))
  {
    Valence.resize(M.NumberOfVertices());
    for (Index v = 0; v < M.NumberOfVertices(); ++v)
    {
      Valence[v] = M.Valence(v);
    }
    for (Index v = 0; ImportanceValues && v < M.NumberOfVertices(); ++v)
    {
      VertexImportance.push_back(ImportanceAt(v));
    }
    for (Index v = 0; v < M.NumberOfVertices(); ++v)
    {
      InputNormals.push_back(InputNormalOf(R.Triangle[v]));
    }
    for (Index v = 0; MetricValues && v < M.NumberOfVertices(); ++v)
    {
      VertexMetric.push_back(MetricAt(v));
    }
    PathIndex.assign(M.NumberOfVertices(), -1);
    for (const SamplePath& path : samples.Paths)
    {
      for (std::size_t i = 1; i + 1 < path.Samples.size(); ++i)
      {
        PathIndex[path.Samples[i]] = static_cast<Index>(i);
      }
    }
  }

  std::int64_t SwapForValence();
  std::int64_t SwapForShape();
  std::int64_t SwapSlivers();
  std::int64_t SwapFolds();
  std::int64_t MendSlivers(double degrees);
  template <typename Wanted, typename Accept>
  std::int64_t SwapWhere(Wanted&& wanted, Accept&& accept);
  std::vector<Index> ActiveHalfEdges() const;
  double Relax();
  Index BeginStitching(const std::uint8_t* featureEdges);
  /// After the stitching rounds: each corner on the surface's boundary that
  /// may slide along it (SlidingRimCorner), beside a triangle with an angle
  /// below RimCornerDegrees, moves along it between its neighbours there,
  /// where its triangles' smallest angle is largest (if larger than where
  /// it is), its chords to them departing from the boundary by at most
  /// maxSag times their mean length or by what they do now (a corner of the
  /// rim is not cut).  Where any moved, every vertex on the boundary is
  /// then fixed for the rounds after.  Returns the corners moved.
  std::int64_t RoundRimCorners(const std::uint8_t* featureEdges, const std::uint8_t* pinned, double maxSag);
  /// One round: shape and valence swaps (while stitching, unfolding swaps
  /// first), then the relaxation (LatticeWeight as set); adds to `stats`.
  void OptimizationRound(RemeshOptimizationStatistics& stats);
  /// While stitching: free vertex v moves exactly onto `target` (an input
  /// vertex: at a corner of one of its triangles) and stays there, as a
  /// Tip, where no face around it folds or turns by 90 degrees
  /// (Place); false where it cannot.
  bool PinAt(Index v, const PinTarget& target);
  /// The free vertex nearest to `target` among those of its face and their
  /// neighbours that PinAt can move onto it, moved so (-1 if none can).
  Index PinNear(const PinTarget& target);
  /// Joins each of the `pinned` vertices to the fixed vertices across the
  /// edges opposite it that lie on one input crease edge with it
  /// (OnOneInputEdge): such an edge of the remesh lies on the input, along
  /// the crease the remesh cut; swapped in where that keeps the surface and
  /// half the triangles' roundness, and kept (KeptEdges, as the edges it
  /// has already to such vertices).  The joins made.
  Index JoinAlongInputEdges(const std::vector<Index>& pinned);
  /// Per vertex: the relaxation moves it and the swaps take its edges
  /// (empty: all).
  std::vector<std::uint8_t> Active;
  int NumberOfThreads = 0;
  double OverRelaxation = 1.0; ///< the first try of a move off a path, of the way to its target
  /// With a metric: the share of the lattice's pull in the moves while
  /// stitching (LatticeShift; the rest Lloyd's in the metric).
  double LatticeWeight = 0.0;

private:
  const double* UVAt(Index h) const { return &R.CornerUV[2 * h]; }
  bool SameChart(Index h) const
  {
    return !M.IsBoundary(h) && R.FaceChart[h / 3] == R.FaceChart[M.Twin(h) / 3];
  }
  /// h's edge may be swapped: inside a chart, or, while stitching, anywhere
  /// but along a path that stays (a feature).
  bool Swappable(Index h) const
  {
    if (!Stitching)
    {
      return SameChart(h);
    }
    const Index a = M.Tail(h), b = M.Head(h);
    return !M.IsBoundary(h) &&
      (Moves[a] == Free || Moves[b] == Free || !KeptEdges.count(EdgeKey(a, b)) || VertexOnEdge(h) >= 0);
  }
  /// The vertex c of a face of h's edge a-b that lies on it (the face's
  /// angle at c above 179 degrees: a triangle of no area), or -1.  The
  /// swap of a-b then leaves the surface as it is (the other face is split
  /// at c) and removes that triangle; along a kept path, the path runs
  /// a-c-b (Flip hands the edge's keeping to a-c and c-b, and c, if free,
  /// stays where it is: relaxed off the line, it left the faces on either
  /// side of a crease joined across it).
  Index VertexOnEdge(Index h) const;

  static std::uint64_t EdgeKey(Index a, Index b)
  {
    return static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint32_t>(std::max(a, b));
  }
  /// Fixed vertices a and b lie on one input edge (at its ends or on it)
  /// whose triangles' normals differ by JoinCreaseDegrees or more: the
  /// straight segment between them lies on the input, along its crease.
  bool OnOneInputEdge(Index a, Index b) const;
  /// v's edges to the fixed vertices on one input crease edge with it
  /// (OnOneInputEdge) kept by the swaps (KeptEdges).
  void KeepEdgesAlongCreases(Index v);
  bool FlipKeepsCharts(Index h) const;
  bool FlipKeepsSurface(Index h) const;
  bool CanSwap(Index h) const
  {
    return M.CanFlip(h) && (Stitching || FlipKeepsCharts(h)) && (FlipKeepsSurface(h) || VertexOnEdge(h) >= 0);
  }
  void Flip(Index h);
  std::pair<double, double> Roundnesses(Index h) const;
  /// The quad of h's edge (a, b, c, d: faces (a, b, c), (b, a, d)); with a
  /// metric, relative to a and in it (MetricFactor of the four).
  std::array<Vec3, 4> Quad(Index h) const;
  /// The tangent metric at v's place (RemeshMetric's TangentMetric).
  Mat3 MetricAt(Index v) const;
  /// U with U^T U the mean metric of `vertices` (its Cholesky factor): U d
  /// is d as the metric measures it.  Only with a metric.
  Mat3 MetricFactor(std::initializer_list<Index> vertices) const;
  /// The cosine of the smallest angle of face f (in the metric, if any).
  double FaceLargestCosine(Index f) const;
  /// The valence that gives v's triangles angles near 60 degrees: 6
  /// inside; on the surface's boundary one more than its angle (the sum of
  /// its corners) in sixties, 4 on a straight stretch (UpdateBoundaryTargets).
  int Target(Index v) const { return M.IsBoundaryVertex(v) ? BoundaryTarget[v] : 6; }
  void UpdateBoundaryTargets();
  std::vector<int> BoundaryTarget;
  double Importance(Index f) const;
  double ImportanceAt(Index v) const;
  double Weight(Index f) const;
  bool MoveInterior(Index v, double& moved);
  Eigen::Matrix2d PlaneMetricFactor(Index v) const;
  Vec3 LatticeShift(Index v, const Mat3& u, double& weight) const;
  bool MoveOnPath(Index v, double& moved);
  bool SlidingRimCorner(Index v, const std::uint8_t* featureEdges, const std::uint8_t* pinned) const;
  bool MoveOnSurface(Index v, double& moved);
  double LargestCosineAround(Index v, const Vec3& x) const;
  Vec3 ShiftToNeighbours(Index v) const;
  bool MoveToRounder(Index v);
  Index NearestOnSurface(const Vec3& p, Index start, double radius, double* w);
  bool KeepsPlane(Index v, Index triangle, const double* w);
  Vec3 FanNormal(Index v) const;
  bool KeepsSurface(
    Index v, const Vec3& x, const Vec3& normal, const Vec3& inputNormal, double cosine, int foldsBefore) const;
  Vec3 InputNormalOf(Index triangle) const;
  int FoldsAround(Index v, const Vec3& x, const Vec3& inputNormal) const;
  int FoldsOfFlip(Index h, bool flipped) const;
  /// (foldsBefore: FoldsAround v where it is, if the caller has it; -1: not.)
  bool Place(Index v, Index triangle, const double* w, double& moved, const Vec3* normal = nullptr, double cosine = 0.5,
    int foldsBefore = -1);
  void Move(Index v, double& moved);
  void ColourVertices();
  void Prefetch(Index v) const;

  Remesh& R;
  HalfEdgeMesh& M;
  const MeshTopology& Topology;
  const double* Points;
  const AtlasResult& Atlas;
  const SurfaceSamples& Samples;
  const double* ImportanceValues;
  const double* MetricValues; ///< 6 per input vertex (anisotropic mode), or null
  RemeshCache LocalCache; ///< where the caller keeps none
  const std::vector<ChartLocator>& Locators;
  std::vector<Index> Valence;
  std::vector<Index> PathIndex; ///< per vertex: its index in its path's Samples
  std::vector<double> VertexImportance; ///< per vertex: ImportanceAt (empty without an importance)
  std::vector<Vec3> InputNormals; ///< per vertex: the unit normal of the input triangle it lies in
  std::vector<Mat3> VertexMetric; ///< per vertex: MetricAt (empty without a metric)
  bool Stitching = false;
  std::vector<std::uint8_t> Moves;     ///< per vertex while stitching: its Mobility
  std::unordered_set<std::uint64_t> KeptEdges; ///< EdgeKey of the remesh's edges along kept paths
  std::vector<std::int64_t> ColourOffsets; ///< CSR of the colours over ColourVerticesList
  std::vector<Index> ColourVerticesList;
  std::vector<int> Colour; ///< per vertex: ColourVertices' colour (empty: none yet)
  std::vector<Index> Recolour; ///< the vertices whose neighbours a swap changed since
  std::vector<std::uint8_t> Pending; ///< ColourVertices' marks (all 0 between calls)
};

} // namespace beltrami::detail
