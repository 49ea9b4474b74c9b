// Beltrami core: the remesher of thesis chapter 4 from an atlas to a new
// mesh: exactly N samples on the surface (Remeshing/SurfaceSampling),
// triangulated chart by chart in the parameter planes and joined
// (Remeshing/Remesh), then optimised with the vertices kept
// (Remeshing/RemeshOptimization).  The atlas is an input so that callers
// that change only sampling parameters (count, importance) reuse it.
#pragma once

#include "Mesh/MeshMeasures.h"
#include "Remeshing/RemeshOptimization.h"

#include <cstdint>
#include <string>
#include <vector>

namespace beltrami
{

struct RemeshOptions
{
  std::int64_t NumberOfVertices = 10000;
  int Resolution = 0; ///< of the control map; 0: automatic (SamplingOptions)
  int Iterations = 5;           ///< chart rounds of swaps and relaxation
  int StitchingIterations = 20; ///< stitching rounds after them (RemeshOptimization)
  double OverRelaxation = 1.8;  ///< of the relaxation's moves (RemeshOptimization)
  /// > 0: edges whose triangles' normals differ by more than this many
  /// degrees are features, kept while stitching (the atlas's FeatureAngle
  /// when it splits at features: then its FeatureEdges, the lines it kept);
  /// 0: none.
  double FeatureAngle = 0.0;
  /// Feature lines and the surface's boundary sampled more densely where
  /// they bend (SamplingOptions::MaximumLineSag).
  double MaximumLineSag = 0.05;
  /// SamplingOptions::SparserSeams.
  bool SparserSeams = false;
  /// The same bound for the surface (0: none): where a triangle of the
  /// density's spacing s would depart from the surface by more than this
  /// fraction of s (about s^2 kappa / 8, kappa the larger principal
  /// curvature), the importance is raised so that it departs by this much
  /// (RaiseImportanceForSag).  A uniform remesh stays uniform wherever the
  /// spacing follows the surface.
  double MaximumSurfaceSag = 0.1;
  /// Input vertices that get a remesh vertex each, exactly there (one flag
  /// per surface vertex; null: none; SamplingOptions::PinnedVertices).
  const std::uint8_t* PinnedVertices = nullptr;
  /// Where the remesh leaves input vertices farther than this many
  /// spacings from it (each the farthest of its 1-ring: a tip, a hoof or a
  /// corner the samples missed), the vertex of the remesh nearest to each
  /// that can move there without a fold is moved onto it and kept there,
  /// the rings around it settled by stitching rounds, up to FarPinRounds
  /// times (each round measures again).  Where a point along an input
  /// edge is that far (a crease of an input coarser than the remesh, which
  /// its triangles cut), the round is made twice, once also moving vertices
  /// so onto points a spacing apart along the edge, once with the far
  /// vertices alone, and the closer kept.  A round is kept where the remesh
  /// comes closer to the input by 2% (in the larger of its deviations, or
  /// no farther in that and by 2% in both together) and its triangles stay within the bar
  /// or as good as the first's (FarPinGain, AsGoodTriangles; measured in
  /// the metric in the anisotropic mode).  Where far vertices are left that
  /// no vertex could reach, or whose moves brought it no closer, the remesh
  /// is made again with them pinned, up to FarPinRounds times, on the same
  /// terms (RemeshSurface; only beyond FarRemeshSpacings).  The density
  /// keeps a smooth surface's sag within MaximumSurfaceSag (a tenth) of the
  /// spacing: a vertex farther is a corner of the input the samples missed.  0: one remesh as made.
  /// Not with FinalSurface, nor with PinnedVertices unless
  /// RoundsWithPinnedVertices.
  double FarPinSpacings = 0.15;
  /// The most fidelity rounds, and remeshes after the first
  /// (FarPinSpacings; 0: one remesh as made).
  int FarPinRounds = 3;
  /// The fidelity rounds also on a remesh with PinnedVertices (the
  /// error-driven mode's remeshes, whose pins are its own; the remeshes
  /// made again with the far vertices pinned take none).
  bool RoundsWithPinnedVertices = false;
  /// The anisotropic mode: a metric per input vertex (6 numbers, as
  /// Remeshing/RemeshMetric's; null: isotropic).  Its density (the square
  /// root of its tangent determinant) times the importance is the density,
  /// the optimisation measures edges and angles in it (RemeshOptimization),
  /// and MaximumSurfaceSag bounds the sag of its shortest edges
  /// (ShortestEdgeCurvatures).
  const double* Metric = nullptr;
  /// With a metric: its components smoothed over this many spacings of the
  /// count (GradeMetric; 0: as given), so that its lengths grade from one
  /// region to the next at the remesh's own scale.
  double MetricGradation = 1.0;
  /// Without a metric: the most a non-constant importance's spacing may
  /// grow per unit of distance (GradedImportance; 0: as given), so that the
  /// triangles grow gradually away from its peaks: a curvature's importance
  /// jumps at creases and rims.  Mean curvature on fandisk at 2,000
  /// vertices, its sharp edges kept: 42% of the triangles below 30 degrees
  /// as given, 2.4% at 0.2 (12% at 0.5; the heat kernel over one spacing,
  /// which lowers the peaks too, 1.5%).  Over the corpus and 28 generated
  /// shapes at 2,000 and 10,000 (mean curvature), the remeshes below the
  /// uniform mode's bar on triangles 48 -> 32 of 98, the deviation 0.93
  /// times in geometric mean; at equal deviation the curvature modes' best
  /// count on fandisk, the blade and the bunny 6%, 15% and -5% more (the
  /// heat kernel: 7%, 44% and 17%).
  double ImportanceGradation = 0.2;
  int NumberOfThreads = 0;
  RemeshCache* Cache = nullptr; ///< optional: kept between calls on the same surface and atlas (RemeshCache)
  /// Optional: the points of the surface the remesh must lie on, where the
  /// remesher's `points` are a smoothed copy of them (DenoisedLayout, same
  /// triangles).  The remesh is made on the copy; then every vertex goes to
  /// the same barycentric place of its triangle on these points, and
  /// FinalIterations stitching rounds (swaps and relaxation) shape its
  /// triangles there.  Its fidelity (RemeshResult's Deviation*, Error) is
  /// that of the remesh on the copy, before it moved (the error-driven
  /// mode's bound holds on the copy: the noise's spikes are no lost parts).
  const double* FinalSurface = nullptr;
  int FinalIterations = 5;
  RemeshCache* FinalCache = nullptr; ///< optional: RemeshCache of FinalSurface
};

struct RemeshResult
{
  std::string Error;                 ///< non-empty: no mesh
  std::vector<double> Points;        ///< 3 per vertex
  std::vector<Index> Triangles;      ///< 3 per triangle
  std::vector<Index> SourceTriangle; ///< per vertex: the input triangle it lies on
  std::vector<double> SourceBarycentric; ///< 3 per vertex
  SurfaceSamples Samples;            ///< the control map and the halftone
  /// With a metric: the metric as the remesh followed it, raised on the kept
  /// lines (RaiseMetricOnKeptLines) and graded (RemeshOptions::MetricGradation).
  std::vector<double> GradedMetric;
  RemeshOptimizationStatistics Optimization;
  /// The remesh's fidelity, over the input's bounding-box diagonal: the
  /// largest distance of its triangles' centres and edge midpoints from the
  /// input, and of the input's vertices, edge midpoints and triangle centres
  /// from it (where a part is lost or bridged, or a crease cut), with that
  /// input point (RemeshDistances); and the spacing of the requested count
  /// (of equilateral triangles covering the input).
  double DeviationToInput = 0.0, DeviationFromInput = 0.0;
  Vec3 FarthestInputPoint = Vec3::Zero();
  double Spacing = 0.0, Diagonal = 0.0; ///< of the input (its bounding box)
  /// The far input vertices (RemeshOptions::FarPinSpacings) the fidelity
  /// rounds moved a vertex of the remesh onto; whether far input vertices
  /// are left that no vertex could be moved onto, or whose moves did not
  /// bring the remesh closer (RemeshSurface then remeshes with them pinned).
  std::vector<Index> ReachedFarVertices;
  bool FarVerticesLeft = false;
  double SamplingSeconds = 0.0, TriangulationSeconds = 0.0, OptimizationSeconds = 0.0, FidelitySeconds = 0.0;
};

/// The atlas the remesher wants (thesis sections 4.2.2 and 4.2.4): natural
/// (free) chart boundaries, whose conformal maps are nearly isotropic (a
/// square boundary stretches the charts near it and the triangulation in the
/// plane turns into slivers: bunny00 at 10k vertices 48.1 deg mean minimum
/// angle and 1.6% of the triangles below 30 deg, against 51.0 and 0.4%), and
/// area-balanced charts (long thin charts such as the bunny's ears are
/// squeezed by their maps beyond what the control map can sample: the
/// Hausdorff distance of bunny00 at 10k vertices 1.3% -> 0.8%), and charts
/// split where a third of them or more is squeezed eightfold
/// (AtlasOptions::MaximumSqueezedShare 0.3: the arms of a cactus, the legs
/// and horns of a cow, whose samples the control map could not hold), and
/// where a third of them or more is stretched threefold one way
/// (AtlasOptions::MaximumStretchedShare 0.3: charts of long slivers, whose
/// free boundary overlapped and whose circle map then laid the samples in
/// rows: a decimated bone's remesh folded, with angles of 0 degrees).
/// spacing > 0 (the remesh's, UniformSpacing): dangling feature chains
/// shorter than it are no features (AtlasOptions::MinimumFeatureLength):
/// each end would take a sample of its own, and their charts more samples
/// than the remesh has (fandisk_large, whose creases cross its edges at a
/// slant: 419 ends, 643 charts, 2,585 boundary samples for 2,000).
AtlasOptions RemeshingAtlasOptions(double spacing = 0.0);

/// The edge length of `count` equilateral triangles' vertices covering `area`.
double UniformSpacing(double area, std::int64_t count);

/// What a curvature-adapted remesh follows (thesis 4.3.1's curvature maps).
enum class CurvatureMeasure : int
{
  MeanCurvature = 1,     ///< |kappa_H|
  GaussianCurvature = 2, ///< |kappa_G|
  TotalCurvature = 3,    ///< kappa_1^2 + kappa_2^2
  MaximumCurvature = 4   ///< max(|kappa_1|, |kappa_2|)
};

/// The measure per vertex (chapter 2's operators; boundary vertices NaN).
std::vector<double> CurvatureValues(const MeshTopology& topology, const double* points, CurvatureMeasure measure,
  int numThreads = 0);

/// `steps` implicit heat steps of (width^2 / 2) / steps each on `values`
/// (`columns` per vertex, interleaved) with the surface's cotangent
/// `laplacian`, solved to `tolerance` (relative; the largest |value| is
/// every column's size): the heat kernel of standard deviation `width`
/// (eight steps: its step response within 0.012 of the Gaussian's in 1D;
/// four: 0.020); vertices without area kept; false if a solve did not
/// converge.
bool SmoothOverSurface(const MeshTopology& topology, const double* points, const GraphLaplacian& laplacian,
  double width, int steps, double tolerance, std::vector<double>& values, int numThreads, int columns = 1);

/// A non-constant, positive `importance` (one per vertex) raised where the
/// spacing it gives a remesh of `count` vertices would grow faster than
/// `growth` times the distance along the surface's edges (a Lipschitz
/// gradation of the sizes, as mesh generators grade theirs: MMG's -hgrad);
/// never lowered, so the dense parts keep their density; empty where it is
/// constant.  The cache's surface Laplacian gives the edges and areas.
std::vector<double> GradedImportance(const MeshTopology& topology, const double* points, const double* importance,
  std::int64_t count, double growth, int numThreads, RemeshCache& cache);

/// How values per vertex become the importance (thesis section 4.3.1).
struct ImportanceOptions
{
  /// The transfer function of x = |value| / mean |value|: x^Gamma (0:
  /// uniform; larger gammas adapt more) ...
  double Gamma = 1.0;
  /// ... or, when not empty, the piecewise-linear function through these
  /// (x, importance) pairs (sorted by x; pairs with a non-finite number are
  /// left out), constant beyond the first and the last.
  std::vector<double> TransferFunction;
  /// Smooth gradation: the importance low-pass filtered over the surface
  /// with a kernel of this standard deviation (surface units; 0: none;
  /// widths beyond the bounding-box diagonal act as the diagonal, where the
  /// kernel is flat over the surface already).
  double Gradation = 0.0;
  /// Minimum sampling: the importance is at least this (after the filter).
  double Minimum = 0.0;
};

struct ImportanceResult
{
  std::vector<double> Importance; ///< per vertex, >= 0
  std::string Warning;            ///< non-empty: the gradation's solve did not converge (its last iterate is used)
};

/// The importance from any values per vertex (non-finite values count as
/// the mean: importance 1 before the filter).  The gradation is the heat
/// kernel of variance Gradation^2 on the surface (its natural "Gaussian
/// filter" in surface units, which the thesis approximates by an image
/// filter and would ideally drive by the area map): eight implicit heat steps
/// with the cotangent Laplacian (SolveShiftedLaplacian), keeping the
/// importance's integral over the surface.
ImportanceResult ImportanceFromValues(const MeshTopology& topology, const double* points,
  const std::vector<double>& values, const ImportanceOptions& options, int numThreads = 0);

/// The importance (null: uniform) raised where the surface bends tighter
/// than `count` samples can follow within `sag` of their spacing: at a
/// vertex of larger principal curvature kappa and density spacing s (from
/// the count and the importance's integral over the surface), by the factor
/// kappa s / (8 sag) where it is above 1, but to no finer spacing than the
/// vertex's longest input edge.  The factors are spread over the
/// spacing at importance 1 (one implicit heat step of that variance, solved
/// to 1e-2), so that the density rises smoothly around tight bends.
/// `maximumCurvature`: max |kappa_i| per vertex (CurvatureValues;
/// non-finite values count as 0), taken as 0 on `featureEdges` (one flag
/// per edge of topology.Edges(); may be null): kept lines, whose bends
/// MaximumLineSag bounds.  Empty where no vertex needs more samples (the
/// importance stands).  surfaceLaplacian (optional): the surface's
/// cotangent Laplacian, assembled here where null.
std::vector<double> RaiseImportanceForSag(const MeshTopology& topology, const double* points,
  const double* importance, const std::vector<double>& maximumCurvature, const std::uint8_t* featureEdges,
  std::int64_t count, double sag, int numThreads = 0, const GraphLaplacian* surfaceLaplacian = nullptr);

/// How far (in spacings of the count) an input point may be left from the
/// remesh before CheckFidelity calls a part lost.  A remesh too coarse for
/// the surface's bends stays within a few spacings (over the corpus and the
/// hard shapes at 2k and 10k at most 3.1, the spiky sphere's needles at 2k;
/// the others below 2.4); a limb's end cut off or bridged lies farther
/// (cow.off's hooves: 5-11).
constexpr double LostPartSpacings = 4.0;

/// The remesh's fidelity into `out` (its Deviation* and Spacing), and its
/// Error where its topology is not the input's (Euler characteristic,
/// components, boundary loops, a manifold oriented mesh: a thin part
/// bridged or cut off, or a component lost) or an input point is left
/// farther than LostPartSpacings from it.  RemeshSurface measures its
/// remeshes so (CheckFidelityInRounds).
void CheckFidelity(const MeshTopology& topology, const double* points, const RemeshOptions& options,
  RemeshResult& out);

/// The larger of a remesh's two deviations (to and from the input).
double WorstDeviation(const RemeshResult& r);

/// The share of the closest remesh's deviation (the larger of the two, or
/// their sum where the larger is no farther) a remesh with more far
/// vertices pinned must be within to be kept (RemeshOptions::FarPinSpacings,
/// KeptOver).
constexpr double FarPinGain = 0.98;

/// A remesh is made again with the far vertices pinned (RemeshSurface) only
/// where the closest so far leaves the input farther than this many
/// spacings: over the corpus and the generated shapes at 2,000 and 10,000
/// vertices, no remesh again came closer where the first was within 0.2
/// spacings (a cone's tip 0.17, a needle 0.19; the 1.2M-triangle bunny at
/// 100,000 vertices 0.17 in one order of the moves, where the remesh again
/// took 4.5 s, as long as the first), and where one was at 0.24-0.27 (a CAD
/// part with holes) it came 13-25% closer.
constexpr double FarRemeshSpacings = 0.2;

/// Where no input vertex is left farther than RemeshOptions::FarPinSpacings
/// spacings, a fidelity round takes all those farther than this share of
/// the spacing and than CornerSagRatio times the sag of the nearest remesh
/// triangle's longest edge on a sphere of the input's largest |kappa|
/// there: corners of the input at the remesh's scale, where the density's
/// smooth surface is not the input's (the shared coarse polyhedral spheres
/// under a remesh of 10,000 vertices: their vertices were left 0.06
/// spacings off, 3-24% beyond CGAL's deviation; moved onto, 30-40%
/// within it).
constexpr double CornerPinSpacings = 0.03;
constexpr double CornerSagRatio = 4.0;

/// `importance`: one value >= 0 per input vertex (null: uniform).
RemeshResult RemeshSurface(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const RemeshOptions& options = {});

/// Counts named where a remesh with options.NumberOfVertices fails or
/// leaves an input point farther than its spacing (0: none found).
struct CountAdvice
{
  /// Where it failed: the smallest count found that remeshes (from the
  /// samples the failed remesh's boundaries and charts need, a quarter
  /// more each try, four tries, two significant digits).
  std::int64_t Remeshes = 0;
  /// The smallest count found whose remesh (the same settings otherwise,
  /// without the second remesh of FarPinSpacings) keeps every input point
  /// within its spacing and lies within it of the input: Remeshes where its
  /// remesh does, else the smallest of 2, 4 and 8 times the count above it.
  std::int64_t Keeps = 0;
};

/// The counts to name in the message about `result`, a remesh of
/// options.NumberOfVertices; none beyond MostVerticesPerInputVertex per
/// input vertex (more than the input's resolution can use).
CountAdvice AdviseCounts(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const RemeshOptions& options, const RemeshResult& result);

/// The steps of DenoisedLayout's smoothing a remesh tries, one after the
/// other (order 2, umbrella operator, dimensionless).  On bunny00 with
/// noise along its normals of 0.1-0.6% of the diagonal (whose own charts
/// fail from 0.2%: boundaries that cross, or that take more samples than
/// the count) each of 2, 8 and 32 made it remeshable at 2,000 and 10,000
/// vertices; with isotropic noise of 0.6% (triangles folded by the noise in
/// their planes) a step of 8 left charts that did not join at 2,000, 32
/// and more did.
constexpr double DenoisedLayoutSteps[3] = { 8.0, 32.0, 128.0 };

/// The triangle quality of a remesh (Mesh/MeshMeasures).
TriangleQuality RemeshQuality(const RemeshResult& remesh, int numThreads = 0);

/// Whether the triangles of `second` are as good as those of `first` (a
/// smallest angle as large, or of 15 degrees at least, and no more than a
/// thousandth more of them below 30 degrees), or within the remesher's
/// bar: no angle below 15 degrees and at most 0.5% of them below 30 (the
/// second remesh of bunny00 decimated to a fifth at 2,000 vertices, its far
/// vertices pinned: 1.45% of the diagonal from it, not 1.82%, with 0.15% of
/// its triangles below 30 degrees, none in the first; CGAL 1.56%).
bool AsGoodTriangles(const RemeshResult& second, const RemeshResult& first, int numThreads = 0);

/// The share of the interior edges whose two triangles face more than 90
/// degrees apart: noise as large as the edges folds a tenth of them and
/// more (bunny00 with noise along its normals of 0.1, 0.2 and 0.3% of its
/// diagonal: 0.9, 5.8 and 11.7%; isosurfaces of real MRI volumes 0.2-7.7%;
/// the shared meshes 2% at most).
double FoldedEdgeShare(const MeshTopology& topology, const double* points);

/// At this share of folded edges and above, a remesh of the input's own
/// charts that is poor (PoorRemesh) is made again on a smoothed copy
/// (DenoisedLayout), and that one kept where KeepCopysRemesh says so: the
/// charts of a noisy scan have jagged boundaries, their remesh slivers
/// beside them and parts far from the input (bunny00 with noise of 0.2%
/// of its diagonal at 2,000 vertices: 4.8% of the diagonal from it and
/// 3.5% of its triangles below 30 degrees; on the copy 1.2% and none).
constexpr double CrumpledShare = 0.02;

/// At this share of folded edges and above (FoldedEdgeShare: noise larger
/// than the edges), the remesh is laid out on a smoothed copy first
/// (DenoisedLayout) and kept there where it is not poor (PoorRemesh),
/// before the input's own charts are tried: they fail or remesh poorly
/// there, after their atlas.  The 1.2M-triangle bunny with noise of 0.075%
/// of its diagonal along its normals (10.2% folded) at 100,000 vertices:
/// 11.8 s on its own 28,368 charts, which take more samples than the count,
/// then the copy's remesh; 29.6 s -> 17.4-18.0 s (CGAL 21.0 s), the same remesh.
/// bunny00 with 0.3% (11.7%) at 10,000 vertices: 3.3 s -> 0.6 s.  Over the
/// corpus with noise of 0.3% and 1% of the diagonal (14 cases fold
/// 10-30%) the same remeshes; from 5%, three coarse meshes with 1% at
/// 2,000 vertices (hand, knot1, sphere966: 6.4-6.5% and 5.2%) came out 1.4
/// to 2.1 times farther from the input on the copy than on their own charts.
constexpr double HeavilyFoldedShare = 0.1;

/// Whether a remesh failed, leaves an input point farther than its
/// spacing, or has an angle below 15 degrees or more than 0.5% of its
/// triangles below 30.
bool PoorRemesh(const RemeshResult& remesh, int numThreads = 0);

/// A remesh laid out on a smoothed copy of the input may be this many
/// times as far from the input as the input's own (both follow its noise;
/// the copy's triangles are the better ones).
constexpr double CopyDeviationAllowance = 1.25;

/// Whether `copy` (laid out on a smoothed copy, moved onto the input) is
/// kept over `own` (the input's own charts): it succeeded, its triangles
/// are as good (AsGoodTriangles) and it is at most CopyDeviationAllowance
/// times as far from the input.
bool KeepCopysRemesh(const RemeshResult& copy, const RemeshResult& own, int numThreads = 0);

/// A copy of `points` for laying a remesh out on where the input's own
/// charts fail (a scan whose noise is as large as its edges: its charts'
/// boundaries are jagged, cross, or take more samples than the count): the
/// surface after one implicit umbrella step of order 2 of `step`
/// (DenoisedLayoutSteps; Flows/Fairing.h), whose uniform weights do not
/// depend on the noisy triangles' shapes, its boundary loops smoothed as
/// curves; same triangles.  Empty where the step cannot run or leaves the
/// points as they are.
std::vector<double> DenoisedLayout(const MeshTopology& topology, const double* points, double step,
  int numThreads = 0);

/// The error-driven mode (as MMG's -hausd; the thesis' future work):
/// remeshes until the remesh is within `maximumDeviation` (a fraction of the
/// input's bounding-box diagonal) of the input both ways (RemeshResult's
/// Deviation*).  options.NumberOfVertices: the least count to use, or 0 for
/// as few as the deviation takes, estimated first from the curvature (a
/// triangle of spacing s departs about s^2 kappa / 8 from a surface of
/// largest principal curvature kappa).  Null `importance` starts from the
/// density that curvature needs where it is more than twice its mean
/// (WeightsForDeviation), 1 elsewhere.  Each remesh takes its fidelity
/// rounds (RoundsWithPinnedVertices).  After each remesh the importance
/// is raised at the input's vertices left
/// farther than the bound, by the ratio of their distance to it (the
/// deviation falls with the square of the spacing), spread over the
/// spacing, with the count raised in proportion (by a tenth at least), so
/// that the density elsewhere stays, and the input's vertices farthest
/// from it are pinned (SamplingOptions::PinnedVertices); where two rounds
/// in a row bring the remesh no closer, the count is raised everywhere
/// instead, by the square of the deviation over the bound, a quarter more
/// to twice (twice at most); with a metric (options.Metric), whose lengths
/// keep the deviation even, the count alone is raised, by the ratio of the
/// deviation to 0.85 of the bound, and the farthest input vertices are
/// pinned.  The importance is graded once first (ImportanceGradation).  At
/// most `maximumRounds` remeshes, fewer where the raised
/// counts do not help either or the count reaches
/// MostVerticesPerInputVertex times the input's vertices.  The result is
/// the last remesh; Rounds and Met say how it went.
/// (RemeshToDeviation: its largest count per vertex of the input.)
constexpr std::int64_t MostVerticesPerInputVertex = 64;
struct DeviationRemeshResult
{
  RemeshResult Remesh;
  int Rounds = 0;
  bool Met = false; ///< both deviations within the bound
  std::vector<std::int64_t> Counts; ///< the count of each round
};
DeviationRemeshResult RemeshToDeviation(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const double* importance, const RemeshOptions& options, double maximumDeviation, int maximumRounds = 12);

} // namespace beltrami
