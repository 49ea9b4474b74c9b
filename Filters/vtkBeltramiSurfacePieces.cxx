// vtkBeltramiSurface, distributed runs: how many pieces hold data, the
// exchange of the triangles around the points at the edges of the pieces
// (whole 1-rings), and Execute, the one way a surface
// filter runs (gathered on rank 0 when it needs the whole surface).
#include "vtkBeltramiSurface.h"

#include "vtkBeltramiGather.h"

#include <vtkAlgorithm.h>
#include <vtkBoundingBox.h>
#include <vtkCommunicator.h>
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

std::vector<double> vtkBeltramiSurface::AllGather(
  vtkMultiProcessController* controller, const std::vector<double>& mine, std::vector<vtkIdType>& offsets)
{
  const int ranks = controller->GetNumberOfProcesses();
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(ranks), 0);
  offsets.assign(ranks + 1, 0);
  const vtkIdType length = static_cast<vtkIdType>(mine.size());
  controller->AllGather(&length, lengths.data(), 1);
  for (int r = 0; r < ranks; ++r)
  {
    offsets[r + 1] = offsets[r] + lengths[r];
  }
  std::vector<double> all(static_cast<std::size_t>(offsets[ranks]));
  controller->AllGatherV(mine.data(), all.data(), length, lengths.data(), offsets.data());
  return all;
}

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
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!RingsAreMissing(controller))
  {
    return false; // the pieces came with ghost cells, or none holds points
  }
  std::vector<Index>& edgeVertices = EdgeVertices; // this piece's boundary and non-manifold vertices
  const bool built = InputData && InputData->GetNumberOfPoints() > 0 && Build(InputData, numberOfThreads);
  const std::vector<double> offer = built ? EdgeTriangles(edgeVertices) : std::vector<double>();
  const int ranks = controller->GetNumberOfProcesses();
  std::vector<vtkIdType> offsets;
  std::vector<double> offers = AllGather(controller, offer, offsets);
  if (edgeVertices.empty() || offsets[ranks] == static_cast<vtkIdType>(offer.size()))
  {
    return built; // nothing to join (this piece has no edge, or no other piece offers)
  }
  // The other pieces' offers, without this one's.
  const int rank = controller->GetLocalProcessId();
  offers.erase(offers.begin() + offsets[rank], offers.begin() + offsets[rank + 1]);
  return AddRing(edgeVertices, offers, numberOfThreads);
}

bool vtkBeltramiSurface::RingsAreMissing(vtkMultiProcessController* controller) const
{
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
  return global[0] > 0 && global[1] == 0;
}

std::vector<double> vtkBeltramiSurface::EdgeTriangles(std::vector<Index>& edgeVertices)
{
  // Every triangle at a vertex on the edge of the piece (a boundary or
  // non-manifold vertex of its own topology), as its corners' coordinates.
  // A point that pieces share is on the edge of each of them, so every
  // piece gets the whole star of its shared points - also from a piece that
  // touches it at that point only.
  const beltrami::MeshTopology& topo = *Mesh;
  std::vector<double> offer;
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
  std::vector<std::uint8_t> corner(static_cast<std::size_t>(topo.NumberOfVertices()), 0);
  for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
  {
    for (int k = 0; offered[t] && k < 3; ++k)
    {
      double x[3];
      InputData->GetPoint(topo.CornerVertex(3 * t + k), x);
      offer.insert(offer.end(), x, x + 3);
      corner[topo.CornerVertex(3 * t + k)] = 1;
    }
  }
  OfferedPoints.clear();
  for (Index v = 0; v < topo.NumberOfVertices(); ++v)
  {
    if (corner[v])
    {
      OfferedPoints.push_back(v);
    }
  }
  return offer;
}

bool vtkBeltramiSurface::AddRing(
  const std::vector<Index>& edgeVertices, const std::vector<double>& offers, int numberOfThreads)
{
  // Join: this piece's edge vertices, then the other pieces' corners, with
  // their copies of common points merged (as vtkBeltramiGather does).
  const vtkIdType own = static_cast<vtkIdType>(edgeVertices.size());
  const vtkIdType corners = static_cast<vtkIdType>(offers.size() / 3);
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
  for (vtkIdType corner = 0; corner < corners; ++corner)
  {
    double x[3] = { offers[3 * corner], offers[3 * corner + 1], offers[3 * corner + 2] };
    joined->SetPoint(own + corner, x);
    box.AddPoint(x);
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
  return Rebuild(std::move(triangles), ghostPoints, kept, numberOfThreads);
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
  return -1;
}

int vtkBeltramiSurface::ExecuteDistributed(vtkAlgorithm* owner, vtkPolyData* input, vtkPolyData* output,
  vtkInformation* outInfo, int numberOfThreads, const std::function<bool(vtkBeltramiSurface&)>& run)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!OnePiecePerRank(outInfo) || !vtkMPICommunicator::SafeDownCast(controller->GetCommunicator()))
  {
    return -1; // the ranks cannot solve together
  }
  vtkBeltramiSurface surface;
  surface.InputData = input;
  surface.OutputData = output;
  surface.Pieces = RequestedPieces(outInfo);
  surface.Holding = PiecesHoldingData(outInfo, input);  // collective
  surface.Collective = true;
  if (surface.Holding <= 1 || !surface.RingsAreMissing(controller)) // collective
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
  if (!surface.AllAgree(surface.BuildPartition(controller)))
  {
    vtkErrorWithObjectMacro(owner, "Cannot split the solve over the ranks: " << surface.Error());
    return 0;
  }
  return run(surface) ? 1 : 0;
}

bool vtkBeltramiSurface::AllAgree(bool ok) const
{
  if (!Collective)
  {
    return ok;
  }
  int local = ok ? 1 : 0, all = 0;
  vtkMultiProcessController::GetGlobalController()->AllReduce(&local, &all, 1, vtkCommunicator::MIN_OP);
  return all == 1;
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
    return done >= 0 ? done : (run(surface) ? 1 : 0);
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
      return started >= 0 ? started : (run(surface) ? 1 : 0);
    });
  if (!ran && received && output)
  {
    received(output);
  }
  return done;
}

