#include "vtkBeltramiSurface.h"

#include "vtkBeltramiGather.h"

#include "Support/LargeBuffer.h"

#include <vtkAOSDataArrayTemplate.h>
#include <vtkBoundingBox.h>
#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellData.h>
#include <vtkCommunicator.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMath.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolygon.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

namespace
{

using beltrami::Index;

// Splits a polygon into triangles: quads along the shorter diagonal, larger
// polygons by VTK's ear cutting (which handles non-convex polygons).
void TriangulatePolygon(vtkPoints* points, vtkIdType n, const vtkIdType* ids,
  beltrami::IndexArray& triangles, vtkPolygon* polygon, vtkIdList* scratch)
{
  auto emit = [&](vtkIdType a, vtkIdType b, vtkIdType c) {
    triangles.push_back(static_cast<Index>(a));
    triangles.push_back(static_cast<Index>(b));
    triangles.push_back(static_cast<Index>(c));
  };
  if (n == 3)
  {
    emit(ids[0], ids[1], ids[2]);
    return;
  }
  if (n == 4)
  {
    double p[4][3];
    for (int k = 0; k < 4; ++k)
    {
      points->GetPoint(ids[k], p[k]);
    }
    const double d02 = vtkMath::Distance2BetweenPoints(p[0], p[2]);
    const double d13 = vtkMath::Distance2BetweenPoints(p[1], p[3]);
    if (d02 <= d13)
    {
      emit(ids[0], ids[1], ids[2]);
      emit(ids[0], ids[2], ids[3]);
    }
    else
    {
      emit(ids[0], ids[1], ids[3]);
      emit(ids[1], ids[2], ids[3]);
    }
    return;
  }
  polygon->Initialize(static_cast<int>(n), const_cast<vtkIdType*>(ids), points);
  scratch->Reset();
  if (polygon->Triangulate(scratch) && scratch->GetNumberOfIds() == 3 * (n - 2))
  {
    for (vtkIdType k = 0; k < scratch->GetNumberOfIds(); k += 3)
    {
      emit(ids[scratch->GetId(k)], ids[scratch->GetId(k + 1)], ids[scratch->GetId(k + 2)]);
    }
    return;
  }
  for (vtkIdType k = 1; k + 1 < n; ++k) // degenerate polygon: fan (zero-area parts are flagged later)
  {
    emit(ids[0], ids[k], ids[k + 1]);
  }
}

/// The common case read in parallel without a cell iterator: every polygon
/// a triangle with valid point ids.  Returns false (and leaves the work to
/// the general path) otherwise.
template <typename OffsetArray, typename ConnectivityArray>
bool CopyTriangles(OffsetArray* offsets, ConnectivityArray* connectivity, vtkIdType numPoints,
  int numThreads, beltrami::IndexArray& triangles)
{
  const vtkIdType cells = offsets->GetNumberOfValues() - 1;
  if (cells <= 0 || connectivity->GetNumberOfValues() != 3 * cells)
  {
    return false;
  }
  const auto* o = offsets->GetPointer(0);
  const auto* c = connectivity->GetPointer(0);
  triangles.resize(3 * static_cast<std::size_t>(cells));
  std::atomic<bool> ok{ true };
  beltrami::ParallelFor(cells, numThreads, [&](std::int64_t begin, std::int64_t end) {
    bool good = true;
    for (std::int64_t k = begin; k < end; ++k)
    {
      good = good && o[k + 1] - o[k] == 3;
    }
    for (std::int64_t k = 3 * begin; k < 3 * end; ++k)
    {
      good = good && c[k] >= 0 && c[k] < numPoints;
      triangles[k] = static_cast<Index>(c[k]);
    }
    if (!good)
    {
      ok = false;
    }
  });
  if (!ok)
  {
    triangles.clear();
  }
  return ok;
}

bool ValidCell(vtkIdType n, const vtkIdType* ids, vtkIdType numPoints)
{
  for (vtkIdType k = 0; k < n; ++k)
  {
    if (ids[k] < 0 || ids[k] >= numPoints)
    {
      return false;
    }
  }
  return true;
}

} // namespace

bool vtkBeltramiSurface::Build(vtkPolyData* input, int numberOfThreads)
{
  InputData = input; // the lookups read it
  Mesh.reset();
  CellOfTriangle.clear();
  Floats = nullptr;
  Doubles = nullptr;
  ErrorText.clear();
  IgnoredCells = 0;
  InvalidCells = 0;
  InputCells = input ? input->GetNumberOfCells() : 0;
  const vtkIdType numPoints = input ? input->GetNumberOfPoints() : 0;
  if (numPoints > std::numeric_limits<Index>::max())
  {
    ErrorText = "more than 2^31 points are not supported";
    return false;
  }

  beltrami::IndexArray triangles;
  FirstPolygonCell = input ? input->GetNumberOfVerts() + input->GetNumberOfLines() : 0;
  if (numPoints > 0)
  {
    vtkPoints* points = input->GetPoints();
    vtkDataArray* data = points->GetData();
    if (auto* f = vtkFloatArray::SafeDownCast(data))
    {
      Floats = f->GetPointer(0);
      PointData = f;
    }
    else if (auto* d = vtkDoubleArray::SafeDownCast(data))
    {
      Doubles = d->GetPointer(0);
      PointData = d;
    }
    else // rare point types: one conversion to double
    {
      vtkNew<vtkDoubleArray> converted;
      converted->DeepCopy(data);
      Doubles = converted->GetPointer(0);
      PointData = converted;
    }

    IgnoredCells = input->GetNumberOfVerts() + input->GetNumberOfLines();
    vtkCellArray* polys = input->GetPolys();
    const bool triangleList = input->GetNumberOfStrips() == 0 &&
      (polys->IsStorage64Bit()
          ? CopyTriangles(polys->GetOffsetsArray64(), polys->GetConnectivityArray64(), numPoints,
              numberOfThreads, triangles)
          : CopyTriangles(polys->GetOffsetsArray32(), polys->GetConnectivityArray32(), numPoints,
              numberOfThreads, triangles));
    if (!triangleList)
    {
      BuildTriangles(input, triangles);
    }
  }
  try
  {
    Mesh = std::make_unique<beltrami::MeshTopology>(
      static_cast<Index>(numPoints), std::move(triangles), numberOfThreads);
  }
  catch (const std::exception& e)
  {
    ErrorText = e.what();
    return false;
  }
  return true;
}

void vtkBeltramiSurface::BuildTriangles(vtkPolyData* input, beltrami::IndexArray& triangles)
{
  const vtkIdType numPoints = input->GetNumberOfPoints();
  vtkPoints* points = input->GetPoints();
  triangles.reserve(3 * static_cast<std::size_t>(input->GetNumberOfPolys()));
  CellOfTriangle.reserve(input->GetNumberOfPolys());
  vtkIdType cellId = input->GetNumberOfVerts() + input->GetNumberOfLines();
  const auto recordCell = [&]() {
    CellOfTriangle.resize(triangles.size() / 3, cellId);
    ++cellId;
  };
  vtkNew<vtkPolygon> polygon;
  vtkNew<vtkIdList> scratch;
  auto polys = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
  for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    polys->GetCurrentCell(n, ids);
    if (!ValidCell(n, ids, numPoints))
    {
      ++InvalidCells;
    }
    else if (n >= 3)
    {
      TriangulatePolygon(points, n, ids, triangles, polygon, scratch);
    }
    recordCell();
  }
  auto strips = vtk::TakeSmartPointer(input->GetStrips()->NewIterator());
  for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    strips->GetCurrentCell(n, ids);
    if (!ValidCell(n, ids, numPoints))
    {
      ++InvalidCells;
      recordCell();
      continue;
    }
    for (vtkIdType k = 0; k + 2 < n; ++k) // alternate orientation along the strip
    {
      const bool even = k % 2 == 0;
      triangles.push_back(static_cast<Index>(ids[even ? k : k + 1]));
      triangles.push_back(static_cast<Index>(ids[even ? k + 1 : k]));
      triangles.push_back(static_cast<Index>(ids[k + 2]));
    }
    recordCell();
  }
}

namespace
{

int RequestedPieces(vtkInformation* outInfo)
{
  return outInfo && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    : 1;
}

} // namespace

bool vtkBeltramiSurface::OnePiecePerRank(vtkInformation* outInfo)
{
  const int pieces = RequestedPieces(outInfo);
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  return pieces > 1 && controller && controller->GetNumberOfProcesses() == pieces &&
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) == controller->GetLocalProcessId();
}

int vtkBeltramiSurface::PiecesHoldingData(vtkInformation* outInfo, vtkDataSet* input)
{
  const int pieces = RequestedPieces(outInfo);
  if (pieces <= 1)
  {
    return 1;
  }
  if (!OnePiecePerRank(outInfo))
  {
    return pieces; // not one piece per rank: cannot ask the others
  }
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  int local = input && input->GetNumberOfPoints() > 0 ? 1 : 0, holding = 0;
  controller->AllReduce(&local, &holding, 1, vtkCommunicator::SUM_OP);
  return holding;
}

void vtkBeltramiSurface::WarnDistributed(vtkAlgorithm* owner, int pieces, const char* pieceBoundary)
{
  vtkWarningWithObjectMacro(owner, "Distributed data (" << pieces << " pieces hold points): each piece is "
    "smoothed on its own with " << pieceBoundary << ", so near the piece boundaries the result is not the "
    "serial one. Run it on the whole data set (e.g. after Merge Blocks / D3 to one process).");
}

void vtkBeltramiSurface::WarnAboutInput(
  vtkAlgorithm* owner, const char* pieceBoundary, const char* consequence) const
{
  if (Holding > 1)
  {
    WarnDistributed(owner, Holding, pieceBoundary);
  }
  else if (!TopologyWarning().empty())
  {
    vtkWarningWithObjectMacro(owner, << TopologyWarning() << ". " << consequence);
  }
}

bool vtkBeltramiSurface::ExchangeOneRings(int numberOfThreads)
{
  // Called on every rank when the pieces are the ranks and several hold
  // points (PiecesHoldingData communicated): the decision is collective.
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const bool hasPoints = InputData && InputData->GetNumberOfPoints() > 0;
  bool hasGhosts = false; // duplicate cells (a ghost array of zeros is no ghost layer)
  if (vtkUnsignedCharArray* ghosts = InputData ? InputData->GetCellGhostArray() : nullptr)
  {
    const unsigned char* flags = ghosts->GetPointer(0);
    hasGhosts = std::any_of(flags, flags + ghosts->GetNumberOfValues(),
      [](unsigned char f) { return (f & vtkDataSetAttributes::DUPLICATECELL) != 0; });
  }
  int local[2] = { hasPoints && !hasGhosts ? 1 : 0, hasGhosts ? 1 : 0 };
  int global[2] = { 0, 0 };
  controller->AllReduce(local, global, 2, vtkCommunicator::SUM_OP);
  if (global[0] == 0 || global[1] > 0)
  {
    return false; // the pieces came with ghost cells, or none holds points
  }

  // What this piece offers: every triangle at a vertex on the edge of the
  // piece (a boundary or non-manifold vertex of its own topology), as its
  // corners' coordinates.  A point that pieces share is on the edge of each
  // of them, so every piece gets the whole star of its shared points - also
  // from a piece that touches it at that point only.
  const int ranks = controller->GetNumberOfProcesses();
  const int rank = controller->GetLocalProcessId();
  std::vector<double> offer;
  std::vector<Index> edgeVertices; // this piece's boundary and non-manifold vertices
  const bool built = hasPoints && Build(InputData, numberOfThreads);
  if (built)
  {
    const beltrami::MeshTopology& topo = *Mesh;
    std::vector<std::uint8_t> offered(static_cast<std::size_t>(topo.NumberOfTriangles()), 0);
    for (Index v = 0; v < topo.NumberOfVertices(); ++v)
    {
      if (topo.VertexFlags(v) & (beltrami::VertexBoundary | beltrami::VertexNonManifold))
      {
        edgeVertices.push_back(v);
        for (const Index* c = topo.CornersBegin(v); c != topo.CornersEnd(v); ++c)
        {
          offered[*c / 3] = 1;
        }
      }
    }
    for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
    {
      for (int k = 0; offered[t] && k < 3; ++k)
      {
        double x[3];
        InputData->GetPoint(topo.CornerVertex(3 * t + k), x);
        offer.insert(offer.end(), x, x + 3);
      }
    }
  }
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(ranks), 0), offsets(ranks + 1, 0);
  const vtkIdType length = static_cast<vtkIdType>(offer.size());
  controller->AllGather(&length, lengths.data(), 1);
  for (int r = 0; r < ranks; ++r)
  {
    offsets[r + 1] = offsets[r] + lengths[r];
  }
  std::vector<double> offers(static_cast<std::size_t>(offsets[ranks]));
  controller->AllGatherV(offer.data(), offers.data(), length, lengths.data(), offsets.data());
  if (edgeVertices.empty() || offsets[ranks] == length)
  {
    return built; // nothing to join (this piece has no edge, or no other piece offers)
  }

  // Join: this piece's edge vertices, then the other pieces' corners, with
  // their copies of common points merged (as vtkBeltramiGather does).
  const vtkIdType own = static_cast<vtkIdType>(edgeVertices.size());
  const vtkIdType corners = (offsets[ranks] - length) / 3;
  vtkNew<vtkPoints> joined;
  joined->SetDataTypeToDouble();
  joined->SetNumberOfPoints(own + corners);
  vtkBoundingBox box;
  for (vtkIdType i = 0; i < own; ++i)
  {
    double x[3];
    InputData->GetPoint(edgeVertices[i], x);
    joined->SetPoint(i, x);
    box.AddPoint(x);
  }
  vtkIdType corner = 0;
  for (int r = 0; r < ranks; ++r)
  {
    for (vtkIdType k = offsets[r]; r != rank && k < offsets[r + 1]; k += 3, ++corner)
    {
      joined->SetPoint(own + corner, offers.data() + k);
      box.AddPoint(offers.data() + k);
    }
  }
  const std::vector<vtkIdType> merged =
    vtkBeltramiGather::CoincidentPoints(joined, 1e-12 * box.GetDiagonalLength());
  // Per representative: the piece's point it stands for, or a new ghost point
  // (numbered after the piece's points).
  std::vector<vtkIdType> pointOf(static_cast<std::size_t>(own + corners), -1);
  for (vtkIdType i = 0; i < own; ++i)
  {
    pointOf[merged[i]] = edgeVertices[i];
  }
  const Index n = Mesh->NumberOfVertices();
  beltrami::IndexArray triangles(Mesh->TriangleList());
  const std::size_t kept = triangles.size() / 3;
  std::vector<double> ghostPoints;
  for (vtkIdType t = 0; t < corners / 3; ++t)
  {
    const vtkIdType* m = merged.data() + own + 3 * t;
    if (pointOf[m[0]] < 0 && pointOf[m[1]] < 0 && pointOf[m[2]] < 0)
    {
      continue; // not at this piece
    }
    for (int k = 0; k < 3; ++k)
    {
      if (pointOf[m[k]] < 0)
      {
        pointOf[m[k]] = n + static_cast<vtkIdType>(ghostPoints.size() / 3);
        const double* x = joined->GetPoint(m[k]);
        ghostPoints.insert(ghostPoints.end(), x, x + 3);
      }
      triangles.push_back(static_cast<Index>(pointOf[m[k]]));
    }
  }
  if (triangles.size() / 3 == kept)
  {
    return true; // the other pieces' edges do not touch this one
  }
  // The piece's coordinates (their own precision), then the ghost points'.
  const Index total = n + static_cast<Index>(ghostPoints.size() / 3);
  vtkSmartPointer<vtkDataArray> coordinates = NewArray(Floats ? VTK_FLOAT : VTK_DOUBLE, nullptr, 3, total);
  if (Floats)
  {
    float* x = vtkFloatArray::FastDownCast(coordinates)->GetPointer(0);
    std::copy(Floats, Floats + 3 * static_cast<std::size_t>(n), x);
    std::copy(ghostPoints.begin(), ghostPoints.end(), x + 3 * static_cast<std::size_t>(n));
    Floats = x;
  }
  else
  {
    double* x = vtkDoubleArray::FastDownCast(coordinates)->GetPointer(0);
    std::copy(Doubles, Doubles + 3 * static_cast<std::size_t>(n), x);
    std::copy(ghostPoints.begin(), ghostPoints.end(), x + 3 * static_cast<std::size_t>(n));
    Doubles = x;
  }
  PointData = coordinates;
  // Input cells of the kept triangles (TriangleCell); -1 for the ring's.
  std::vector<vtkIdType> cells(triangles.size() / 3, -1);
  const beltrami::IndexArray& original = Mesh->OriginalTriangleIds();
  for (std::size_t t = 0; t < kept; ++t)
  {
    cells[t] = TriangleCell(original[t]);
  }
  try
  {
    Mesh = std::make_unique<beltrami::MeshTopology>(total, std::move(triangles), numberOfThreads);
  }
  catch (const std::exception& e)
  {
    ErrorText = e.what();
    Mesh.reset();
    return false;
  }
  CellOfTriangle = std::move(cells);
  return true;
}

vtkIdType vtkBeltramiSurface::NumberOfInputPoints() const
{
  return InputData ? InputData->GetNumberOfPoints() : 0;
}

vtkIdType vtkBeltramiSurface::NumberOfTopologyPoints() const
{
  return Mesh ? Mesh->NumberOfVertices() : NumberOfInputPoints();
}

vtkBeltramiSurface::PrepareResult vtkBeltramiSurface::Prepare(vtkAlgorithm* owner,
  vtkInformationVector** inputVector, vtkInformationVector* outputVector, int numberOfThreads, Needs needs)
{
  InputData = vtkPolyData::GetData(inputVector[0]);
  OutputData = vtkPolyData::GetData(outputVector);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  Holding = PiecesHoldingData(outInfo, InputData); // collective: before any return
  bool built = false;
  if (needs == Needs::OneRings && Holding > 1 && OnePiecePerRank(outInfo))
  {
    built = ExchangeOneRings(numberOfThreads); // collective too
  }
  Gather = nullptr;
  if (needs == Needs::WholeSurface && Holding > 1 && OnePiecePerRank(outInfo))
  {
    Gather = std::make_shared<vtkBeltramiGather>();
    vtkNew<vtkPolyData> empty; // (a missing input: an empty piece)
    Whole = vtkPolyData::SafeDownCast(Gather->Collect(
      vtkMultiProcessController::GetGlobalController(), InputData ? InputData : empty.Get())); // collective
    PieceOutput = OutputData;
    if (PieceOutput && InputData)
    {
      PieceOutput->ShallowCopy(InputData);
    }
    if (!Whole)
    {
      return Gathered;
    }
    WholeOutput = vtkSmartPointer<vtkPolyData>::New();
    InputData = Whole;
    OutputData = WholeOutput;
    Holding = 1; // the whole surface, as in a serial run
  }
  if (!InputData || !OutputData)
  {
    vtkErrorWithObjectMacro(owner, "Missing input or output poly data.");
    Finish(false);
    return Failed;
  }
  OutputData->ShallowCopy(InputData);
  Pieces = Gather ? 1 : std::max(1, RequestedPieces(outInfo));
  if (InputData->GetNumberOfPoints() == 0)
  {
    if (Pieces <= 1) // an empty piece of distributed data is normal
    {
      vtkWarningWithObjectMacro(owner, "Input has no points: nothing to do.");
    }
    Finish(true); // (a gathered run: the outputs stay the inputs)
    return NothingToDo;
  }
  if (!built && !Build(InputData, numberOfThreads))
  {
    vtkErrorWithObjectMacro(owner, "Cannot process the input surface: " << Error());
    Finish(false);
    return Failed;
  }
  return Ready;
}

int vtkBeltramiSurface::Execute(vtkAlgorithm* owner, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, int numberOfThreads, Needs needs,
  const std::function<bool(vtkBeltramiSurface&)>& run, const std::function<void(vtkPolyData*)>& received)
{
  vtkBeltramiSurface surface;
  const PrepareResult prepared = surface.Prepare(owner, inputVector, outputVector, numberOfThreads, needs);
  if (prepared == Gathered)
  {
    const int done = surface.Finish(true);
    if (received)
    {
      received(vtkPolyData::GetData(outputVector));
    }
    return done;
  }
  if (prepared != Ready)
  {
    return prepared == NothingToDo ? 1 : 0;
  }
  return surface.Finish(run(surface));
}

int vtkBeltramiSurface::Finish(bool ok)
{
  if (!Gather)
  {
    return ok ? 1 : 0;
  }
  const bool done = Gather->Distribute(Whole, WholeOutput, ok, PieceOutput);
  Gather = nullptr; // once
  return done ? 1 : 0;
}

vtkDataArray* vtkBeltramiSurface::SelectedPointArray(
  vtkAlgorithm* owner, int idx, int components, const char* what, std::string& error) const
{
  return SelectedPointArray(owner, InputData, idx, components, what, error);
}

vtkDataArray* vtkBeltramiSurface::SelectedPointArray(vtkAlgorithm* owner, vtkDataSet* input, int idx,
  int components, const char* what, std::string& error)
{
  vtkInformation* info = owner->GetInputArrayInformation(idx);
  const char* name =
    info && info->Has(vtkDataObject::FIELD_NAME()) ? info->Get(vtkDataObject::FIELD_NAME()) : nullptr;
  if (!name || !*name || !input)
  {
    return nullptr;
  }
  vtkDataArray* a = input->GetPointData()->GetArray(name);
  if (!a && std::string(name) == "None") // ParaView's none_string of an array selection
  {
    return nullptr;
  }
  if (!a)
  {
    // A warning, not an error: these arrays are optional, and pvpython's
    // Filter(Input=x) chooses defaults from the active source before x is set,
    // so a stale name can reach the filter.
    vtkWarningWithObjectMacro(owner, << "The " << what << " point array '" << name
                                     << "' does not exist in the input"
                                     << (input->GetCellData()->GetAbstractArray(name)
                                            ? " (it is a cell array; point data are needed)"
                                            : "")
                                     << "; it is ignored.");
    return nullptr;
  }
  if (components > 0 && a->GetNumberOfComponents() != components)
  {
    error = std::string("The ") + what + " point array '" + name + "' needs " + std::to_string(components) +
      (components == 1 ? " component." : " components.");
    return nullptr;
  }
  return a;
}

std::vector<std::uint8_t> vtkBeltramiSurface::SelectedPointMask(
  vtkAlgorithm* owner, vtkDataSet* input, int idx, const char* what, std::string& error)
{
  std::vector<std::uint8_t> mask;
  if (vtkDataArray* a = SelectedPointArray(owner, input, idx, 1, what, error))
  {
    mask.resize(static_cast<std::size_t>(a->GetNumberOfTuples()));
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    {
      mask[i] = a->GetComponent(i, 0) != 0.0;
    }
  }
  return mask;
}

namespace
{
template <typename T>
void AllocateLarge(vtkDataArray* array, vtkIdType values)
{
  auto* aos = vtkAOSDataArrayTemplate<T>::SafeDownCast(array);
  T* memory = aos ? beltrami::LargeBufferAllocator<T>().allocate(static_cast<std::size_t>(values)) : nullptr;
  if (!memory)
  {
    array->SetNumberOfValues(values);
    return;
  }
  aos->SetArray(memory, values, /*save=*/0, vtkAbstractArray::VTK_DATA_ARRAY_USER_DEFINED);
  aos->SetArrayFreeFunction(&beltrami::FreeLargeBlock); // back to the block cache
}
} // namespace

vtkSmartPointer<vtkDataArray> vtkBeltramiSurface::NewArray(
  int dataType, const char* name, int components, vtkIdType tuples)
{
  auto array = vtk::TakeSmartPointer(vtkDataArray::CreateDataArray(dataType));
  array->SetName(name);
  array->SetNumberOfComponents(components);
  const vtkIdType values = static_cast<vtkIdType>(components) * std::max<vtkIdType>(tuples, 0);
  if (values * array->GetDataTypeSize() < static_cast<vtkIdType>(beltrami::LargeBufferAllocator<char>::HugePage))
  {
    array->SetNumberOfTuples(tuples);
    return array;
  }
  switch (dataType)
  {
    vtkTemplateMacro(AllocateLarge<VTK_TT>(array, values));
    default:
      array->SetNumberOfTuples(tuples);
  }
  return array;
}

const double* vtkBeltramiSurface::PointsAsDouble(std::vector<double>& storage) const
{
  if (Doubles)
  {
    return Doubles;
  }
  const std::size_t n = Mesh ? static_cast<std::size_t>(Mesh->NumberOfVertices()) : 0;
  storage.assign(Floats, Floats + 3 * n);
  return storage.data();
}

std::string vtkBeltramiSurface::TopologyWarning() const
{
  if (!Mesh)
  {
    return {};
  }
  const beltrami::TopologySummary& s = Mesh->Summary();
  if (s.IsManifold() && s.IsOriented() && Mesh->NumberOfDroppedTriangles() == 0 &&
    s.NumberOfIsolatedVertices == 0 && InvalidCells == 0)
  {
    return {};
  }
  std::ostringstream os;
  os << "Input surface has defects: " << Mesh->Describe();
  if (s.NumberOfIsolatedVertices)
  {
    os << ", " << s.NumberOfIsolatedVertices << " points used by no triangle";
  }
  if (InvalidCells)
  {
    os << ", " << InvalidCells << " cells with point ids out of range (ignored)";
  }
  return os.str();
}
// VTK-HeaderTest-Exclude: vtkBeltramiSurface.cxx
