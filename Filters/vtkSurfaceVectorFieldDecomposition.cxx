#include "vtkSurfaceVectorFieldDecomposition.h"
#include "vtkBeltramiSettings.h"

#include "vtkBeltramiSurface.h"

#include "Mesh/VectorFields.h"
#include "Solvers/Partition.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>
#include <vector>

BELTRAMI_SAME_ENUM(vtkSurfaceVectorFieldDecomposition::TANGENT_DIVERGENCE_FREE,
  beltrami::VectorFieldBoundary::TangentDivergenceFree);
BELTRAMI_SAME_ENUM(vtkSurfaceVectorFieldDecomposition::NORMAL_CURL_FREE, beltrami::VectorFieldBoundary::NormalCurlFree);

vtkStandardNewMacro(vtkSurfaceVectorFieldDecomposition);

struct vtkSurfaceVectorFieldDecomposition::vtkPrepared
{
  std::uint64_t Key = 0;    ///< of the last run's surface and settings
  std::vector<double> Points; ///< the prepared decomposition's own copies
  std::unique_ptr<beltrami::MeshTopology> Topology;
  std::unique_ptr<beltrami::VectorFieldDecomposer> Decomposer;
};

vtkSurfaceVectorFieldDecomposition::~vtkSurfaceVectorFieldDecomposition() = default;

vtkSurfaceVectorFieldDecomposition::vtkSurfaceVectorFieldDecomposition()
  : Prepared(std::make_unique<vtkPrepared>())
{
  beltrami::VectorFieldOptions defaults;
  this->CopySettings(defaults, vtkBeltramiCopy::FromCore);
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::VECTORS);
}

void vtkSurfaceVectorFieldDecomposition::CopySettings(beltrami::VectorFieldOptions& o, vtkBeltramiCopy direction)
{
  BeltramiCopySetting(this->BoundaryCondition, o.Boundary, direction);
  BeltramiCopySetting(this->NumberOfThreads, o.NumberOfThreads, direction);
}

int vtkSurfaceVectorFieldDecomposition::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The two Poisson solves couple the whole surface: data split over the
  // ranks of a distributed run are solved over the ranks, each rank holding
  // its piece and the rings around it (pieces with ghost cells are gathered
  // on rank 0).
  // Where the pieces turn out not to hold the stars of their points (points
  // of one coordinate that the pieces join but a piece keeps apart, at
  // non-manifold points: every rank finds it alike), the surface is
  // gathered on rank 0 instead.
  const auto compute = [this](vtkBeltramiSurface& surface) { return this->Compute(surface); };
  this->PiecesDisagree = false;
  const int done = vtkBeltramiSurface::Execute(
    this, inputVector, outputVector, this->NumberOfThreads, vtkBeltramiSurface::Needs::Distributed, compute);
  if (!this->PiecesDisagree)
  {
    return done;
  }
  return vtkBeltramiSurface::Execute(
    this, inputVector, outputVector, this->NumberOfThreads, vtkBeltramiSurface::Needs::WholeSurface, compute);
}

namespace
{

constexpr double NaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::uint8_t Defects = beltrami::VertexNonManifold | beltrami::VertexInconsistent |
  beltrami::VertexDuplicateFace;

/// The triangles of `topology` (ids into it) kept for the decomposition:
/// none with a vertex at a non-manifold point, an inconsistent orientation
/// or a duplicate triangle, repeated until the kept ones have none.  Split
/// over ranks (`split`), the defects are those found at the points of a
/// piece (its first `pieceRows` rows, whose whole stars it holds), made known
/// to every rank that holds the point, so that all leave out the same
/// triangles.  Null when all are kept.
std::unique_ptr<beltrami::MeshTopology> ManifoldPart(const beltrami::MeshTopology& topo,
  std::vector<beltrami::Index>& kept, int threads, const beltrami::Partition* split, beltrami::Index pieceRows)
{
  kept.resize(topo.NumberOfTriangles());
  std::iota(kept.begin(), kept.end(), 0);
  std::unique_ptr<beltrami::MeshTopology> part;
  const beltrami::MeshTopology* current = &topo;
  const beltrami::Index nv = topo.NumberOfVertices();
  for (;;)
  {
    std::vector<double> bad(nv, 0.0);
    double count = 0.0;
    for (beltrami::Index v = 0; v < nv; ++v)
    {
      bad[v] = (current->VertexFlags(v) & Defects) && (!split || v < pieceRows) ? 1.0 : 0.0;
    }
    if (split)
    {
      split->SumToOwners(bad.data(), 1);
      split->UpdateGhosts(bad.data(), 1);
    }
    for (beltrami::Index v = 0; v < nv; ++v)
    {
      count += bad[v] > 0.0 && (!split || split->IsOwned(v));
    }
    if ((split ? split->Sum(count) : count) == 0.0)
    {
      return part;
    }
    std::vector<beltrami::Index> next;
    beltrami::IndexArray triangles;
    const beltrami::IndexArray& list = current->TriangleList();
    for (beltrami::Index t = 0; t < current->NumberOfTriangles(); ++t)
    {
      const beltrami::Index* v = &list[3 * static_cast<std::int64_t>(t)];
      if (bad[v[0]] == 0.0 && bad[v[1]] == 0.0 && bad[v[2]] == 0.0)
      {
        next.push_back(kept[t]);
        triangles.insert(triangles.end(), v, v + 3);
      }
    }
    kept.swap(next);
    part = std::make_unique<beltrami::MeshTopology>(nv, std::move(triangles), threads);
    current = part.get();
  }
}

/// A 64-bit hash of the surface (its points and triangles) and the settings.
std::uint64_t SurfaceKey(const beltrami::MeshTopology& topo, const double* points, const beltrami::VectorFieldOptions& o)
{
  std::uint64_t h = 1469598103934665603ull;
  const auto mix = [&h](std::uint64_t word) {
    h ^= word + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  };
  mix(static_cast<std::uint64_t>(topo.NumberOfVertices()));
  mix(static_cast<std::uint64_t>(o.Boundary));
  for (std::int64_t k = 0; k < 3 * static_cast<std::int64_t>(topo.NumberOfVertices()); ++k)
  {
    std::uint64_t word;
    std::memcpy(&word, points + k, sizeof word);
    mix(word);
  }
  for (const beltrami::Index v : topo.TriangleList())
  {
    mix(static_cast<std::uint64_t>(v));
  }
  return h;
}

void AddScalar(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}

vtkDoubleArray* AddArray(vtkDataSetAttributes* data, const char* name, int components, vtkIdType tuples)
{
  const vtkSmartPointer<vtkDataArray> array = vtkBeltramiSurface::NewArray(VTK_DOUBLE, name, components, tuples);
  data->AddArray(array); // (holds it)
  return vtkDoubleArray::SafeDownCast(array);
}

} // namespace

void vtkSurfaceVectorFieldDecomposition::AddArrays(vtkBeltramiSurface& surface, const beltrami::MeshTopology& topo,
  const std::vector<vtkIdType>& cellOf, const beltrami::VectorFieldDecomposition& r, bool onPoints)
{
  vtkPolyData* output = surface.Output();
  const vtkIdType np = output->GetNumberOfPoints();
  const std::vector<beltrami::Index>& merged = surface.MergedPoints();
  const auto topologyPoint = [&merged](vtkIdType i) { return merged.empty() ? i : merged[i]; };
  const std::vector<double> stream = beltrami::PointValuesFromEdges(topo, r.StreamFunction.data());
  struct Output
  {
    const char* Name;
    const std::vector<double>& Values; ///< per vertex (Point) or per triangle
    int Components;
    bool Point;
  };
  const Output outputs[] = { { "Potential", r.Potential, 1, true }, { "StreamFunction", stream, 1, true },
    { "Divergence", r.Divergence, 1, true }, { "Curl", r.Curl, 1, true },
    { "NormalComponent", r.Normal, 1, false }, { "TangentField", r.Tangent, 3, false },
    { "CurlFreePart", r.CurlFree, 3, false }, { "DivergenceFreePart", r.DivergenceFree, 3, false },
    { "HarmonicPart", r.Harmonic, 3, false } };
  // Cell values: the area-weighted mean of the cell's triangles, summed in
  // their order (the kept triangles of each cell: `members` from `first`).
  const vtkIdType nc = output->GetNumberOfCells();
  const int threads = this->NumberOfThreads;
  std::vector<double> weight(cellOf.size());
  std::vector<vtkIdType> first(onPoints ? 0 : nc + 1, 0), members;
  for (std::size_t k = 0; k < cellOf.size(); ++k)
  {
    weight[k] = r.Areas[k] > 0.0 ? r.Areas[k] : 1e-300; // a lone zero-area triangle keeps its 0
    if (!onPoints && cellOf[k] >= 0)
    {
      ++first[cellOf[k] + 1];
    }
  }
  std::partial_sum(first.begin(), first.end(), first.begin());
  members.resize(onPoints ? 0 : static_cast<std::size_t>(first.back()));
  std::vector<vtkIdType> next(first.begin(), first.end() - (onPoints ? 0 : 1));
  for (std::size_t k = 0; !onPoints && k < cellOf.size(); ++k)
  {
    if (cellOf[k] >= 0)
    {
      members[next[cellOf[k]]++] = static_cast<vtkIdType>(k);
    }
  }
  for (const Output& o : outputs)
  {
    const int nk = o.Components;
    if (o.Point || onPoints)
    {
      const std::vector<double> values = o.Point
        ? std::vector<double>()
        : beltrami::PointValuesFromTriangles(topo, r.Areas, o.Values.data(), nk);
      const std::vector<double>& perPoint = o.Point ? o.Values : values;
      double* a = AddArray(output->GetPointData(), o.Name, nk, np)->GetPointer(0);
      beltrami::ParallelFor(np, threads, [&](std::int64_t begin, std::int64_t end) {
        for (vtkIdType i = begin; i < end; ++i)
        {
          const beltrami::Index v = static_cast<beltrami::Index>(topologyPoint(i));
          for (int d = 0; d < nk; ++d)
          {
            a[nk * i + d] = topo.Valence(v) > 0 ? perPoint[nk * v + d] : NaN;
          }
        }
      });
      continue;
    }
    double* a = AddArray(output->GetCellData(), o.Name, nk, nc)->GetPointer(0);
    beltrami::ParallelFor(nc, threads, [&](std::int64_t begin, std::int64_t end) {
      for (vtkIdType c = begin; c < end; ++c)
      {
        double area = 0.0, sum[3] = { 0.0, 0.0, 0.0 };
        for (vtkIdType m = first[c]; m < first[c + 1]; ++m)
        {
          const vtkIdType k = members[m];
          area += weight[k];
          for (int d = 0; d < nk; ++d)
          {
            sum[d] += weight[k] * o.Values[nk * k + d];
          }
        }
        for (int d = 0; d < nk; ++d)
        {
          a[nk * c + d] = area > 0.0 ? sum[d] / area : NaN;
        }
      }
    });
  }
  (onPoints ? static_cast<vtkDataSetAttributes*>(output->GetPointData()) : output->GetCellData())
    ->SetActiveVectors("TangentField");
  output->GetPointData()->SetActiveScalars("Potential");
}

bool vtkSurfaceVectorFieldDecomposition::Decompose(const beltrami::MeshTopology& topo, const double* points,
  const double* vectors, const beltrami::VectorFieldOptions& options, beltrami::VectorFieldDecomposition& r)
{
  // A surface seen twice in a row is prepared once and kept (the
  // factorizations); a single run keeps nothing.
  const std::uint64_t key = SurfaceKey(topo, points, options);
  vtkPrepared& prepared = *this->Prepared;
  const bool reused = key == prepared.Key && prepared.Decomposer;
  if (key == prepared.Key && !prepared.Decomposer)
  {
    prepared.Points.assign(points, points + 3 * static_cast<std::size_t>(topo.NumberOfVertices()));
    prepared.Topology = std::make_unique<beltrami::MeshTopology>(
      topo.NumberOfVertices(), beltrami::IndexArray(topo.TriangleList()), this->NumberOfThreads);
    beltrami::VectorFieldOptions many = options;
    many.ManyFields = true;
    prepared.Decomposer =
      std::make_unique<beltrami::VectorFieldDecomposer>(*prepared.Topology, prepared.Points.data(), many);
  }
  else if (key != prepared.Key)
  {
    prepared = vtkPrepared();
    prepared.Key = key;
  }
  if (prepared.Decomposer)
  {
    prepared.Decomposer->Decompose(vectors, r);
  }
  else
  {
    beltrami::DecomposeVectorField(topo, points, vectors, options, r);
  }
  return reused;
}

bool vtkSurfaceVectorFieldDecomposition::Compute(vtkBeltramiSurface& surface)
{
  vtkPolyData* input = surface.Input();
  const beltrami::Partition* split = surface.Split(); // a distributed run: every rank runs, an empty piece's too
  const bool empty = split && input->GetNumberOfPoints() == 0;
  int association = -1;
  vtkDataArray* array = this->GetInputArrayToProcess(0, input, association);
  const bool selected = array && array->GetNumberOfComponents() == 3 &&
    (association == vtkDataObject::FIELD_ASSOCIATION_POINTS || association == vtkDataObject::FIELD_ASSOCIATION_CELLS);
  if (!selected && !empty)
  {
    vtkErrorMacro("Select a point or cell array of 3 components, the vector field to decompose"
      << (array ? " (the selected one has " + std::to_string(array->GetNumberOfComponents()) + ")" : std::string())
      << ": SetInputArrayToProcess(0, 0, 0, association, name), or give the points active vectors.");
  }
  if (!surface.AllAgree(selected || empty))
  {
    return false;
  }
  const bool onPoints = association == vtkDataObject::FIELD_ASSOCIATION_POINTS;
  const bool reports = !split || split->Rank() == 0; // (the warnings about the whole surface)
  const beltrami::MeshTopology& whole = surface.Topology();
  const double triangles = static_cast<double>(whole.NumberOfTriangles());
  if ((split ? split->Sum(triangles) : triangles) == 0.0)
  {
    if (reports)
    {
      vtkWarningMacro("Input has no polygons or triangle strips: there is no field to decompose.");
    }
    return true;
  }
  const int threads = this->NumberOfThreads;
  std::vector<beltrami::Index> kept;
  const std::unique_ptr<beltrami::MeshTopology> part =
    ManifoldPart(whole, kept, threads, split, static_cast<beltrami::Index>(surface.NumberOfInputPoints()));
  const beltrami::MeshTopology& topo = part ? *part : whole;
  // Kept triangles of this piece (a split run's topology has the rings of
  // the pieces around it too: their cells -1).
  std::vector<vtkIdType> cellOf(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k)
  {
    cellOf[k] = surface.TriangleCell(whole.OriginalTriangleIds()[kept[k]]);
  }
  const auto ofPiece = [](vtkIdType cell) { return cell >= 0; };
  std::vector<vtkIdType> cells(whole.NumberOfTriangles());
  for (beltrami::Index t = 0; t < whole.NumberOfTriangles(); ++t)
  {
    cells[t] = surface.TriangleCell(whole.OriginalTriangleIds()[t]);
  }
  double excluded = static_cast<double>(std::count_if(cells.begin(), cells.end(), ofPiece) -
    std::count_if(cellOf.begin(), cellOf.end(), ofPiece));
  excluded = split ? split->Sum(excluded) : excluded;
  if (surface.NumberOfInvalidCells())
  {
    vtkWarningMacro(<< surface.NumberOfInvalidCells() << " cells with point ids out of range are left out.");
  }
  if (part && reports)
  {
    vtkWarningMacro(<< (split ? std::string("Non-manifold points, inconsistent orientation or duplicate triangles")
                              : surface.TopologyWarning())
                    << ": the " << excluded << " triangles at those points are left out (their parts are NaN).");
  }
  // The field per kept triangle.
  std::vector<double> pointStorage, vectors(3 * kept.size(), 0.0);
  const double* points = surface.PointsAsDouble(pointStorage);
  const beltrami::IndexArray& list = whole.TriangleList();
  std::atomic<vtkIdType> nonFinite{ 0 };
  beltrami::ParallelFor(static_cast<std::int64_t>(kept.size()), threads, [&](std::int64_t begin, std::int64_t end) {
    vtkIdType bad = 0;
    for (std::int64_t k = begin; k < end; ++k)
    {
      for (int d = 0; d < 3 && cellOf[k] >= 0; ++d)
      {
        double value = 0.0;
        if (onPoints)
        {
          for (int c = 0; c < 3; ++c)
          {
            value += array->GetComponent(list[3 * static_cast<std::int64_t>(kept[k]) + c], d) / 3.0;
          }
        }
        else
        {
          value = array->GetComponent(cellOf[k], d);
        }
        vectors[3 * k + d] = value;
      }
      const double* v = &vectors[3 * k];
      bad += std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]) ? 0 : 1;
    }
    nonFinite += bad;
  });
  if (nonFinite > 0)
  {
    vtkWarningMacro(<< nonFinite << " triangles have NaN or infinite vectors" << (onPoints ? " at a corner" : "")
                    << ": their field is left out (parts 0).");
  }
  beltrami::VectorFieldOptions options;
  this->CopySettings(options, vtkBeltramiCopy::ToCore);
  beltrami::VectorFieldDecomposition r;
  bool reused = false;
  this->UpdateProgress(0.0);
  try
  {
    if (split)
    {
      // The rings' triangles get the vectors of the pieces they belong to:
      // from there to the triangle's owner, and on to every rank holding
      // it.  (OfItems throws on every rank alike.)
      const std::unique_ptr<beltrami::Partition> shared =
        beltrami::Partition::OfItems(*split, topo.NumberOfTriangles(), 3, topo.TriangleList().data());
      shared->SumToOwners(vectors.data(), 3);
      shared->UpdateGhosts(vectors.data(), 3);
      *this->Prepared = vtkPrepared(); // (a split run keeps nothing)
      beltrami::DecomposeVectorField(topo, points, vectors.data(), options, *split, r);
    }
    else
    {
      reused = this->Decompose(topo, points, vectors.data(), options, r);
    }
  }
  catch (const beltrami::InconsistentOwnership&)
  {
    if (reports)
    {
      vtkWarningMacro("The pieces do not hold the whole neighbourhood of every point (coincident points kept "
                      "apart within a piece, at non-manifold points): the surface is gathered on rank 0 and "
                      "decomposed there.");
    }
    this->PiecesDisagree = true;
    return false;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro("The decomposition failed: " << e.what());
    return false;
  }
  this->UpdateProgress(1.0);
  if (!r.Converged && reports)
  {
    // The parts of a decomposition are orthogonal: their energies sum to the
    // field's.  Far from that the parts are not approximate but wrong (a
    // sphere with 1% of its triangles flattened beside folds: 1e13 times).
    const double sum = r.Energy[1] + r.Energy[2] + r.Energy[3];
    const double ratio = r.Energy[0] > 0.0 ? sum / r.Energy[0] : 1.0;
    std::ostringstream said;
    said << "The Poisson solves did not reach their tolerance (" << r.Iterations << " iterations, relative residual "
         << r.Residual << "): ";
    if (std::abs(ratio - 1.0) > 0.01 || !std::isfinite(ratio))
    {
      said << "the parts are wrong: their energies sum to " << ratio
           << " times the field's. Triangles of next to no area beside folded ones make the solves "
              "ill-conditioned; repair or smooth the surface first.";
    }
    else
    {
      said << "the parts are approximate.";
    }
    vtkWarningMacro(<< said.str());
  }
  if (r.DegenerateTriangles && reports)
  {
    vtkWarningMacro(<< r.DegenerateTriangles
                    << " triangles have zero area or NaN coordinates: their field is left out (parts 0).");
  }
  const auto infinite = [](double x) { return std::isinf(x); };
  if (std::any_of(r.Potential.begin(), r.Potential.end(), infinite) || std::any_of(r.Energy, r.Energy + 4, infinite))
  {
    vtkWarningMacro("The potentials or energies exceed the range of doubles (the vectors times the coordinates, or "
                    "their squares, beyond 1e308): those values are infinite; the parts are not affected.");
  }

  this->AddArrays(surface, topo, cellOf, r, onPoints);
  vtkFieldData* fd = surface.Output()->GetFieldData();
  AddScalar(fd, "TangentEnergy", r.Energy[0]);
  AddScalar(fd, "CurlFreeEnergy", r.Energy[1]);
  AddScalar(fd, "DivergenceFreeEnergy", r.Energy[2]);
  AddScalar(fd, "HarmonicEnergy", r.Energy[3]);
  AddScalar(fd, "CurlFreeDivergenceFreeInnerProduct", r.InnerProducts[0]);
  AddScalar(fd, "CurlFreeHarmonicInnerProduct", r.InnerProducts[1]);
  AddScalar(fd, "DivergenceFreeHarmonicInnerProduct", r.InnerProducts[2]);
  AddScalar(fd, "ExcludedTriangles", excluded);
  AddScalar(fd, "SolverIterations", r.Iterations);
  AddScalar(fd, "SolverResidual", r.Residual);
  AddScalar(fd, "PreparedSystemsReused", reused ? 1.0 : 0.0);
  return true;
}

void vtkSurfaceVectorFieldDecomposition::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "BoundaryCondition: " << this->BoundaryCondition << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
