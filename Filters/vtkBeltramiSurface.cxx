#include "vtkBeltramiSurface.h"

#include "vtkBeltramiGather.h"

#include "Core/LargeBuffer.h"

#include <vtkAOSDataArrayTemplate.h>
#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellData.h>
#include <vtkCommunicator.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkGhostCellsGenerator.h>
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
  InputData = input; // PointsAsDouble() and the lookups read it
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

vtkSmartPointer<vtkPolyData> vtkBeltramiSurface::GenerateGhosts(vtkAlgorithm* owner, int layers)
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
    return nullptr; // the pieces came with ghost cells (as requested), or none holds points
  }
  // The piece as the generator gets it: its cells, float points and the
  // exact coordinates as point data (VTK 9.2's generator joins the pieces
  // only where their points are float: with double points, e.g. from the
  // OFF reader, it added no ghost cell at all).
  static const char* const exactName = "vtkBeltramiSurface::ExactCoordinates";
  vtkNew<vtkPolyData> piece;
  if (hasPoints)
  {
    vtkDataArray* coordinates = InputData->GetPoints()->GetData();
    vtkSmartPointer<vtkDataArray> exact = vtk::TakeSmartPointer(coordinates->NewInstance());
    exact->ShallowCopy(coordinates);
    exact->SetName(exactName);
    vtkNew<vtkPoints> floats;
    floats->SetDataTypeToFloat();
    floats->GetData()->DeepCopy(coordinates);
    piece->SetPoints(floats);
    piece->GetPointData()->AddArray(exact);
    piece->SetVerts(InputData->GetVerts());
    piece->SetLines(InputData->GetLines());
    piece->SetPolys(InputData->GetPolys());
    piece->SetStrips(InputData->GetStrips());
  }
  vtkNew<vtkGhostCellsGenerator> generator;
  generator->SetController(controller);
  generator->BuildIfRequiredOff();
  generator->SetNumberOfGhostLayers(layers);
  generator->SetInputData(piece);
  generator->Update();
  vtkSmartPointer<vtkPolyData> ghosted = vtkPolyData::SafeDownCast(generator->GetOutputDataObject(0));
  vtkDataArray* exact = ghosted ? ghosted->GetPointData()->GetArray(exactName) : nullptr;
  // The generator keeps the piece's points first, in order (it may give a
  // point shared with another piece that piece's copy of the coordinates);
  // anything else (not seen with VTK 9.2) would mix up the point ids: then
  // go without.
  const vtkIdType n = hasPoints ? InputData->GetNumberOfPoints() : 0;
  bool prefix = exact && exact->GetNumberOfComponents() == 3 && exact->GetNumberOfTuples() >= n &&
    ghosted->GetNumberOfPoints() == exact->GetNumberOfTuples();
  for (vtkIdType i = 0; prefix && i < n; ++i)
  {
    double a[3], b[3];
    InputData->GetPoint(i, a);
    ghosted->GetPoint(i, b);
    prefix = static_cast<float>(a[0]) == b[0] && static_cast<float>(a[1]) == b[1] &&
      static_cast<float>(a[2]) == b[2];
  }
  if (!prefix)
  {
    vtkWarningWithObjectMacro(owner, "Could not add ghost cells to this piece of distributed data: "
                                     "points at the piece boundary are treated as boundary points.");
    return nullptr;
  }
  if (n > 0)
  {
    // The piece's own coordinates, then the ghost points' exact ones.
    vtkNew<vtkPoints> points;
    points->SetDataType(InputData->GetPoints()->GetDataType());
    points->SetNumberOfPoints(ghosted->GetNumberOfPoints());
    vtkDataArray* coordinates = points->GetData();
    coordinates->InsertTuples(0, n, 0, InputData->GetPoints()->GetData());
    coordinates->InsertTuples(n, ghosted->GetNumberOfPoints() - n, n, exact);
    ghosted->SetPoints(points);
  }
  return ghosted;
}

vtkIdType vtkBeltramiSurface::NumberOfInputPoints() const
{
  return InputData ? InputData->GetNumberOfPoints() : 0;
}

vtkIdType vtkBeltramiSurface::NumberOfTopologyPoints() const
{
  return Ghosted ? Ghosted->GetNumberOfPoints() : NumberOfInputPoints();
}

vtkBeltramiSurface::PrepareResult vtkBeltramiSurface::Prepare(vtkAlgorithm* owner,
  vtkInformationVector** inputVector, vtkInformationVector* outputVector, int numberOfThreads,
  int ghostLayers, bool wholeSurface)
{
  InputData = vtkPolyData::GetData(inputVector[0]);
  OutputData = vtkPolyData::GetData(outputVector);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  Holding = PiecesHoldingData(outInfo, InputData); // collective: before any return
  Ghosted = nullptr;
  if (ghostLayers > 0 && Holding > 1 && OnePiecePerRank(outInfo))
  {
    Ghosted = GenerateGhosts(owner, ghostLayers); // collective too
  }
  Gather = nullptr;
  if (wholeSurface && Holding > 1 && OnePiecePerRank(outInfo))
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
  if (!Build(Ghosted ? Ghosted.Get() : InputData, numberOfThreads))
  {
    vtkErrorWithObjectMacro(owner, "Cannot process the input surface: " << Error());
    Finish(false);
    return Failed;
  }
  return Ready;
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
  const vtkIdType n = InputData ? InputData->GetNumberOfPoints() : 0;
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
