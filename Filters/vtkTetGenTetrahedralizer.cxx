#include "vtkTetGenTetrahedralizer.h"

#include "vtkBeltramiGather.h"
#include "vtkBeltramiSurface.h"

#include "Mesh/HarmonicExtension.h"
#include "Mesh/MeshMeasures.h"
#include "Support/HelperProcess.h"
#include "Mesh/Tetrahedra.h"

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkCommunicator.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkTetGenTetrahedralizer);

namespace
{
/// TetGen's exit codes (terminatetetgen) in words.
const char* TetGenReason(int code)
{
  switch (code)
  {
    case 1: return "out of memory";
    case 2: return "an internal error of TetGen";
    case 3: return "the surface intersects itself";
    case 4: return "a very small input feature size was detected (nearly touching parts)";
    case 5: return "two very close input facets were detected";
    case 10: return "an input error";
    default: return "an unknown error";
  }
}
/// The TetGen helper next to this library (or BELTRAMI_TETGEN).
const std::string& TetGenHelperPath()
{
  static const std::string path = beltrami::HelperPathNextTo(
    reinterpret_cast<const void*>(&TetGenReason), "beltrami-tetgen", "BELTRAMI_TETGEN");
  return path;
}

/// One TetGen helper per process, kept running between runs of the filter
/// (its memory stays faulted in; never destroyed: it exits when this
/// process ends and its input closes).
beltrami::PersistentHelperProcess& TetGenHelper()
{
  static auto* helper = new beltrami::PersistentHelperProcess(TetGenHelperPath(), { "--serve" });
  return *helper;
}
/// Meshes the closed surface (points, triangles) in the TetGen helper
/// (Filters/Tools/beltrami_tetgen.cxx) with `switches`: the points
/// (the input's first) and tetrahedra of the answer, checked; a crash of
/// libtet is diagnosed by TetGen's self-intersection check.  False after
/// an error on `self`.
bool RunTetGen(vtkAlgorithm* self, const std::string& switches, vtkIdType numPoints, const double* points,
  const beltrami::IndexArray& triangles, const std::vector<beltrami::Vec3>& holes, std::vector<double>& outputPoints,
  std::vector<std::int32_t>& tets)
{
  // The request for the TetGen helper (Filters/Tools/beltrami_tetgen.cxx).
  std::vector<char> request;
  const auto put = [&request](const void* data, std::size_t n) {
    request.insert(request.end(), static_cast<const char*>(data), static_cast<const char*>(data) + n);
  };
  const std::uint32_t length = static_cast<std::uint32_t>(switches.size());
  const std::int32_t pointCount = static_cast<std::int32_t>(numPoints);
  const std::int32_t triangleCount = static_cast<std::int32_t>(triangles.size() / 3);
  request.reserve(64 + switches.size() + 24 * static_cast<std::size_t>(numPoints) + 4 * triangles.size());
  put("BTET1", 5);
  put(&length, 4);
  put(switches.data(), switches.size());
  put(&pointCount, 4);
  put(points, 3 * sizeof(double) * static_cast<std::size_t>(numPoints));
  put(&triangleCount, 4);
  put(triangles.data(), triangles.size() * sizeof(beltrami::Index));
  const std::int32_t holeCount = static_cast<std::int32_t>(holes.size());
  put(&holeCount, 4);
  for (const beltrami::Vec3& p : holes)
  {
    put(p.data(), 3 * sizeof(double));
  }

  // The answer: at most ~64 points and ~400 tetrahedra per input point even
  // with small volume bounds; more means a damaged answer.
  const double maximumBytes = 1e8 + 2e4 * static_cast<double>(numPoints);
  const auto keepGoing = [self]() { return !self->GetAbortExecute(); };
  beltrami::HelperProcessResult run;
  try
  {
    run = TetGenHelper().Request(request, maximumBytes, /*timeout=*/0.0, keepGoing);
    if (run.Signal && !run.Cancelled)
    {
      // Diagnose the crash with TetGen's self-intersection check.
      const beltrami::HelperProcessResult check = beltrami::RunHelperProcess(
        TetGenHelperPath(), { "--intersections" }, request, maximumBytes, /*timeout=*/0.0, keepGoing);
      beltrami::ByteReader answer(check.Output, "TetGen helper");
      char magic[5];
      if (!check.Signal && check.Output.size() == 13 && (answer.Take(magic, 5), answer.Get<std::int32_t>() == 0))
      {
        const std::int32_t intersecting = answer.Get<std::int32_t>();
        if (intersecting > 0)
        {
          vtkErrorWithObjectMacro(self, "The surface intersects itself: TetGen found "
            << intersecting << " intersecting triangles. The output is empty.");
          return false;
        }
      }
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorWithObjectMacro(self, << e.what() << ". The output is empty.");
    return false;
  }
  try
  {
    beltrami::ByteReader answer(run.Output, "TetGen helper");
    char magic[5];
    answer.Take(magic, 5);
    if (std::memcmp(magic, "BTET1", 5) != 0)
    {
      throw std::runtime_error("malformed answer of the TetGen helper");
    }
    const std::int32_t code = answer.Get<std::int32_t>();
    if (code != 0)
    {
      vtkErrorWithObjectMacro(self, << answer.String() << ": " << TetGenReason(code) << " (code " << code << ", switches '"
                    << switches << "'). The output is empty.");
      return false;
    }
    const std::int32_t n = answer.Get<std::int32_t>();
    if (n < numPoints || static_cast<double>(n) * 24.0 > static_cast<double>(answer.Left()))
    {
      throw std::runtime_error("malformed answer of the TetGen helper");
    }
    outputPoints.resize(3 * static_cast<std::size_t>(n));
    answer.Take(outputPoints.data(), outputPoints.size() * sizeof(double));
    const std::int32_t t = answer.Get<std::int32_t>();
    if (t <= 0 || static_cast<double>(t) * 16.0 != static_cast<double>(answer.Left()))
    {
      throw std::runtime_error("malformed answer of the TetGen helper");
    }
    tets.resize(4 * static_cast<std::size_t>(t));
    answer.Take(tets.data(), tets.size() * sizeof(std::int32_t));
    for (const std::int32_t id : tets)
    {
      if (id < 0 || id >= n)
      {
        throw std::runtime_error("the TetGen helper returned a tetrahedron with a point that does not exist");
      }
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorWithObjectMacro(self, << e.what() << ". The output is empty.");
    return false;
  }
  return true;
}

/// RunTetGen on the points of the triangles alone: the points that
/// coincident points were merged into (`merge`: vtkBeltramiSurface::
/// MergedPoints; empty: none merged) and that some triangle uses. TetGen
/// refuses coincident points and drops points outside the surface (a point
/// of a line or vertex cell on the surface, a copy of a surface point: its
/// answer then lacked input points), so the others are left out of its
/// input and come back unused at their places, the input's points first as
/// always.
bool RunTetGenOnSurfacePoints(vtkAlgorithm* self, const std::string& switches, vtkIdType numPoints,
  const double* points, const beltrami::IndexArray& triangles, const std::vector<beltrami::Index>& merge,
  const std::vector<beltrami::Vec3>& holes, std::vector<double>& outputPoints, std::vector<std::int32_t>& tets)
{
  std::vector<std::uint8_t> used(static_cast<std::size_t>(numPoints), 0);
  for (const beltrami::Index v : triangles)
  {
    used[v] = 1;
  }
  const auto keep = [&](vtkIdType p) { return used[p] && (merge.empty() || merge[p] == p); };
  vtkIdType count = 0;
  for (vtkIdType p = 0; p < numPoints; ++p)
  {
    count += keep(p) ? 1 : 0;
  }
  if (count == numPoints)
  {
    return RunTetGen(self, switches, numPoints, points, triangles, holes, outputPoints, tets);
  }
  std::vector<beltrami::Index> compact(static_cast<std::size_t>(numPoints), -1), original;
  std::vector<double> kept;
  for (vtkIdType p = 0; p < numPoints; ++p)
  {
    if (keep(p))
    {
      compact[p] = static_cast<beltrami::Index>(original.size());
      original.push_back(static_cast<beltrami::Index>(p));
      kept.insert(kept.end(), points + 3 * p, points + 3 * p + 3);
    }
  }
  beltrami::IndexArray renumbered(triangles.size());
  for (std::size_t k = 0; k < triangles.size(); ++k)
  {
    renumbered[k] = compact[triangles[k]];
  }
  std::vector<double> meshed;
  if (!RunTetGen(
        self, switches, static_cast<vtkIdType>(original.size()), kept.data(), renumbered, holes, meshed, tets))
  {
    return false;
  }
  const std::size_t added = meshed.size() - kept.size(); // TetGen's own points (3 values each)
  outputPoints.assign(points, points + 3 * numPoints);
  outputPoints.insert(outputPoints.end(), meshed.end() - static_cast<std::ptrdiff_t>(added), meshed.end());
  const auto keptCount = static_cast<std::int32_t>(original.size());
  for (std::int32_t& v : tets)
  {
    v = v < keptCount ? original[v] : static_cast<std::int32_t>(numPoints) + (v - keptCount);
  }
  return true;
}

} // namespace

std::string vtkTetGenTetrahedralizer::GetSwitches() const
{
  std::ostringstream s;
  s.precision(17);
  s << "pQz"; // a piecewise linear complex, quiet, ids from 0
  if (this->RadiusEdgeRatio > 0.0)
  {
    s << "q" << this->RadiusEdgeRatio;
    if (this->MinimumDihedralAngle > 0.0)
    {
      s << "/" << this->MinimumDihedralAngle;
    }
  }
  if (this->MaximumVolume > 0.0)
  {
    s << "a" << this->MaximumVolume;
  }
  if (this->PreserveSurface)
  {
    s << "Y";
  }
  return s.str();
}

int vtkTetGenTetrahedralizer::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

int vtkTetGenTetrahedralizer::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  // Pieces that are closed surfaces of their own are meshed where they
  // are; a surface split over the ranks (open pieces) is gathered on rank
  // 0 and meshed whole there (the other ranks' outputs stay empty).
  vtkBeltramiSurface piece; // built once: meshed from here when all pieces are closed
  bool built = false;
  const auto anyPieceOpen = [&]() {
    built = input->GetNumberOfPoints() > 0 && piece.Build(input, 1);
    int open = input->GetNumberOfPoints() > 0 && (!built || !piece.Topology().Summary().IsClosed()) ? 1 : 0;
    int anyOpen = 0;
    vtkMultiProcessController::GetGlobalController()->AllReduce(&open, &anyOpen, 1, vtkCommunicator::SUM_OP);
    return anyOpen > 0;
  };
  return vtkBeltramiGather::RunWhole(outputVector->GetInformationObject(0), input, output,
    vtkBeltramiGather::Results::OnRankZero,
    [&](vtkPointSet* in, vtkPointSet* out, int holding) {
      return this->Mesh(vtkPolyData::SafeDownCast(in), vtkUnstructuredGrid::SafeDownCast(out), holding,
        built && in == input ? &piece : nullptr);
    },
    anyPieceOpen);
}

int vtkTetGenTetrahedralizer::Mesh(
  vtkPolyData* input, vtkUnstructuredGrid* output, int holding, vtkBeltramiSurface* built)
{
  if (!input || !output)
  {
    vtkErrorMacro("Input must be vtkPolyData and output vtkUnstructuredGrid.");
    return 0;
  }
  output->Initialize(); // a defined output: empty
  const vtkIdType numPoints = input->GetNumberOfPoints();
  if (numPoints == 0)
  {
    return 1;
  }
  vtkBeltramiSurface own;
  vtkBeltramiSurface& surface = built ? *built : own;
  if (!built && !surface.Build(input, 1))
  {
    vtkErrorMacro(<< surface.Error() << " The output is empty.");
    return 0;
  }
  if (!surface.RepairWarning().empty())
  {
    vtkWarningMacro(<< surface.RepairWarning());
  }
  const beltrami::MeshTopology& topo = surface.Topology();
  const beltrami::TopologySummary& info = topo.Summary();
  if (topo.NumberOfTriangles() == 0)
  {
    vtkErrorMacro("The input has no polygons: TetGen needs a closed surface. The output is empty.");
    return 0;
  }
  if (!info.IsClosed() || !info.IsManifold())
  {
    vtkErrorMacro("TetGen needs a closed manifold surface; the input "
      << (holding > 1 ? "(one of " + std::to_string(holding) + " pieces of distributed data: run it on "
                          "the whole surface, e.g. after Merge Blocks / D3 to one process) " : std::string())
      << "has "
      << info.NumberOfBoundaryEdges << " boundary edges in " << info.NumberOfBoundaryLoops
      << " loops, " << info.NumberOfNonManifoldEdges << " non-manifold edges and "
      << info.NumberOfDuplicateTriangles << " duplicate triangles. The output is empty.");
    return 0;
  }
  std::vector<double> storage;
  const double* points = surface.PointsAsDouble(storage);
  const std::string coordinates = beltrami::CoordinateRangeProblem(topo, points);
  if (!coordinates.empty())
  {
    vtkErrorMacro(<< coordinates << ". The output is empty.");
    return 0;
  }
  if (numPoints > std::numeric_limits<int>::max() / 4)
  {
    vtkErrorMacro("Too many points for TetGen (" << numPoints << "). The output is empty.");
    return 0;
  }

  const std::string switches = this->GetSwitches();
  std::vector<double> outputPoints;
  std::vector<std::int32_t> tets;
  this->UpdateProgress(0.0);
  // (A hollow solid's voids left empty: their walls face into them.)
  const std::vector<beltrami::Vec3> cavities = beltrami::CavityPoints(topo, points);
  if (!RunTetGenOnSurfacePoints(this, switches, numPoints, points, topo.TriangleList(), surface.MergedPoints(),
        cavities, outputPoints, tets))
  {
    return 0;
  }
  this->UpdateProgress(0.8);

  const vtkIdType numOutputPoints = static_cast<vtkIdType>(outputPoints.size() / 3);
  const vtkIdType numTets = static_cast<vtkIdType>(tets.size() / 4);
  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataTypeToDouble();
  outPoints->SetNumberOfPoints(numOutputPoints);
  std::copy(outputPoints.begin(), outputPoints.end(),
    vtkDoubleArray::SafeDownCast(outPoints->GetData())->GetPointer(0));
  output->SetPoints(outPoints);

  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(numTets + 1);
  connectivity->SetNumberOfValues(4 * numTets);
  for (vtkIdType t = 0; t <= numTets; ++t)
  {
    offsets->SetValue(t, 4 * t);
  }
  std::copy(tets.begin(), tets.end(), connectivity->GetPointer(0));
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  output->SetCells(VTK_TETRA, cells);

  this->InterpolatePointData(input->GetPointData(), numPoints, output, connectivity);
  vtkNew<vtkStringArray> used;
  used->SetName("TetGenSwitches");
  used->InsertNextValue(switches);
  output->GetFieldData()->AddArray(used);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkTetGenTetrahedralizer::InterpolatePointData(
  vtkPointData* inPD, vtkIdType numInput, vtkUnstructuredGrid* output, vtkIdTypeArray* connectivity)
{
  const vtkIdType numOutput = output->GetNumberOfPoints();
  std::vector<vtkDataArray*> arrays;
  int columns = 0;
  for (int a = 0; a < inPD->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = inPD->GetArray(a);
    if (array && array->GetNumberOfTuples() == numInput)
    {
      arrays.push_back(array);
      columns += array->GetNumberOfComponents();
    }
  }
  if (arrays.empty())
  {
    return;
  }
  // The input points come first and keep their values; the new (Steiner)
  // points get the harmonic extension: (K u)_i = 0 with the volume Laplacian
  // K of the output, exact for linear fields (linear precision).
  std::vector<double> values(static_cast<std::size_t>(numOutput) * columns, 0.0);
  {
    int slot = 0;
    for (vtkDataArray* array : arrays)
    {
      for (vtkIdType i = 0; i < numInput; ++i)
      {
        for (int c = 0; c < array->GetNumberOfComponents(); ++c)
        {
          values[i * columns + slot + c] = array->GetComponent(i, c);
        }
      }
      slot += array->GetNumberOfComponents();
    }
  }
  if (numOutput > numInput)
  {
    std::vector<beltrami::Index> tets(connectivity->GetPointer(0),
      connectivity->GetPointer(0) + connectivity->GetNumberOfValues());
    const beltrami::TetrahedralMesh mesh(static_cast<beltrami::Index>(numOutput), std::move(tets));
    std::vector<double> points(3 * static_cast<std::size_t>(numOutput));
    for (vtkIdType i = 0; i < numOutput; ++i)
    {
      output->GetPoint(i, &points[3 * i]);
    }
    beltrami::GraphLaplacian laplacian;
    beltrami::AssembleTetrahedralLaplacian(mesh, points.data(), 3, laplacian);
    std::vector<std::uint8_t> known(numOutput, 0);
    std::fill(known.begin(), known.begin() + numInput, 1);
    beltrami::ExtendHarmonically(laplacian, known.data(), columns, values.data());
  }
  int slot = 0;
  vtkPointData* outPD = output->GetPointData();
  for (vtkDataArray* array : arrays)
  {
    const int nc = array->GetNumberOfComponents();
    auto result = vtk::TakeSmartPointer(array->NewInstance());
    result->SetName(array->GetName());
    result->SetNumberOfComponents(nc);
    result->SetNumberOfTuples(numOutput);
    for (vtkIdType i = 0; i < numOutput; ++i)
    {
      for (int c = 0; c < nc; ++c)
      {
        result->SetComponent(i, c, values[i * columns + slot + c]);
      }
    }
    slot += nc;
    outPD->AddArray(result);
    if (array == inPD->GetScalars())
    {
      outPD->SetActiveScalars(result->GetName());
    }
  }
}

void vtkTetGenTetrahedralizer::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "RadiusEdgeRatio: " << this->RadiusEdgeRatio << "\n";
  os << indent << "MinimumDihedralAngle: " << this->MinimumDihedralAngle << "\n";
  os << indent << "MaximumVolume: " << this->MaximumVolume << "\n";
  os << indent << "PreserveSurface: " << this->PreserveSurface << "\n";
}
