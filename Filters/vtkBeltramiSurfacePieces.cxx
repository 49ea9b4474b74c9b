// vtkBeltramiSurface, distributed runs: how many pieces hold data, the
// exchange of the triangles around the points at the edges of the pieces
// (whole 1-rings), and Execute, the one way a surface
// filter runs (gathered on rank 0 when it needs the whole surface).
#include "vtkBeltramiSurface.h"

#include "vtkBeltramiGather.h"

#include <vtkAlgorithm.h>
#include <vtkBoundingBox.h>
#include <vtkCommunicator.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMPICommunicator.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

using beltrami::Index;

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
  // points (PiecesHoldingData communicated): the decisions are collective.
  if (!vtkBeltramiPieces::RingsAreMissing(InputData))
  {
    return false; // the pieces came with ghost cells, or none holds points
  }
  bool built = InputData && InputData->GetNumberOfPoints() > 0 && Build(InputData, numberOfThreads);
  // Copies within the piece (two of RedistributeDataSet's regions on one
  // rank): one is kept.
  std::vector<std::uint8_t> repeated(built ? static_cast<std::size_t>(Mesh->NumberOfTriangles()) : 0, 0);
  if (built && Mesh->Summary().NumberOfDuplicateTriangles > 0)
  {
    vtkBeltramiPieces::RepeatedCells(3, std::vector<Index>(Mesh->TriangleList().begin(), Mesh->TriangleList().end()),
      repeated, [this](Index v) { return (Mesh->VertexFlags(v) & beltrami::VertexDuplicateFace) != 0; });
  }
  if (std::find(repeated.begin(), repeated.end(), 1) != repeated.end())
  {
    built = DropTriangles(repeated, numberOfThreads); // (false: Error() says why; AddRings still collective)
  }
  const Index n = built ? Mesh->NumberOfVertices() : 0;
  const auto point = [this](Index i, double* x) { PointAt(i, x); };
  std::vector<std::uint8_t> edge(static_cast<std::size_t>(n)); // boundary and non-manifold vertices
  for (Index v = 0; v < n; ++v)
  {
    edge[v] = (Mesh->VertexFlags(v) & (beltrami::VertexBoundary | beltrami::VertexNonManifold)) != 0;
  }
  std::vector<Index> triangles;
  if (built)
  {
    triangles.assign(Mesh->TriangleList().begin(), Mesh->TriangleList().end());
  }
  Rings.ShareCopiedCells(3, n, point, triangles, edge); // (collective)
  const std::size_t kept = triangles.size() / 3;
  if (!Rings.AddRings(3, n, point, edge, triangles)) // collective
  {
    return built; // no other piece's triangle touches this one
  }
  return Rebuild(beltrami::IndexArray(triangles.begin(), triangles.end()), Rings.GhostPoints(), kept, numberOfThreads);
}

void vtkBeltramiSurface::PointAt(Index i, double* x) const
{
  for (int k = 0; k < 3; ++k)
  {
    x[k] = Floats ? Floats[3 * static_cast<std::size_t>(i) + k] : Doubles[3 * static_cast<std::size_t>(i) + k];
  }
}

bool vtkBeltramiSurface::DropTriangles(const std::vector<std::uint8_t>& drop, int numberOfThreads)
{
  const beltrami::IndexArray& all = Mesh->TriangleList();
  const beltrami::IndexArray& original = Mesh->OriginalTriangleIds();
  beltrami::IndexArray triangles;
  std::vector<vtkIdType> cells;
  for (std::size_t t = 0; t < drop.size(); ++t)
  {
    if (!drop[t])
    {
      triangles.insert(triangles.end(), all.begin() + 3 * t, all.begin() + 3 * t + 3);
      cells.push_back(TriangleCell(original[t]));
    }
  }
  return Remake(Mesh->NumberOfVertices(), std::move(triangles), std::move(cells), numberOfThreads);
}

bool vtkBeltramiSurface::Remake(
  Index points, beltrami::IndexArray triangles, std::vector<vtkIdType> cells, int numberOfThreads)
{
  try
  {
    Mesh = std::make_unique<beltrami::MeshTopology>(points, std::move(triangles), numberOfThreads);
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

bool vtkBeltramiSurface::Rebuild(
  beltrami::IndexArray triangles, const std::vector<double>& ghostPoints, std::size_t kept, int numberOfThreads)
{
  const Index n = Mesh->NumberOfVertices();
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
  return Remake(total, std::move(triangles), std::move(cells), numberOfThreads);
}

int vtkBeltramiSurface::Start(vtkAlgorithm* owner, int numberOfThreads, bool built)
{
  if (!InputData || !OutputData)
  {
    vtkErrorWithObjectMacro(owner, "Missing input or output poly data.");
    return 0;
  }
  OutputData->ShallowCopy(InputData);
  if (InputData->GetNumberOfPoints() == 0)
  {
    if (Pieces <= 1) // an empty piece of distributed data is normal
    {
      vtkWarningWithObjectMacro(owner, "Input has no points: nothing to do.");
    }
    return 1;
  }
  if (!built && !Build(InputData, numberOfThreads))
  {
    vtkErrorWithObjectMacro(owner, "Cannot process the input surface: " << Error());
    return 0;
  }
  if (!RepairText.empty())
  {
    vtkWarningWithObjectMacro(owner, << RepairText);
  }
  return -1;
}

int vtkBeltramiSurface::ExecuteDistributed(vtkAlgorithm* owner, vtkPolyData* input, vtkPolyData* output,
  vtkInformation* outInfo, int numberOfThreads, const std::function<bool(vtkBeltramiSurface&)>& run)
{
  if (!vtkBeltramiPieces::CanSolveTogether(outInfo))
  {
    return -1; // the ranks cannot solve together
  }
  vtkBeltramiSurface surface;
  surface.InputData = input;
  surface.OutputData = output;
  surface.Pieces = RequestedPieces(outInfo);
  surface.Holding = PiecesHoldingData(outInfo, input);  // collective
  surface.Rings.SetCollective(true);
  if (surface.Holding <= 1 || !vtkBeltramiPieces::RingsAreMissing(input)) // collective
  {
    return -1; // whole on one rank (serial), or pieces that came with ghost cells (gathered)
  }
  const bool built = surface.ExchangeOneRings(numberOfThreads); // collective
  const bool empty = !input || input->GetNumberOfPoints() == 0;
  if (!input || !output)
  {
    vtkWarningWithObjectMacro(owner, "Missing input or output poly data on this rank: an empty piece.");
  }
  else
  {
    output->ShallowCopy(input);
  }
  if (!built && !empty)
  {
    vtkErrorWithObjectMacro(owner, "Cannot process the input surface: " << surface.Error());
  }
  if (!surface.AllAgree(built || empty))
  {
    if (built || empty)
    {
      vtkErrorWithObjectMacro(owner, "Another rank cannot process its piece of the surface (see its error).");
    }
    return 0;
  }
  if (!built)
  {
    surface.Mesh = std::make_unique<beltrami::MeshTopology>(0, beltrami::IndexArray());
  }
  const Index rows = surface.Mesh->NumberOfVertices();
  const Index pieceRows = std::min<Index>(rows, input ? static_cast<Index>(input->GetNumberOfPoints()) : 0);
  if (!surface.AllAgree(surface.Rings.BuildPartition(
        rows, pieceRows, [&surface](Index i, double* x) { surface.PointAt(i, x); }, surface.ErrorText)))
  {
    vtkErrorWithObjectMacro(owner, "Cannot split the solve over the ranks: " << surface.Error());
    return 0;
  }
  return run(surface) ? 1 : 0;
}

void vtkBeltramiSurface::NewCompositeOutputs(vtkInformation* request, vtkInformationVector* outputVector)
{
  if (!request->Has(vtkDemandDrivenPipeline::REQUEST_DATA_OBJECT()))
  {
    return;
  }
  for (int port = 1; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    vtkInformation* info = outputVector->GetInformationObject(port);
    if (vtkCompositeDataSet* maps = vtkCompositeDataSet::SafeDownCast(info->Get(vtkDataObject::DATA_OBJECT())))
    {
      info->Set(vtkDataObject::DATA_OBJECT(), vtkSmartPointer<vtkDataObject>::Take(maps->NewInstance()));
    }
  }
}

int vtkBeltramiSurface::RunOnWholeSurface(vtkAlgorithm* owner, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, const std::function<int(vtkPolyData*, vtkPolyData*)>& run)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorWithObjectMacro(owner, "Input and output must be vtkPolyData.");
    return 0;
  }
  for (int port = 1; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    if (vtkDataObject* other = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT()))
    {
      other->Initialize(); // nothing until run fills it
    }
  }
  return vtkBeltramiGather::RunWhole(outputVector->GetInformationObject(0), input, output,
    vtkBeltramiGather::Results::OnRankZero, [&run](vtkPointSet* in, vtkPointSet* out, int) {
      return run(vtkPolyData::SafeDownCast(in), vtkPolyData::SafeDownCast(out));
    });
}

int vtkBeltramiSurface::Execute(vtkAlgorithm* owner, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, int numberOfThreads, Needs needs,
  const std::function<bool(vtkBeltramiSurface&)>& run, const std::function<void(vtkPolyData*)>& received)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int requested = std::max(1, RequestedPieces(outInfo));
  if (needs == Needs::Distributed)
  {
    const int done = ExecuteDistributed(owner, input, output, outInfo, numberOfThreads, run);
    if (done >= 0)
    {
      return done;
    }
    needs = Needs::WholeSurface; // not split over ranks that can talk, or pieces with ghost cells
  }
  if (needs != Needs::WholeSurface)
  {
    vtkBeltramiSurface surface;
    surface.InputData = input;
    surface.OutputData = output;
    surface.Pieces = requested;
    surface.Holding = PiecesHoldingData(outInfo, input); // collective: before any return
    const bool built = needs == Needs::OneRings && surface.Holding > 1 && OnePiecePerRank(outInfo) &&
      surface.ExchangeOneRings(numberOfThreads); // collective too
    const int done = surface.Start(owner, numberOfThreads, built);
    return done >= 0 ? done : surface.RunAndSpread(run);
  }
  vtkNew<vtkPolyData> empty; // (a missing input: an empty piece)
  vtkPointSet* piece = input ? static_cast<vtkPointSet*>(input) : empty.Get();
  bool ran = false;
  const int done = vtkBeltramiGather::RunWhole(outInfo, piece, output, vtkBeltramiGather::Results::ToEveryPiece,
    [&](vtkPointSet* in, vtkPointSet* out, int holding) {
      ran = true;
      vtkBeltramiSurface surface;
      surface.InputData = vtkPolyData::SafeDownCast(in);
      surface.OutputData = vtkPolyData::SafeDownCast(out);
      surface.Gathered = in != piece;
      surface.Pieces = surface.Gathered ? 1 : requested;
      surface.Holding = holding;
      const int started = surface.Start(owner, numberOfThreads, false);
      return started >= 0 ? started : surface.RunAndSpread(run);
    });
  if (!ran && received && output)
  {
    received(output);
  }
  return done;
}

