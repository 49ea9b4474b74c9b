// Beltrami core: feature-preserving graph flows for bivariate data (thesis
// section 3.8): images, colour images, vector fields and height fields on a
// pixel grid, and point data on triangle meshes.
//
// The data f (n components) over a 2-manifold is the graph surface
// S = (base point, alpha f) in R^(2+n) (images) or R^(3+n) (surfaces).  With
// B = Delta_g S its Laplace-Beltrami operator (the cotangent formula of
// section 2.8.1, cotangents from dot products in R^N) and B_bar its data
// components, the flow moves the data only (a graph flow, section 3.6):
//
//     d(alpha f)/dt = E^(gamma - 1) B_bar,
//
// with E the edge indicator in [0, 1]: |B_bar| / |B| on images (eq. 3.22),
// bounded below by A_base / A_graph, and that ratio of the mixed areas on
// surfaces (1/W, eq. 3.17).  On the smooth surface |B_bar| / |B| >= 1/W
// (the normal's data part is at least 1/W), with equality for greyscale;
// the discrete B is not exactly normal, and where B_bar vanishes (an
// inflection of the noise) the ratio fell to 0 and the gamma < 1 speed
// E^(gamma - 1) exploded (gamma = -1 at the default explicit step: camera
// image to 1.8 dB, values to 94).  The bound keeps the speed at most
// W^(1 - gamma).
// Tetrahedral volumes (section 2.8.2) use the same flow one dimension up.
// gamma is the edge-contrast parameter of eq. 3.19: gamma = 1 is the Beltrami
// flow (Delta_g f), gamma = 0 El-Fallah-Ford, gamma = -1 the graph flow that
// is geometrically a mean curvature flow (eq. 3.21).  For greyscale images
// E = 1/W, so the flow is I_t = -kappa_H / W^gamma, eq. 3.19 exactly; eq.
// 3.22 writes the colour flow with the exponent gamma - 1.
//
// Integration (section 3.8.5): explicit Euler, or semi-implicit Euler with
// the weights, areas and indicators of the current state (a sparse SPD system
// per step, solved by conjugate gradients, all channels at once).  Time step
// fixed, or adapted from the change of the total area.  Stop after a fixed
// number of steps, by the discrepancy principle (when the RMS change of the
// data reaches the noise level), or at the least estimated risk: Monte-Carlo
// SURE (Stein's unbiased risk estimate, Ramani, Blu and Unser 2008), the
// mean squared error to the unknown clean data estimated at every step from
// a second run on the data plus a small known perturbation.
#pragma once

#include "Mesh/MeshMeasures.h"
#include "Mesh/MeshTopology.h"
#include "Solvers/Partition.h"
#include "Support/Parallel.h"

#include <cstdint>
#include <functional>
#include <string>

namespace beltrami
{

enum class GraphFlowIntegration : int
{
  Explicit = 0,
  SemiImplicit = 1
};

/// When the time loop ends.
enum class GraphFlowStop : int
{
  Iterations = 0, ///< after NumberOfIterations steps
  NoiseLevel = 1, ///< when the RMS change reaches NoiseLevel (discrepancy principle)
  MinimumRisk = 2 ///< at the step of least estimated risk (SURE; NoiseLevel is the noise)
};

/// What the image flow assumes beyond the image border.
enum class GridBoundary : int
{
  Reflect = 0, ///< mirror (Neumann): f(-1) = f(1)
  Linear = 1   ///< linear extrapolation: f(-1) = 2 f(0) - f(1); ramps are fixed points
};

/// The defaults are those of vtkImageBeltramiDenoising; ForMeshes() gives
/// those of vtkSurfaceDataDenoising and vtkTetrahedralBeltramiDenoising (one
/// source: the filters start from these).
struct GraphFlowOptions
{
  /// alpha: data units -> embedding units (section 3.8.4).  0 (default):
  /// automatic, c h / sigma with h the base's length unit (the spacing's
  /// geometric mean on images, Units on meshes), sigma the noise level and c
  /// calibrated with the least-risk stop (1.5; 1.0 on volumes).
  double ContrastScale = 0.0;
  double EdgeContrast = 1.0;  ///< gamma of eq. 3.19 (1: Beltrami flow)
  GraphFlowIntegration Integration = GraphFlowIntegration::Explicit;
  /// In (length unit)^2 of the base: pixel spacing, or `Units` on meshes.
  /// 0: automatic, below the explicit stability limit on unit grids: 0.2 on
  /// pixel grids (limit about 0.24), 0.1 on voxel grids (0.12) and meshes.
  double TimeStep = 0.0;
  /// Meshes: the length unit of the base (TimeStep, ContrastScale): the mean
  /// edge length (the same settings suit meshes of any size) or the mesh's
  /// own units.  Images use their spacing.
  LengthUnit Units = LengthUnit::MeanEdgeLength;
  bool AdaptiveTimeStep = false;
  int NumberOfIterations = 10; ///< the steps of GraphFlowStop::Iterations
  /// The rule that ends the flow.  NoiseLevel and MinimumRisk need NoiseLevel
  /// > 0 (legacy: NoiseLevel > 0 with Iterations stops by NoiseLevel too, after at
  /// most NumberOfIterations steps).
  GraphFlowStop Stop = GraphFlowStop::MinimumRisk;
  /// The safety bound of the rule-based stops (NoiseLevel, MinimumRisk): far
  /// above what the rules need; GraphFlowResult::StoppedByLimit tells when
  /// it ended a run before its rule.
  int MaximumNumberOfIterations = 2000;
  /// MinimumRisk on grids of more than 2^21 values (samples x components)
  /// with explicit steps: the probe run covers a band of about 1/8 of an
  /// image's rows or 1/16 of a volume's planes, not all of them; false: all
  /// (twice the work).
  bool WindowedRisk = true;
  /// The standard deviation of the noise (per component, data units): the
  /// stop of NoiseLevel and MinimumRisk.  0: estimated from the data.
  double NoiseLevel = 0.0;
  /// Optional, for data smoothed in another space than the one the noise
  /// lives in (colours flowed in L*u*v*, noise in RGB): converts values
  /// (data units, Components per vertex, in place) into the noise's space,
  /// and back.  The change and the risk are measured in the noise's space.
  /// On a mesh split over processes they convert every row of the piece
  /// with its rings (ghost rows too).
  std::function<void(double* values)> ToNoiseSpace, FromNoiseSpace;
  GridBoundary Boundary = GridBoundary::Linear; ///< images only
  double SolverTolerance = 1e-4;                ///< semi-implicit: CG residual reduction
  int MaximumSolverIterations = 500;
  int NumberOfThreads = 0;

  /// The defaults of the mesh filters: semi-implicit steps of 0.1 h^2.
  static GraphFlowOptions ForMeshes()
  {
    GraphFlowOptions o;
    o.Integration = GraphFlowIntegration::SemiImplicit;
    o.TimeStep = 0.1;
    return o;
  }
};

struct GraphFlowResult
{
  bool Completed = true;      ///< false if cancelled (the values of the last full step)
  std::string Error;          ///< non-empty: nothing was changed
  int Iterations = 0;         ///< steps taken
  double Time = 0.0;          ///< total flow time (length^2 of the base, physical)
  double InitialArea = 0.0;   ///< area (volume) of the graph before / after, physical units
  double FinalArea = 0.0;
  double RMSChange = 0.0;     ///< RMS of f_out - f_in per component (data units)
  /// The last step and the explicit stability limit (positivity, smallest
  /// seen), in the units of TimeStep.
  double LastTimeStep = 0.0;
  double SmallestStableStep = 0.0;
  int UnstableSteps = 0;      ///< explicit steps larger than that limit
  int SolverIterations = 0;   ///< semi-implicit: CG iterations, all steps
  /// Semi-implicit: whether every solve reached SolverTolerance within
  /// MaximumSolverIterations, and the largest relative residual of those
  /// that did not.
  bool SolverConverged = true;
  double LargestSolverResidual = 0.0;
  /// MinimumRisk: the estimated root mean squared error to the clean data
  /// (data units) at the input and at the result.
  double InitialRisk = 0.0;
  double FinalRisk = 0.0;
  /// A rule-based stop (NoiseLevel, MinimumRisk) ended by
  /// MaximumNumberOfIterations before its rule.
  bool StoppedByLimit = false;
  /// The noise level estimated from the data (Flows/NoiseEstimation; 0
  /// where the domain is too small), the noise level and the contrast scale
  /// the run used.
  double EstimatedNoiseLevel = 0.0;
  double NoiseLevel = 0.0;
  double ContrastScale = 0.0;
};

/// A pixel grid: Width x Height samples, row-major (x fastest), spacing in
/// physical units.
struct PixelGrid
{
  Index Width = 0;
  Index Height = 0;
  double SpacingX = 1.0;
  double SpacingY = 1.0;
};

/// A piece of a grid split over processes (ParaView's ranks): the grid
/// given to a flow is the box of the whole grid from sample Origin (x, y,
/// z; 2D grids: z 0, Whole[2] 1) - the samples this process owns and a
/// ring of one sample around them wherever the whole grid goes on, all in
/// the grid's order - and Split says which it owns and who owns the others
/// (Solvers/Partition; the values and mask of the ring are their owners').
/// Every process calls the flow with its piece, an empty one too
/// (collective); the noise estimate (an exact median over the processes),
/// the figures, the stops' sums and the semi-implicit solves run over all
/// of them, and each process's samples of the result are those of a serial
/// run on the whole grid to round-off and the solver's tolerance.
struct GridPiece
{
  std::int64_t Whole[3] = { 1, 1, 1 };
  std::int64_t Origin[3] = { 0, 0, 0 };
  const Partition* Split = nullptr;
};

/// Runs the flow on `components` (1 to 6) interleaved values per pixel,
/// in place.  fixed (optional): non-zero = pixel kept as it is.  piece
/// (optional): the grid is a piece of a grid split over processes.
GraphFlowResult RunImageGraphFlow(const PixelGrid& grid, int components, double* values,
  const std::uint8_t* fixed, const GraphFlowOptions& options,
  const ProgressCallback& progress = {}, const GridPiece* piece = nullptr);

/// Runs the flow on point data over a triangle mesh: points are 3 doubles per
/// vertex, `components` (1 to 5) interleaved values per vertex, in place.
/// Vertices that are fixed, non-manifold, isolated or without area keep
/// their values.  split (optional, collective): the surface split over
/// processes (Solvers/Partition: each process its rows and the 1-rings of
/// its own, values and fixed flags of ghost rows their owners'); every
/// process, one with an empty piece too, calls it; the mean edge length, the
/// noise estimate, the sums of the stops and the semi-implicit solves run
/// over all of them: the serial numbers up to the solver's tolerance.
GraphFlowResult RunSurfaceGraphFlow(const MeshTopology& topology, const double* points,
  int components, double* values, const std::uint8_t* fixed, const GraphFlowOptions& options,
  const ProgressCallback& progress = {}, const Partition* split = nullptr);

/// A voxel grid: Width x Height x Depth samples (x fastest, then y),
/// spacing in physical units.
struct VoxelGrid
{
  std::int64_t Width = 0;
  std::int64_t Height = 0;
  std::int64_t Depth = 0;
  double SpacingX = 1.0;
  double SpacingY = 1.0;
  double SpacingZ = 1.0;
};

/// Runs the 3-manifold flow (section 2.8.2) on `components` (1 to 6)
/// interleaved values per voxel of a 3D image, in place: the grid split
/// into Kuhn tetrahedra (six per cell, as GridTetrahedra), evaluated per
/// step without an explicit mesh - the same discretization as
/// RunTetrahedralGraphFlow on GridTetrahedra, at a fraction of the time and
/// memory.  Every dimension must be at least 2 (else nothing is done).
GraphFlowResult RunVolumeGraphFlow(const VoxelGrid& grid, int components, double* values,
  const std::uint8_t* fixed, const GraphFlowOptions& options, const ProgressCallback& progress = {},
  const GridPiece* piece = nullptr);

class TetrahedralMesh;

/// Runs the flow on point data over a tetrahedral mesh (section 2.8.2: the
/// 3-manifold (x, y, z, alpha f) in R^(3+n), the volume gradient of appendix
/// A.4, the indicator V_base / V_graph): points are 3 doubles per vertex,
/// `components` (1 to 6) interleaved values per vertex, in place.  Vertices
/// that are fixed or in no tetrahedron with volume keep their values.
/// voxels (optional): the mesh is the Kuhn split of these voxel cells (8
/// point ids each, VTK_VOXEL corner order, as vtkBeltramiGraphFlow splits
/// them) - then the cells run on the dense 3D kernel's arithmetic (single
/// precision tetrahedra, a 14-neighbour stencil), the same flow several
/// times faster, wherever they form one lattice.  split (optional,
/// collective): the mesh split over processes, as for RunSurfaceGraphFlow
/// (each process its rows and the tetrahedra around them; then voxels are
/// not used: the general tetrahedra run).
GraphFlowResult RunTetrahedralGraphFlow(const TetrahedralMesh& mesh, const double* points,
  int components, double* values, const std::uint8_t* fixed, const GraphFlowOptions& options,
  const ProgressCallback& progress = {}, const std::vector<Index>* voxels = nullptr,
  const Partition* split = nullptr);

} // namespace beltrami
