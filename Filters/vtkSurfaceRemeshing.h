/**
 * @class   vtkSurfaceRemeshing
 * @brief   Remeshes a triangle surface of any genus, open or closed, with
 *          exactly NumberOfVertices vertices (thesis chapter 4): uniform,
 *          adapted to curvature or to a point array, or anisotropic.
 *
 * The surface's atlas (vtkSurfaceAtlas's core with natural chart boundaries
 * and area-balanced charts, section 4.2.4; sharp edges kept as chart
 * boundaries with SplitAtFeatures) gives the control map: the area map of
 * the packed atlas times an importance per vertex (section 4.3.1).  Exactly
 * NumberOfVertices samples are spread over it: the chart boundaries (seams,
 * the surface's boundary, sharp edges) by 1D error diffusion with the
 * square-root law (the surface's boundary and sharp edges more densely where
 * they bend, MaximumLineSag), the rest by Ostromoukhov's variable-coefficient
 * error diffusion (section 4.3.2).  They are triangulated chart by chart in the
 * parameter plane (CGAL's constrained Delaunay triangulation with exact
 * predicates, the boundary samples as constraints; section 4.4.1), lifted
 * to 3D through the input triangles (barycentric coordinates), joined along
 * the shared boundary samples into one watertight mesh with the input's
 * topology, and optimised with the vertices kept (sections 4.4.2-4.4.4):
 * Iterations rounds of area/perimeter^2 and valence edge swaps and Lloyd
 * relaxation (over-relaxed Lloyd steps, 1.8 times the way to the cell
 * centroids; default 25): the first fifth in the parameter planes, seam vertices
 * sliding along the seams, the rest stitching the charts (section 4.4.4):
 * swaps across the seams and Lloyd relaxation on the surface in 3D, seam
 * vertices free, only the surface's boundary and the sharp edges (with
 * SplitAtFeatures) kept as lines.
 *
 * Importance: UNIFORM (default), MEAN_CURVATURE (|H|), GAUSSIAN_CURVATURE
 * (|K|), TOTAL_CURVATURE (k1^2 + k2^2), MAXIMUM_CURVATURE (max |k_i|) or
 * POINT_ARRAY (input array 0, a 1-component point array), through the
 * transfer function of x = |value| / mean: x^Gamma, or the piecewise-linear
 * function through the points given by AddTransferFunctionPoint(x,
 * importance) when there are any; then low-pass filtered over the surface
 * when Gradation > 0 (smooth gradation: the heat kernel of that standard
 * deviation, in surface units) and raised to at least MinimumImportance:
 * vertex density proportional to it.  Where the surface bends tighter than
 * that density can follow (a triangle of its spacing s would depart from
 * the surface by more than MaximumSurfaceSag times s, about s^2 kappa / 8
 * with kappa the larger principal curvature), the density is raised there
 * (to no finer spacing than the input's own edges there), with a smooth
 * gradation over one spacing, so the remesh keeps to the
 * surface (a uniform remesh of the bunny at 10k vertices: Hausdorff distance
 * 0.51% -> 0.31% of the diagonal, edge-length variation 0.089 both;
 * MaximumSurfaceSag 0: the density as given).
 *
 * Anisotropy PRINCIPAL_CURVATURES (the thesis' future work, section 6.2)
 * remeshes in a metric from the curvature tensor: wanted edge lengths
 * proportional to |k_i|^(-1/2) along the principal directions (at most
 * MaximumAnisotropy times longer one way; MinimumImportance: the least
 * density), graded over the remesh's spacing; TENSOR_ARRAY takes the metric
 * from input array 1 (6 components: xx, yy, zz, xy, yz, xz).  The density
 * follows the metric (times the importance), chart boundaries and kept lines
 * are sampled at its length along them (kept lines no sparser than a
 * uniform remesh's), and the swaps, the relaxation (Lloyd's step in the
 * metric; the first half of the stitching rounds pulled towards a lattice
 * aligned with it) and the sliver repair measure in it.  Output point array
 * Metric (scaled to the count) and field array RemeshMetricQuality.
 *
 * Output 0: the remesh (triangles), the input's point arrays interpolated at
 * its vertices (barycentric in the input triangle under each), its cell
 * arrays from the input cell nearest each triangle's centre, point array
 * SampleKind (0 inside a chart, 1 on a chart boundary, 2 at a corner of the
 * chart boundaries, 3 pinned at a tip: an input vertex whose angle defect
 * exceeds 1 radian, a cone narrower than about 57 degrees - a spike's,
 * horn's or finger's tip, the sharpest of those closer than the spacing -
 * takes its chart's nearest interior sample, which the relaxation leaves
 * there), field arrays RemeshMeanMinimumAngle,
 * RemeshMinimumAngle, RemeshFractionBelow30, RemeshFractionValence6,
 * RemeshEdgeLengthVariation (degrees and fractions), RemeshCharts,
 * RemeshDeviation (the remesh's fidelity, measured after every run, as
 * fractions of the input's bounding-box diagonal: the largest distance of
 * its triangles' centres and edge midpoints from the input, and of the
 * input's vertices, edge midpoints (a spacing apart along edges longer than
 * two spacings) and triangle centres from it; a warning
 * names the input point where a part is left farther than the remesh's
 * spacing, and beyond four spacings - a limb's end cut off or
 * bridged - it is an error with an empty output) and RemeshSeconds (sampling,
 * triangulation, optimisation, the fidelity's measurement).  The
 * error-driven mode (MaximumDeviation > 0, as MMG's -hausd) remeshes until
 * both deviations are within that fraction of the diagonal, raising the
 * density where the input is left farther (field array RemeshRounds: the
 * count of each remesh).  Output 1: a
 * vtkMultiBlockDataSet with the control map as an image (block
 * "ControlMap": point arrays ControlMap, expected samples per texel, NaN
 * outside the charts, and Halftone, 1 where an interior sample is).
 *
 * The input's surface (topology and edge table), its curvatures and its
 * atlas are kept between runs: changing only NumberOfVertices, Importance,
 * Gamma, MinimumImportance, the transfer function, Gradation or Iterations
 * re-runs the control map, sampling, triangulation and optimisation only
 * (with Iterations 0, a preview of a uniform 10k remesh of the bunny in
 * about 0.1 s).  Inconsistently oriented input is oriented and an unwelded
 * one (coincident points) welded first, with a warning.  Non-manifold or
 * non-orientable input, NaN points, coordinates beyond 1e75 (or a bounding box
 * below 1e-75), empty input and counts the chart boundaries cannot hold are
 * reported as errors with an empty output, and so is a remesh whose
 * topology (Euler characteristic, components, boundary loops) is not the
 * input's: a filter that cannot keep a part says so rather than return a
 * mesh without it.  Where the input's own charts fail (a scan whose noise is
 * as large as its edges), the remesh is laid out on a smoothed copy (one
 * implicit umbrella step, beltrami::DenoisedLayout, of the steps
 * beltrami::DenoisedLayoutSteps in turn), moved onto the input and its
 * triangles shaped there by a few stitching rounds, with a warning: its
 * vertices lie on the input and follow its noise; on an input whose noise
 * folds a tenth of its edges and more (beltrami::HeavilyFoldedShare) the
 * copy comes first, and its remesh is kept where it is not poor, without
 * the input's own charts.  Where no copy remeshes
 * and the chart boundaries still take more than the count (a surface of
 * many handles at a low count), the seams between charts are sampled two,
 * then three times as sparsely, with a warning; only counts they cannot
 * hold even so are errors.  On an input that does not fold, so too where a
 * copy's remesh is farther from the input than its spacing (the copy
 * rounded off thin parts or sharp edges) and the sparser seams' comes
 * closer.  Where the error-driven mode misses its bound
 * with SplitAtFeatures off, it runs again with the edges sharper than
 * FeatureAngle kept, with a warning, and keeps that remesh where it meets
 * the bound or comes closer.
 * Charts far smaller than the spacing (a speck of a
 * scan) keep one interior sample each, so their components stay closed.  The remesher
 * needs the whole surface: split data are gathered on rank 0, which holds
 * the remesh.
 */
#ifndef vtkSurfaceRemeshing_h
#define vtkSurfaceRemeshing_h

#include "BeltramiFiltersModule.h"
#include <vtkPolyDataAlgorithm.h>

#include <cstdint> // for the feature flags
#include <memory>  // for the kept atlas
#include <vector> // for the transfer function

namespace beltrami
{
struct AtlasResult;
struct RemeshResult;
}

class BELTRAMIFILTERS_EXPORT vtkSurfaceRemeshing : public vtkPolyDataAlgorithm
{
public:
  static vtkSurfaceRemeshing* New();
  vtkTypeMacro(vtkSurfaceRemeshing, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum ImportanceType
  {
    UNIFORM = 0,
    MEAN_CURVATURE = 1,
    GAUSSIAN_CURVATURE = 2,
    TOTAL_CURVATURE = 3,
    MAXIMUM_CURVATURE = 4,
    POINT_ARRAY = 5
  };
  enum AnisotropyType
  {
    ISOTROPIC = 0,
    PRINCIPAL_CURVATURES = 1,
    TENSOR_ARRAY = 2
  };

  /// The vertices of the remesh, met exactly. With a Maximum Deviation, the least count (0: as few
  /// as the deviation takes). Default: 10000.
  vtkSetClampMacro(NumberOfVertices, vtkIdType, 0, VTK_ID_MAX);
  vtkGetMacro(NumberOfVertices, vtkIdType);
  /// The error-driven mode (0: off): the remesh's two-sided deviation from the input at most this
  /// fraction of the input's bounding-box diagonal (e.g. 0.002). With Importance uniform, the
  /// density starts raised where the surface bends more than twice its mean largest curvature, in
  /// proportion (the density a smooth surface's sag needs; not beside kept sharp edges). The
  /// density is then raised where the input is left farther, and the vertex count with it, remesh
  /// after remesh, each with its Fidelity Rounds; a warning says where the bound was not met within
  /// Maximum Deviation Rounds. Default: 0.
  vtkSetClampMacro(MaximumDeviation, double, 0.0, 1.0);
  vtkGetMacro(MaximumDeviation, double);
  /// The most remeshes the error-driven mode makes to meet the Maximum Deviation. Default: 12.
  vtkSetClampMacro(MaximumDeviationRounds, int, 1, 100);
  vtkGetMacro(MaximumDeviationRounds, int);
  /// What the vertex density follows: uniform (equal triangles), a curvature of chapter 2, or the
  /// Importance Array; through the transfer function of x = |value| / mean (x^Gamma, or the
  /// Transfer Function points), the Gradation filter and the Minimum Importance. Values: 0 Uniform,
  /// 1 Mean curvature |H|, 2 Gaussian curvature |K|, 3 Total curvature k1^2+k2^2, 4 Maximum
  /// curvature max|k|, 5 Point array. Default: Uniform.
  vtkSetClampMacro(Importance, int, UNIFORM, POINT_ARRAY);
  vtkGetMacro(Importance, int);
  /// The anisotropic mode (the thesis' future work, section 6.2): triangles stretched along the
  /// directions the surface bends least in, sampled, triangulated and optimised in a metric, a
  /// symmetric tensor per point (an edge d is of unit length where d^T T d = 1). From the principal
  /// curvatures, the wanted edge length along each principal direction is proportional to
  /// |k_i|^(-1/2), so that the chordal error is even, at most Maximum Anisotropy times longer one
  /// way than the other, with a density of at least Minimum Importance times the mean, graded over
  /// the remesh's spacing (or over Gradation when it is set); or the Metric Array. The metric's
  /// density times the importance is the vertex density; output point array Metric (the metric
  /// scaled to the count) and field array RemeshMetricQuality (in the metric: median edge length,
  /// share of edges within 20% of 1, smallest and mean smallest angle, share of triangles below 30
  /// degrees). Values: 0 Isotropic, 1 Principal curvatures, 2 Tensor array. Default: Isotropic.
  vtkSetClampMacro(Anisotropy, int, ISOTROPIC, TENSOR_ARRAY);
  vtkGetMacro(Anisotropy, int);
  /// The anisotropic mode's longest over shortest wanted edge length at a point, at most (1:
  /// isotropic, with the density of the curvature's geometric mean). Default: 6.
  vtkSetClampMacro(MaximumAnisotropy, double, 1.0, 100.0);
  vtkGetMacro(MaximumAnisotropy, double);
  /// Exponent of the transfer function: 0 gives a uniform mesh, larger values adapt more to the
  /// importance. Default: 1.0.
  vtkSetClampMacro(Gamma, double, 0.0, 10.0);
  vtkGetMacro(Gamma, double);
  /// Smooth gradation of the vertex density (section 4.3.1): the importance low-pass filtered over
  /// the surface by the heat kernel of this standard deviation, in the surface's units (0: instead,
  /// the importance is raised where the spacing it gives would grow faster than a fifth of the
  /// distance, as mesh generators grade their sizes, so that the triangles grow gradually away from
  /// a curvature's peaks at creases and rims rather than leave slivers between fine and coarse
  /// ones; the peaks keep their density). A few mean edge lengths of the remesh calm a noisy
  /// curvature; the importance's integral is kept. In the anisotropic mode, the metric's components
  /// are filtered so instead (0: over the remesh's spacing). Default: 0.
  vtkSetClampMacro(Gradation, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Gradation, double);
  /// The transfer function as a piecewise-linear function of x = |value| /
  /// mean |value| (points in ascending x; constant beyond the first and
  /// last), used instead of x^Gamma when it has points.
  void AddTransferFunctionPoint(double x, double importance);
  void RemoveAllTransferFunctionPoints();
  int GetNumberOfTransferFunctionPoints() const { return static_cast<int>(this->TransferFunction.size() / 2); }
  /// The least importance, relative to the mean: flat regions keep at least this density (in the
  /// anisotropic mode, the least density of the metric from the curvatures). Default: 0.05.
  vtkSetClampMacro(MinimumImportance, double, 0.0, 1.0);
  vtkGetMacro(MinimumImportance, double);
  /// Keep sharp edges (normals differing by more than Feature Angle) as chart boundaries, sampled
  /// along them so that the remesh reproduces them (CAD parts, section 4.2.3). A crease that
  /// crosses the input's edges at a slant is sharp on only some of them: the ends of its fragments
  /// are joined along the sharpest edges above half the Feature Angle where the path is no longer
  /// than the remesh's spacing, and dangling runs still shorter than the spacing are not kept; with
  /// Maximum Deviation every run is kept as it is. A line whose crease fades out is continued along
  /// the sharpest edges above half the Feature Angle that turn it by at most 30 degrees. A triangle
  /// turned over against two of its neighbours (a fold of the input, not a crease) makes no sharp
  /// edge. Default: off.
  vtkSetMacro(SplitAtFeatures, bool);
  vtkGetMacro(SplitAtFeatures, bool);
  vtkBooleanMacro(SplitAtFeatures, bool);
  /// Dihedral angle in degrees above which an edge is sharp. Default: 60.
  vtkSetClampMacro(FeatureAngle, double, 0.0, 180.0);
  vtkGetMacro(FeatureAngle, double);
  /// Where a sharp edge line or the surface's boundary bends, it gets more samples than the density
  /// gives: the chord between two of them departs from the line by at most this fraction of the
  /// remesh's spacing there (the rest of the surface gets correspondingly fewer; 0: the density's
  /// spacing everywhere). Default: 0.05.
  vtkSetClampMacro(MaximumLineSag, double, 0.0, 1.0);
  vtkGetMacro(MaximumLineSag, double);
  /// Where the surface bends tighter than the density can follow (a triangle of its spacing would
  /// depart from the surface by more than this fraction of the spacing, about spacing^2 x curvature
  /// / 8 with the larger principal curvature), the density is raised there, smoothly over one
  /// spacing, so the remesh keeps to the surface; a uniform remesh stays uniform wherever the
  /// spacing follows the surface (0: the density as given). In the anisotropic mode, the same bound
  /// for the metric's shortest edges, along the most curved direction (tubes and fins thinner than
  /// them). Default: 0.1.
  vtkSetClampMacro(MaximumSurfaceSag, double, 0.0, 1.0);
  vtkGetMacro(MaximumSurfaceSag, double);
  /// Where the remesh leaves input vertices farther from it than 0.15 of its spacing (corners, tips
  /// and hooves its samples missed: the density keeps a smooth surface within a tenth of the
  /// spacing), the nearest remesh vertex that can move there without folding a triangle is moved
  /// onto each and kept there, and the triangles around are relaxed again, up to this many rounds
  /// (each measuring again); where points along input edges are that far (creases of an input
  /// coarser than the remesh, which its triangles cut), the round is made twice, once also moving
  /// vertices so onto points a spacing apart along those edges, once with the vertices alone, and
  /// the closer kept (vertices so moved onto one edge of a crease, where its triangles meet at 20
  /// degrees or more, are joined by a remesh edge along it where the triangles keep half their
  /// roundness, and that edge is kept); where none is that far, every input vertex farther than
  /// 0.03 of the spacing and four times a spacing's sag on its curvature (the corners of an input
  /// coarser than the remesh) is moved onto so; where vertices are left that none could reach, or
  /// whose moves brought the remesh no closer, the remesh is made again with them pinned, up to
  /// this many times. The closest with triangles as good is kept. 0: one remesh as made, the
  /// fastest. Over the shared corpus at 10,000 vertices the rounds bring the two-sided deviation
  /// down by 21% in geometric mean, by a third to a half on coarse scans, in 1.3 times the time of
  /// one remesh. RemeshDeviation reports the one kept. In the error-driven mode (Maximum Deviation)
  /// each remesh takes the moves, beside the input vertices that mode pins; it makes no remesh
  /// again. Default: 3.
  vtkSetClampMacro(FidelityRounds, int, 0, 100);
  vtkGetMacro(FidelityRounds, int);
  /// Rounds of edge swaps and relaxation after the triangulation, the first fifth in the charts'
  /// parameter planes and the rest stitching the charts on the surface (0: the constrained Delaunay
  /// triangulation as it is). Default: 25.
  vtkSetClampMacro(Iterations, int, 0, VTK_INT_MAX);
  vtkGetMacro(Iterations, int);
  /// Threads for the atlas, the maps and the triangulation; 0 uses all cores, shared among the
  /// processes of an MPI job on the node (or BELTRAMI_NUM_THREADS). Default: 0.
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);
  /// How many times the atlas was built (it is kept while the input and the
  /// feature settings stay the same).
  vtkGetMacro(AtlasBuilds, int);

protected:
  vtkSurfaceRemeshing();
  ~vtkSurfaceRemeshing() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  /// (Composite inputs: vtkBeltramiSurface::NewCompositeOutputs.)
  vtkTypeBool ProcessRequest(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkIdType NumberOfVertices = 10000;
  double MaximumDeviation = 0.0;
  int MaximumDeviationRounds = 12;
  int Importance = UNIFORM;
  int Anisotropy = ISOTROPIC;
  double MaximumAnisotropy = 6.0;
  double Gamma = 1.0;
  double MinimumImportance = 0.05;
  double Gradation = 0.0;
  std::vector<double> TransferFunction; ///< (x, importance) pairs
  bool SplitAtFeatures = false;
  double FeatureAngle = 60.0;
  double MaximumLineSag = 0.05;
  double MaximumSurfaceSag = 0.1;
  int FidelityRounds = 3;
  int Iterations = 25;
  int NumberOfThreads = 0;
  int AtlasBuilds = 0;

private:
  /// The error-driven mode keeps the sharp edges of this run (where the
  /// bound was missed without them: KeepSharpEdgesWhereMissed).
  bool KeepingSharpEdges = false;
  bool SharpEdgesTried = false; ///< and not kept: they did not bring the remesh closer
  bool SplitsAtFeatures() const { return this->SplitAtFeatures || this->KeepingSharpEdges; }
  vtkSurfaceRemeshing(const vtkSurfaceRemeshing&) = delete;
  void operator=(const vtkSurfaceRemeshing&) = delete;

  struct Layout;
  struct Run;
  int Build(vtkPolyData* input, vtkPolyData* output);
  /// One remesh of the active layout into `run` (its seams sampled sparser
  /// where they take more than the count: beltrami::SamplingOptions::
  /// SparserSeams); false on error (reported) before any remesh.
  bool RemeshLayout(Run& run, bool sparserSeams = false);
  /// The importance per input vertex of the settings (empty: uniform);
  /// false on error (reported).
  bool BuildImportance(std::vector<double>& importance);
  /// Makes the input's smoothed copy of the k-th step of
  /// beltrami::DenoisedLayoutSteps the active layout (made once per input);
  /// false where there is none.
  bool LayOutOnDenoisedCopy(int k);
  /// The remesh laid out on the first smoothed copy that can be remeshed
  /// (where its remesh is poor, on the next ones too, the better kept:
  /// beltrami::KeepCopysRemesh) and moved onto the input into `run` (that
  /// copy stays the active layout); false where none can.  Made once per
  /// update (Kept::DenoisedRun), which its fallbacks share.
  bool RemeshDenoised(Run& run);
  /// On an input that folds heavily (beltrami::HeavilyFoldedShare), `run`
  /// laid out on a smoothed copy first (RemeshDenoised), with a warning,
  /// where that remesh is not poor; false otherwise, and with sharp edges
  /// kept or in the error-driven mode.
  bool LayOutFoldedInputOnCopyFirst(Run& run);
  /// Where the input's own charts fail, or remesh poorly on a noisy input,
  /// `run` laid out on a smoothed copy (RemeshDenoised), with a warning.
  void LayOutNoisyInputOnCopy(Run& run);
  /// Where the input's own chart boundaries still take more samples than
  /// the count, `run` again with its seams sampled sparser, with a warning.
  void LayOutWithSparserSeams(Run& run);
  /// `run` again with the input's seams sampled sparser, with a warning
  /// (its chart boundaries needed `needed` samples), where that remeshes
  /// (and, given a `rival`, comes closer to the input than it); false
  /// otherwise, `run` unchanged.  Not in the error-driven mode.
  bool RemeshWithSparserSeams(Run& run, std::int64_t needed, const beltrami::RemeshResult* rival);
  /// Where the error-driven mode missed its bound with the input's sharp
  /// edges rounded off, `run` again with them kept, with a warning, where
  /// that meets the bound or comes closer.
  void KeepSharpEdgesWhereMissed(Run& run);
  /// The run's messages and, without an error, its remesh into `output`.
  int Report(vtkPolyData* input, const Run& run, vtkPolyData* output);
  /// The anisotropic mode's metric (6 per input vertex) into `metric`;
  /// false on error (reported).
  bool BuildMetric(const std::uint8_t* featureEdges, std::vector<double>& metric);
  /// Keeps the input's surface (Cache), or the one kept while the input's
  /// geometry is the one it was built from: 1, -1 for an empty input
  /// (warned), 0 on error (reported).
  int KeepSurface(vtkPolyData* input);
  /// The atlas of the kept surface: the kept one while the feature settings
  /// are those it was built for.
  const beltrami::AtlasResult& Atlas();

  struct Kept;
  std::unique_ptr<Kept> Cache;
};

#endif
