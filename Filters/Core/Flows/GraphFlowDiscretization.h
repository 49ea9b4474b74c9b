// Beltrami core, private to Flows/: what the discretizations of the graph
// flows (PixelGridFlow, VoxelGridFlow, MeshGraphFlow) share with the time
// integrator (GraphFlowIntegrator): the discretization interface, the
// option checks, the per-component-count dispatch and the scratch buffers.
#pragma once

#include "Flows/GraphFlow.h"
#include "Solvers/Partition.h"
#include "Support/LargeBuffer.h"
#include "Support/Vectorization.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <type_traits>
#include <vector>

namespace beltrami
{
struct GraphLaplacian;
}

namespace beltrami::detail
{

/// Edge indicators below this are clamped (cliffs): bounds the speed-up of
/// gamma < 1 flows at E^(gamma - 1) <= 1e6.
constexpr double MinimumIndicator = 1e-3;

/// The constant c of the automatic contrast scale c h / sigma, calibrated
/// with the least-risk stop: images and meshes, and voxel grids.
constexpr double SurfaceAutomaticContrast = 1.5;
constexpr double VolumeAutomaticContrast = 1.0;

/// A discretization of the graph surface: the symmetric stiffness K (with
/// (K u)_i = sum_j c_ij (u_i - u_j)), the lumped mass a_i and the speed
/// s_i = E_i^(gamma - 1), so that the flow is du_i/dt = -s_i (K u)_i / a_i.
class FlowDiscretization
{
public:
  virtual ~FlowDiscretization() = default;

  Index Size = 0;
  int Components = 1;
  LargeVector<std::uint8_t> Fixed; ///< non-zero: value kept
  /// Set before the first Update: the semi-implicit solver needs the operator
  /// (Mass, Speed, Diagonal, KU and Apply); the explicit one only Velocity.
  bool StoreOperator = true;
  /// The time step of GraphFlowOptions::TimeStep = 0 (below the explicit
  /// stability limit, which scales with the square of the spacing).
  double AutomaticTimeStep = 0.1;
  /// The length of the base the automatic contrast scale is relative to:
  /// the geometric mean of the spacing (images), the mesh's length unit.
  double LengthScale = 1.0;
  /// The automatic contrast scale is AutomaticContrast * LengthScale / sigma
  /// (calibrated with the least-risk stop: 1.5 on images, 1.0 on volumes).
  double AutomaticContrast = SurfaceAutomaticContrast;
  // Filled by Update(u) (Velocity: allocated with the stored operator, else
  // by the discretization that writes it):
  LargeVector<double> Velocity; ///< s_i (K u)_i / a_i, zero where fixed: du/dt = -Velocity
  LargeVector<double> Mass, Speed, Diagonal, KU; ///< a_i, s_i, sum_j c_ij, K u (with ghosts)
  double Area = 0.0;    ///< area of the graph surface
  double MaxRate = 0.0; ///< max over free vertices of s_i sum_j max(c_ij, 0) / a_i

  /// Weights, masses and speeds at state u (scaled data, Components per vertex).
  virtual void Update(const double* u) = 0;
  /// Explicit steps fused with the evaluation (optional, FusesSteps()): the
  /// figures of state u (Area, MaxRate) and, unless next is null, the step
  /// next = u - dt Velocity(u), in one pass and without filling Velocity.
  virtual bool FusesSteps() const { return false; }
  virtual void FusedStep(const double* /*u*/, double /*dt*/, double* /*next*/) {}
  /// A sum over the values of a fused step's result, taken in the same
  /// pass (the risk estimate's terms, without a pass of their own): where
  /// the discretization writes the step row by row in the values' order
  /// (SumsRows()), a FusedStep with a next state and RowSum set calls
  /// RowSum(first, count, next + first) for each row of `count` values
  /// from value `first` and leaves the rows' sum, in row order, in StepSum
  /// (a split grid: for the runs of samples it owns in each row).
  using RowSumFunction = std::function<double(std::int64_t first, std::int64_t count, const double* next)>;
  virtual bool SumsRows() const { return false; }
  RowSumFunction RowSum;
  double StepSum = 0.0;
  /// y = K x; ghosts: include the values the boundary rule derives from x
  /// outside the domain (images; false: those neighbours count as zero).
  virtual void Apply(const double* x, double* y, bool ghosts) = 0;
  /// K as an explicit graph Laplacian, where it is one (meshes): the
  /// semi-implicit step then uses the faster graph solver.
  virtual const GraphLaplacian* Graph() const { return nullptr; }
  /// The standard deviation of additive Gaussian noise in `values` (data
  /// units, Components per vertex) estimated from them alone
  /// (Flows/NoiseEstimation); 0 where the domain is too small.
  virtual double EstimateNoise(const double* values) const = 0;
  /// The signs b = +-1 of the risk estimate's probe, one per value (Size x
  /// Components): a fixed pseudo-random sequence (runs are reproducible);
  /// into b those of the values [begin, end) (a probe window's).
  virtual void ProbeSigns(std::size_t begin, std::size_t end, UninitializedVector<double>& b) const;

  /// Meshes split over processes (collective runs): the rows this process
  /// counts in sums and maxima are its own (Split->IsOwned), and the
  /// integrator refreshes the ghost rows after each step.  Null: serial.
  const Partition* Split = nullptr;
  bool Counts(Index i) const { return !Split || Split->IsOwned(i); }

protected:
  double Gamma = 1.0;
  int Threads = 0;

  double SpeedOf(double indicator) const
  {
    if (Gamma == 1.0)
    {
      return 1.0;
    }
    const double e = std::min(1.0, std::max(MinimumIndicator, indicator));
    return Gamma == 0.0 ? 1.0 / e : std::pow(e, Gamma - 1.0);
  }

  /// Sets the sizes and settings every discretization has and allocates
  /// the base's per-sample arrays.
  void Allocate(Index size, int components, double gamma, int threads, bool storeOperator = true)
  {
    Size = size;
    Components = components;
    Gamma = gamma;
    Threads = threads;
    StoreOperator = storeOperator;
    if (StoreOperator)
    {
      Velocity.assign(static_cast<std::size_t>(Size) * Components, 0.0);
      Mass.assign(Size, 0.0);
      Speed.assign(Size, 1.0);
      Diagonal.assign(Size, 0.0);
      KU.assign(static_cast<std::size_t>(Size) * Components, 0.0);
    }
  }
};

/// The options and the number of components (1 to `maximum`) of `what`:
/// an error sentence, empty if they are usable.
std::string CheckOptions(const GraphFlowOptions& o, int components, int maximum, const std::string& what);

/// Makes a discretization of the data's domain (a second one for the
/// risk estimate's probe run).
using DiscretizationFactory = std::function<std::unique_ptr<FlowDiscretization>()>;

/// Optional, for large grids with explicit steps: the risk estimate's probe
/// runs on a window of the data (a band of whole rows or planes, so a
/// contiguous range of vertices) instead of all of it, and the divergence
/// is counted on the window's inner part against the main run there (a
/// margin away from the window's own border, which the flow's few voxels
/// of reach barely cross), scaled to the whole.
struct ProbeWindow
{
  DiscretizationFactory Make;         ///< the window's discretization (empty: no window)
  Index Begin = 0, End = 0;           ///< vertices of the window
  Index InnerBegin = 0, InnerEnd = 0; ///< vertices whose divergence counts
};

/// The window of a grid of `layers` layers (rows, planes) of `layerSize`
/// vertices of `components` values for `o`: an inner band of 1/`fraction`
/// of the layers (at least 16) and margins, or none (grids of at most 2^21
/// values, other stops, semi-implicit steps, a noise space); `make(first,
/// count)` makes the discretization of `count` layers from layer `first`.
ProbeWindow GridProbeWindow(Index layers, Index layerSize, int components, Index fraction, const GraphFlowOptions& o,
  const std::function<std::unique_ptr<FlowDiscretization>(Index first, Index count)>& make);

/// The probe's signs of a mesh's values [begin, end) (of Size x Components): a hash of the
/// component and of the point's position in units of lengthScale, to 1/1024
/// of it, so that a point gets the same signs wherever it lies in the
/// numbering (any split over processes) and at any scale.
void PositionProbeSigns(int components, const double* points, double lengthScale, std::size_t begin, std::size_t end,
  UninitializedVector<double>& b);

/// The samples a piece of a split grid owns (Split->IsOwned), row by row:
/// per row of `width` samples its runs of owned samples [begin, end)
/// (usually one: pieces are boxes), so that the figures and sums of a
/// row's owned samples are loops over ranges.
class OwnedRuns
{
public:
  OwnedRuns() = default;
  OwnedRuns(const Partition& split, std::int64_t rows, std::int64_t width)
  {
    Offsets.assign(1, 0);
    for (std::int64_t r = 0; r < rows; ++r)
    {
      for (std::int64_t x = 0; x < width; ++x)
      {
        const bool owned = split.IsOwned(static_cast<Index>(r * width + x));
        const bool open = Bounds.size() > 2 * static_cast<std::size_t>(Offsets.back()) &&
          Bounds.back() == x; // the last run of this row ends here
        if (owned && open)
        {
          ++Bounds.back();
        }
        else if (owned)
        {
          Bounds.push_back(x);
          Bounds.push_back(x + 1);
        }
      }
      Offsets.push_back(static_cast<std::int64_t>(Bounds.size() / 2));
    }
  }
  /// f(begin, end) for each run of row r.
  template <typename F>
  void ForEach(std::int64_t r, F&& f) const
  {
    for (std::int64_t k = Offsets[r]; k < Offsets[r + 1]; ++k)
    {
      f(Bounds[2 * k], Bounds[2 * k + 1]);
    }
  }

private:
  std::vector<std::int64_t> Offsets; // per row: its runs [Offsets[r], Offsets[r + 1])
  std::vector<std::int64_t> Bounds;  // per run: begin, end
};

/// The probe's signs of a piece of a split grid of w x h x d samples
/// (GridPiece): those of its values in the whole grid's numbering
/// (FlowDiscretization::ProbeSigns of the whole grid), so that every
/// layout probes with the serial signs.
void GridPieceProbeSigns(const FlowDiscretization& disc, const GridPiece& piece, std::int64_t w, std::int64_t h,
  std::int64_t d, UninitializedVector<double>& b);

/// The discretization of the flow on voxel cells (8 point ids per cell in
/// VTK_VOXEL order: corner bit a = a step along axis a) of one lattice, as
/// the sparse active voxels of an OpenVDB grid: the dense 3D kernel's
/// arithmetic (the six Kuhn tetrahedra of each cell in single precision,
/// 7 weights per point to its neighbours up the axes) on the cells present,
/// so the flow of the Kuhn tetrahedra of those cells, without a mesh's
/// sparse matrix.  points: 3 per point (the flow's units); base: the Kuhn
/// mesh's graph (the noise estimate's neighbours); storeOperator: for
/// semi-implicit steps (else explicit steps are fused).  Null where the
/// cells are not axis-aligned boxes of one spacing sharing their corners
/// (then the mesh's own discretization runs).
std::unique_ptr<FlowDiscretization> MakeVoxelCellDiscretization(Index size, const double* points, int components,
  const std::vector<Index>& corners, const std::uint8_t* fixed, const std::int64_t* baseOffsets,
  const Index* baseNeighbors, double gamma, int threads, bool storeOperator);

/// The time loop shared by images, volumes and meshes (section 3.8.5).
GraphFlowResult Integrate(const DiscretizationFactory& make, double* values, const GraphFlowOptions& o,
  const ProgressCallback& progress, const ProbeWindow& window = {});

/// Buffers lent to the threads of a parallel loop and kept for the next loop
/// (no allocation, zeroing or page faults per step).
class ScratchPool
{
public:
  std::vector<double> Take(std::size_t size)
  {
    std::vector<double> buffer;
    {
      std::lock_guard<std::mutex> lock(Mutex);
      if (!Free.empty())
      {
        buffer.swap(Free.back());
        Free.pop_back();
      }
    }
    if (buffer.size() < size)
    {
      buffer.resize(size);
    }
    return buffer;
  }
  void Give(std::vector<double>&& buffer)
  {
    std::lock_guard<std::mutex> lock(Mutex);
    Free.push_back(std::move(buffer));
  }

private:
  std::mutex Mutex;
  std::vector<std::vector<double>> Free;
};

/// A buffer of the pool for one scope.
class ScratchLease
{
public:
  ScratchLease(ScratchPool& pool, std::size_t size)
    : Pool(pool)
    , Buffer(pool.Take(size))
  {
  }
  ~ScratchLease() { Pool.Give(std::move(Buffer)); }
  ScratchLease(const ScratchLease&) = delete;
  ScratchLease& operator=(const ScratchLease&) = delete;
  double* data() { return Buffer.data(); }

private:
  ScratchPool& Pool;
  std::vector<double> Buffer;
};

} // namespace beltrami::detail
