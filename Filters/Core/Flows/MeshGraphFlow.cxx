#include "Flows/GraphFlowDiscretization.h"
#include "Flows/NoiseEstimation.h"

#include "Mesh/Laplacian.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/Tetrahedra.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace beltrami
{

namespace
{

using namespace detail;

// ---------------------------------------------------------------------------
// Meshes: the data as extra coordinates of the mesh, (x, y, z, alpha f) in
// R^(3+n), and the Laplacian of that embedding from the shared assemblers:
// triangle surfaces (the cotangent formula) and tetrahedral volumes (the
// volume gradient, appendix A.4).  The indicator is the ratio of the base
// and graph measures (mixed areas or vertex volumes: 1/W).

class MeshDiscretization final : public FlowDiscretization
{
public:
  /// Assembles the Laplacian of points with `dimension` coordinates each.
  using Assembler = std::function<void(const double* points, int dimension, GraphLaplacian& laplacian)>;

  /// massScale: the lumped mass is massScale * laplacian.Mass, so that
  /// -K u / mass is the Laplace-Beltrami operator (1/2 for the surface
  /// weights cot/4 over mixed areas; 1 for volume gradients over vertex
  /// volumes).  unusable (optional): non-zero = vertex kept (non-manifold).
  /// split: see FlowDiscretization::Split.
  MeshDiscretization(Index size, const double* points, int components, const std::uint8_t* fixed,
    const std::uint8_t* unusable, Assembler assemble, double massScale, double gamma, int threads,
    const Partition* split)
    : Assemble(std::move(assemble))
    , MassScale(massScale)
  {
    Split = split;
    Allocate(size, components, gamma, threads);
    GraphLaplacian base;
    Assemble(points, 3, base);
    BaseMeasure.assign(base.Mass.begin(), base.Mass.end());
    BaseOffsets = base.Offsets; // the mesh's graph: it outlives the run
    BaseNeighbors = base.Neighbors;
    Points = points;
    Fixed.assign(Size, 0);
    for (Index i = 0; i < Size; ++i)
    {
      Fixed[i] = (fixed && fixed[i]) || (unusable && unusable[i]) || !(BaseMeasure[i] > 0.0);
    }
    if (Split) // a ghost row is fixed where its owner's is (here its star may be partial)
    {
      Split->UpdateGhosts(Fixed);
    }
    // The base coordinates of the embedding, once; Update writes the data.
    const int dim = 3 + components;
    Embedded.resize(static_cast<std::size_t>(Size) * dim);
    for (Index i = 0; i < Size; ++i)
    {
      std::copy(points + 3 * static_cast<std::size_t>(i), points + 3 * static_cast<std::size_t>(i) + 3,
        &Embedded[static_cast<std::size_t>(i) * dim]);
    }
  }

  double EstimateNoise(const double* values) const override
  {
    return EstimateGraphNoise(
      Size, BaseOffsets, BaseNeighbors, Points, Components, values, Fixed.data(), Split);
  }

  void ProbeSigns(std::size_t begin, std::size_t end, UninitializedVector<double>& b) const override
  {
    PositionProbeSigns(Components, Points, LengthScale, begin, end, b);
  }

  void Update(const double* u) override
  {
    const int dim = 3 + Components;
    ParallelFor(Size, Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i)
      {
        std::copy(u + i * Components, u + (i + 1) * Components, &Embedded[i * dim + 3]);
      }
    });
    Assemble(Embedded.data(), dim, Laplacian);
    Positive.resize(Size);
    ParallelFor(Size, Threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i)
      {
        Mass[i] = MassScale * Laplacian.Mass[i];
        Diagonal[i] = Laplacian.Diagonal[i];
        double p = 0.0;
        for (std::int64_t k = Laplacian.Offsets[i]; k < Laplacian.Offsets[i + 1]; ++k)
        {
          p += std::max(Laplacian.Weights[k], 0.0);
        }
        Positive[i] = p;
        Speed[i] = Laplacian.Mass[i] > 0.0 ? SpeedOf(BaseMeasure[i] / Laplacian.Mass[i]) : 1.0;
        if (!(Mass[i] > 0.0) && (!Split || Split->IsOwned(static_cast<Index>(i))))
        {
          Fixed[i] = 1; // lost its measure (degenerate graph elements; a ghost row's star may be partial here)
        }
      }
    });
    Laplacian.ApplyStiffness(u, KU.data(), Components, Threads);
    // Chunk maxima (ParallelSum would add them: the step was up to Size/4096
    // times smaller than stable on large meshes).
    std::vector<double> rates = ParallelPartials(Size, 1, Threads, [&](std::int64_t b, std::int64_t e, double* acc) {
      for (std::int64_t i = b; i < e; ++i)
      {
        const double f = !Fixed[i] && Mass[i] > 0.0 ? Speed[i] / Mass[i] : 0.0;
        for (int k = 0; k < Components; ++k)
        {
          Velocity[i * Components + k] = f * KU[i * Components + k];
        }
        acc[0] = Counts(static_cast<Index>(i)) ? std::max(acc[0], f * Positive[i]) : acc[0]; // any order: the same
      }
    });
    MaxRate = rates.empty() ? 0.0 : *std::max_element(rates.begin(), rates.end());
    Area = ParallelSum(Size, 1, Threads, [&](std::int64_t b, std::int64_t e, double* acc) {
      for (std::int64_t i = b; i < e; ++i)
      {
        acc[0] += Counts(static_cast<Index>(i)) ? Laplacian.Mass[i] : 0.0;
      }
    })[0];
    if (Split)
    {
      MaxRate = Split->Max(MaxRate);
      Area = Split->Sum(Area);
    }
  }

  void Apply(const double* x, double* y, bool) override
  {
    Laplacian.ApplyStiffness(x, y, Components, Threads);
  }
  const GraphLaplacian* Graph() const override { return &Laplacian; }

private:
  Assembler Assemble;
  double MassScale;
  std::vector<double> BaseMeasure, Embedded, Positive;
  const std::int64_t* BaseOffsets = nullptr; ///< the base graph (noise estimate)
  const Index* BaseNeighbors = nullptr;
  const double* Points = nullptr; ///< base coordinates, 3 per vertex
  GraphLaplacian Laplacian;
};

/// What a mesh flow needs of its mesh: its size and dimension (2 surfaces,
/// 3 volumes), the vertices that do not move (optional), its mean edge
/// length, the assembler of its Laplacian and the mass scale (section 2.8).
struct MeshFlowInput
{
  Index Vertices = 0;
  int Dimension = 2;
  int MaximumComponents = 5;
  const std::uint8_t* Unusable = nullptr;
  std::function<double(const double* points)> MeanEdgeLength;
  MeshDiscretization::Assembler Assemble;
  double MassScale = 0.5;
  const Partition* Split = nullptr; ///< a mesh split over processes (collective)
  /// Optional: a faster discretization of the same flow for the mesh's
  /// points (in the flow's units) and settings; null where it does not
  /// apply (then the mesh's own runs).
  std::function<std::unique_ptr<FlowDiscretization>(
    const double* points, const std::uint8_t* fixed, const GraphFlowOptions& options)>
    Special;
};

/// The body of both mesh flows: the options checked, the points measured in
/// the options' length unit (divided by the mean edge length, or as they
/// are), the flow, and the area (or volume) and time of the report back in
/// the mesh's units.
GraphFlowResult RunMeshFlow(const MeshFlowInput& mesh, const double* points, int components, double* values,
  const std::uint8_t* fixed, const GraphFlowOptions& options, const ProgressCallback& progress)
{
  GraphFlowResult result;
  result.Error = CheckOptions(options, components, mesh.MaximumComponents, "point data");
  if (!result.Error.empty() || (mesh.Vertices == 0 && !mesh.Split)) // (a split run's empty piece joins in)
  {
    return result;
  }
  const double unit = options.Units == LengthUnit::MeanEdgeLength ? mesh.MeanEdgeLength(points) : 1.0;
  if (!(unit > 0.0) || !std::isfinite(unit))
  {
    result.Error = "the mean edge length of the input is " + std::to_string(unit) + ": cannot scale the mesh";
    return result;
  }
  std::vector<double> scaled(points, points + 3 * static_cast<std::size_t>(mesh.Vertices));
  bool finite = true;
  for (double& x : scaled)
  {
    x /= unit;
    finite = finite && std::isfinite(x);
  }
  if (!finite || (mesh.Split && mesh.Split->Max(finite ? 0.0 : 1.0) > 0.0))
  {
    result.Error = "the input has NaN or infinite point coordinates";
    return result;
  }
  const double length = options.Units == LengthUnit::MeanEdgeLength ? 1.0 : mesh.MeanEdgeLength(points);
  const auto make = [&]() {
    std::unique_ptr<FlowDiscretization> disc = mesh.Special ? mesh.Special(scaled.data(), fixed, options) : nullptr;
    if (!disc)
    {
      disc = std::make_unique<MeshDiscretization>(mesh.Vertices, scaled.data(), components, fixed, mesh.Unusable,
        mesh.Assemble, mesh.MassScale, options.EdgeContrast, options.NumberOfThreads, mesh.Split);
    }
    disc->LengthScale = length;
    return disc;
  };
  result = Integrate(make, values, options, progress);
  const double measure = std::pow(unit, mesh.Dimension);
  result.InitialArea *= measure;
  result.FinalArea *= measure;
  result.Time *= unit * unit;
  return result;
}

} // namespace

GraphFlowResult RunSurfaceGraphFlow(const MeshTopology& topology, const double* points,
  int components, double* values, const std::uint8_t* fixed, const GraphFlowOptions& options,
  const ProgressCallback& progress, const Partition* split)
{
  const int threads = options.NumberOfThreads;
  std::vector<std::uint8_t> unusable(topology.NumberOfVertices());
  for (Index i = 0; i < topology.NumberOfVertices(); ++i)
  {
    unusable[i] = (topology.VertexFlags(i) & ~VertexBoundary) != 0;
  }
  MeshFlowInput mesh;
  mesh.Vertices = topology.NumberOfVertices();
  mesh.Unusable = unusable.data();
  mesh.MeanEdgeLength = [&](const double* x) { return MeanEdgeLength(topology, x, split); };
  mesh.Split = split;
  mesh.Assemble = [&](const double* x, int dimension, GraphLaplacian& l) {
    AssembleSurfaceLaplacian(topology, x, dimension, LaplacianWeights::Cotangent, l, threads);
  };
  return RunMeshFlow(mesh, points, components, values, fixed, options, progress);
}

GraphFlowResult RunTetrahedralGraphFlow(const TetrahedralMesh& mesh, const double* points,
  int components, double* values, const std::uint8_t* fixed, const GraphFlowOptions& options,
  const ProgressCallback& progress, const std::vector<Index>* voxels, const Partition* split)
{
  const int threads = options.NumberOfThreads;
  MeshFlowInput volume;
  volume.Vertices = mesh.NumberOfVertices();
  volume.Dimension = 3;
  volume.MaximumComponents = 6;
  volume.Split = split;
  volume.MeanEdgeLength = [&](const double* x) { return mesh.MeanEdgeLength(x, split); };
  LargeVector<TetrahedronTerms> terms; // kept between the steps
  volume.Assemble = [&](const double* x, int dimension, GraphLaplacian& l) {
    AssembleTetrahedralLaplacian(mesh, x, dimension, l, threads, &terms);
  };
  volume.MassScale = 1.0;
  if (voxels && !split)
  {
    volume.Special = [&](const double* x, const std::uint8_t* f, const GraphFlowOptions& o) {
      return MakeVoxelCellDiscretization(mesh.NumberOfVertices(), x, components, *voxels, f,
        mesh.NeighborOffsets().data(), mesh.Neighbors().data(), o.EdgeContrast, o.NumberOfThreads,
        o.Integration == GraphFlowIntegration::SemiImplicit);
    };
  }
  return RunMeshFlow(volume, points, components, values, fixed, options, progress);
}

} // namespace beltrami
