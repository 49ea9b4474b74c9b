// vtkBeltramiSurface, distributed solves (Needs::Distributed): who owns
// each point of a piece with its rings, agreed between the ranks by the
// points' coordinates, and the core's Partition over MPI built from it.
#include "vtkBeltramiSurface.h"

#include "vtkBeltramiGather.h"

#include <vtkBoundingBox.h>
#include <vtkMPI.h>
#include <vtkMPICommunicator.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <vector>

using beltrami::Index;

namespace
{

/// The coincident-point classes (vtkBeltramiGather::CoincidentPoints) of
/// `first` points (3 values each) followed by `second` points (`width`
/// values each, coordinates first).
std::vector<vtkIdType> MatchPoints(const std::vector<double>& first, const std::vector<double>& second, int width)
{
  const vtkIdType n1 = static_cast<vtkIdType>(first.size() / 3), n2 = static_cast<vtkIdType>(second.size() / width);
  vtkNew<vtkPoints> joined;
  joined->SetDataTypeToDouble();
  joined->SetNumberOfPoints(n1 + n2);
  vtkBoundingBox box;
  for (vtkIdType i = 0; i < n1 + n2; ++i)
  {
    const double* p = i < n1 ? first.data() + 3 * i : second.data() + width * (i - n1);
    double x[3] = { p[0], p[1], p[2] };
    joined->SetPoint(i, x);
    box.AddPoint(x);
  }
  return vtkBeltramiGather::CoincidentPoints(joined, 1e-12 * box.GetDiagonalLength());
}

} // namespace

namespace
{

/// Every rank's `mine` (`width` values per point, the first 3 its
/// coordinates) appended in rank order; owner[k] is the rank of point k.
std::vector<double> GatherPoints(
  vtkMultiProcessController* controller, const std::vector<double>& mine, int width, std::vector<int>& owner)
{
  std::vector<vtkIdType> offsets;
  std::vector<double> all = vtkBeltramiSurface::AllGather(controller, mine, offsets);
  owner.clear();
  for (std::size_t r = 0; r + 1 < offsets.size(); ++r)
  {
    owner.insert(owner.end(), static_cast<std::size_t>((offsets[r + 1] - offsets[r]) / width), static_cast<int>(r));
  }
  return all;
}

} // namespace

bool vtkBeltramiSurface::BuildPartition(vtkMultiProcessController* controller)
{
  const int rank = controller->GetLocalProcessId();
  const Index rows = Mesh->NumberOfVertices();
  const Index pieceRows = std::min<Index>(rows, InputData ? static_cast<Index>(InputData->GetNumberOfPoints()) : 0);
  const auto coordinates = [&](const std::vector<Index>& points, bool withRow) {
    std::vector<double> values;
    for (Index v : points)
    {
      const double x[4] = { Floats ? Floats[3 * v] : Doubles[3 * v], Floats ? Floats[3 * v + 1] : Doubles[3 * v + 1],
        Floats ? Floats[3 * v + 2] : Doubles[3 * v + 2], static_cast<double>(v) };
      values.insert(values.end(), x, x + (withRow ? 4 : 3));
    }
    return values;
  };
  // 1. A point on the edges of several pieces belongs to the lowest rank
  //    among them; every other point of a piece to its own rank.
  std::vector<int> ownerRank(static_cast<std::size_t>(rows), rank), edgeRank;
  std::vector<Index> ownerRow(static_cast<std::size_t>(rows));
  for (Index i = 0; i < rows; ++i)
  {
    ownerRow[i] = i;
  }
  const std::vector<double> edges = GatherPoints(controller, coordinates(EdgeVertices, false), 3, edgeRank);
  const std::vector<vtkIdType> edgeClass = MatchPoints({}, edges, 3);
  std::vector<int> lowest(edgeClass.size(), std::numeric_limits<int>::max());
  for (std::size_t k = 0; k < edgeClass.size(); ++k)
  {
    lowest[edgeClass[k]] = std::min(lowest[edgeClass[k]], edgeRank[k]);
  }
  const std::size_t mineAt = std::find(edgeRank.begin(), edgeRank.end(), rank) - edgeRank.begin();
  for (std::size_t k = 0; k < EdgeVertices.size(); ++k)
  {
    ownerRank[EdgeVertices[k]] = lowest[edgeClass[mineAt + k]];
  }
  // 2. Each rank offers its own points among the corners of the triangles it
  //    gave the others (every point another rank holds as a ghost is one).
  std::vector<Index> offered;
  for (Index v : OfferedPoints)
  {
    if (ownerRank[v] == rank)
    {
      offered.push_back(v);
    }
  }
  std::vector<int> offeredRank;
  const std::vector<double> owned = GatherPoints(controller, coordinates(offered, true), 4, offeredRank);
  // 3. The points this rank does not own (shared edge points, the rings'
  //    points) find their owner and its row there.
  std::vector<Index> foreign;
  for (Index i = 0; i < rows; ++i)
  {
    if (i >= pieceRows || ownerRank[i] != rank)
    {
      foreign.push_back(i);
      ownerRank[i] = -1;
    }
  }
  const std::vector<vtkIdType> match = MatchPoints(coordinates(foreign, false), owned, 4);
  const vtkIdType queries = static_cast<vtkIdType>(foreign.size());
  std::vector<vtkIdType> ownerOf(match.size(), -1); // per class: the offered point in it
  for (vtkIdType k = queries; k < static_cast<vtkIdType>(match.size()); ++k)
  {
    if (offeredRank[k - queries] != rank)
    {
      ownerOf[match[k]] = k - queries;
    }
  }
  for (vtkIdType q = 0; q < queries; ++q)
  {
    const vtkIdType o = ownerOf[match[q]];
    if (o >= 0)
    {
      ownerRank[foreign[q]] = offeredRank[o];
      ownerRow[foreign[q]] = static_cast<Index>(owned[4 * o + 3]);
    }
  }
  vtkMPICommunicator* communicator = vtkMPICommunicator::SafeDownCast(controller->GetCommunicator());
  try
  {
    SplitRows = std::make_unique<beltrami::Partition>(
      communicator->GetMPIComm()->GetHandle(), rows, ownerRank.data(), ownerRow.data());
  }
  catch (const std::exception& e)
  {
    ErrorText = e.what();
    return false;
  }
  return true;
}
