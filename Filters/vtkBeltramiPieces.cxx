#include "vtkBeltramiPieces.h"

#include "vtkBeltramiGather.h"
#include "vtkBeltramiSurface.h"

#include <vtkBoundingBox.h>
#include <vtkCommunicator.h>
#include <vtkDataSet.h>
#include <vtkDataSetAttributes.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkMPI.h>
#include <vtkMPICommunicator.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>

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
  // (No points at all, e.g. pieces that touch nowhere: an empty box.)
  return vtkBeltramiGather::CoincidentPoints(joined, box.IsValid() ? 1e-12 * box.GetDiagonalLength() : 0.0);
}

/// Every rank's `mine` (`width` values per point, the first 3 its
/// coordinates) appended in rank order; owner[k] is the rank of point k.
std::vector<double> GatherPoints(
  vtkMultiProcessController* controller, const std::vector<double>& mine, int width, std::vector<int>& owner)
{
  std::vector<vtkIdType> offsets;
  std::vector<double> all = vtkBeltramiPieces::AllGather(controller, mine, offsets);
  owner.clear();
  for (std::size_t r = 0; r + 1 < offsets.size(); ++r)
  {
    owner.insert(owner.end(), static_cast<std::size_t>((offsets[r + 1] - offsets[r]) / width), static_cast<int>(r));
  }
  return all;
}

/// The coordinates of `points` (and their index after them, withIndex).
std::vector<double> CoordinatesOf(
  const std::vector<Index>& points, const vtkBeltramiPieces::Coordinates& point, bool withIndex)
{
  std::vector<double> values;
  values.reserve(points.size() * (withIndex ? 4 : 3));
  for (Index v : points)
  {
    double x[4] = { 0.0, 0.0, 0.0, static_cast<double>(v) };
    point(v, x);
    values.insert(values.end(), x, x + (withIndex ? 4 : 3));
  }
  return values;
}

} // namespace

std::vector<double> vtkBeltramiPieces::AllGather(
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

bool vtkBeltramiPieces::CanSolveTogether(vtkInformation* outInfo)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  return vtkBeltramiSurface::OnePiecePerRank(outInfo) &&
    vtkMPICommunicator::SafeDownCast(controller->GetCommunicator()) != nullptr;
}

bool vtkBeltramiPieces::RingsAreMissing(vtkDataSet* input)
{
  const bool hasPoints = input && input->GetNumberOfPoints() > 0;
  bool hasGhosts = false; // duplicate cells (a ghost array of zeros is no ghost layer)
  if (vtkUnsignedCharArray* ghosts = input ? input->GetCellGhostArray() : nullptr)
  {
    const unsigned char* flags = ghosts->GetPointer(0);
    hasGhosts = std::any_of(flags, flags + ghosts->GetNumberOfValues(),
      [](unsigned char f) { return (f & vtkDataSetAttributes::DUPLICATECELL) != 0; });
  }
  int local[2] = { hasPoints && !hasGhosts ? 1 : 0, hasGhosts ? 1 : 0 };
  int global[2] = { 0, 0 };
  vtkMultiProcessController::GetGlobalController()->AllReduce(local, global, 2, vtkCommunicator::SUM_OP);
  return global[0] > 0 && global[1] == 0;
}

bool vtkBeltramiPieces::AddRings(int corners, Index numberOfPoints, const Coordinates& point,
  const std::vector<std::uint8_t>& edge, std::vector<Index>& cells, Stars stars)
{
  // The offer: every cell at a point that other pieces hold too (and need
  // the star of: with Stars::Owned, the points this rank does not own), as
  // its corners' coordinates.  Every piece so gets the whole star of its
  // shared points - also from a piece that touches it at that point only.
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const int rank = controller->GetLocalProcessId();
  OfferedPoints.clear();
  Ghosts.clear();
  FindSharedPoints(numberOfPoints, point, edge);
  std::vector<std::uint8_t> shared(static_cast<std::size_t>(numberOfPoints), 0);
  for (std::size_t k = 0; k < EdgePoints.size(); ++k)
  {
    shared[EdgePoints[k]] = stars == Stars::All || EdgeOwners[k] != rank;
  }
  const std::size_t numCells = cells.size() / corners;
  std::vector<std::uint8_t> corner(static_cast<std::size_t>(numberOfPoints), 0);
  std::vector<double> offer;
  for (std::size_t c = 0; c < numCells; ++c)
  {
    const Index* ids = cells.data() + c * corners;
    if (std::any_of(ids, ids + corners, [&](Index v) { return shared[v] != 0; }))
    {
      for (int k = 0; k < corners; ++k)
      {
        double x[3];
        point(ids[k], x);
        offer.insert(offer.end(), x, x + 3);
        corner[ids[k]] = 1;
      }
    }
  }
  for (Index v : EdgePoints)
  {
    corner[v] = 1; // (the owners of shared points offer them in BuildPartition)
  }
  for (Index v = 0; v < numberOfPoints; ++v)
  {
    if (corner[v])
    {
      OfferedPoints.push_back(v);
    }
  }
  std::vector<vtkIdType> offsets;
  std::vector<double> offers = AllGather(controller, offer, offsets);
  offers.erase(offers.begin() + offsets[rank], offers.begin() + offsets[rank + 1]); // the others' only
  Cells = static_cast<std::int64_t>(numCells);
  if (EdgePoints.empty() || offers.empty())
  {
    return false; // nothing to join (this piece has no edge, or no other piece offers)
  }
  // Join this piece's edge points and the other pieces' corners, their
  // copies of common points merged.
  const std::vector<double> own = CoordinatesOf(EdgePoints, point, false);
  const std::vector<vtkIdType> merged = MatchPoints(own, offers, 3);
  const std::size_t numOwn = EdgePoints.size();
  // Per class: the piece's point it stands for, or a new ghost point; and
  // whether this piece needs the star of that point.
  std::vector<vtkIdType> pointOf(merged.size(), -1);
  std::vector<std::uint8_t> needed(merged.size(), 0);
  for (std::size_t i = 0; i < numOwn; ++i)
  {
    pointOf[merged[i]] = EdgePoints[i];
    needed[merged[i]] = stars == Stars::All || EdgeOwners[i] == rank;
  }
  const std::size_t offered = offers.size() / (3 * corners);
  const std::size_t kept = cells.size();
  // A cell held already (one that several pieces hold, ShareCopiedCells)
  // or offered twice is joined once: cells as the sorted classes of their
  // corners (the piece's cells whose corners are all edge points).
  std::vector<vtkIdType> classOf(static_cast<std::size_t>(numberOfPoints), -1);
  for (std::size_t i = 0; i < numOwn; ++i)
  {
    classOf[EdgePoints[i]] = merged[i];
  }
  std::set<std::array<vtkIdType, 4>> held;
  const auto keyOf = [corners](const auto& at) {
    std::array<vtkIdType, 4> key = { -1, -1, -1, -1 };
    for (int k = 0; k < corners; ++k)
    {
      key[k] = at(k);
    }
    std::sort(key.begin(), key.begin() + corners);
    return key;
  };
  for (std::size_t c = 0; c < numCells; ++c)
  {
    const Index* ids = cells.data() + c * corners;
    if (std::all_of(ids, ids + corners, [&](Index v) { return classOf[v] >= 0; }))
    {
      held.insert(keyOf([&](int k) { return classOf[ids[k]]; }));
    }
  }
  for (std::size_t c = 0; c < offered; ++c)
  {
    const vtkIdType* m = merged.data() + numOwn + c * corners;
    if (std::none_of(m, m + corners, [&](vtkIdType k) { return needed[k] != 0; }) ||
      !held.insert(keyOf([m](int k) { return m[k]; })).second)
    {
      continue; // not at a point of this piece whose star it needs, or held already
    }
    for (int k = 0; k < corners; ++k)
    {
      if (pointOf[m[k]] < 0)
      {
        pointOf[m[k]] = numberOfPoints + static_cast<vtkIdType>(Ghosts.size() / 3);
        const double* x = offers.data() + 3 * (c * corners + k);
        Ghosts.insert(Ghosts.end(), x, x + 3);
      }
      cells.push_back(static_cast<Index>(pointOf[m[k]]));
    }
  }
  Cells = static_cast<std::int64_t>(cells.size() / corners);
  return cells.size() > kept;
}

void vtkBeltramiPieces::FindSharedPoints(
  Index numberOfPoints, const Coordinates& point, const std::vector<std::uint8_t>& edge)
{
  // The candidates of all ranks matched: a candidate that another rank
  // holds too is shared, and belongs to the lowest rank holding it.
  const std::vector<Index> candidates = SharedCandidates(numberOfPoints, point, edge);
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const int rank = controller->GetLocalProcessId();
  std::vector<int> holder;
  const std::vector<double> all = GatherPoints(controller, CoordinatesOf(candidates, point, false), 3, holder);
  const std::vector<vtkIdType> classes = MatchPoints({}, all, 3);
  std::vector<int> lowest(classes.size(), std::numeric_limits<int>::max());
  std::vector<int> holders(classes.size(), 0);
  for (std::size_t k = 0; k < classes.size(); ++k)
  {
    lowest[classes[k]] = std::min(lowest[classes[k]], holder[k]);
    ++holders[classes[k]];
  }
  const std::size_t mineAt = std::find(holder.begin(), holder.end(), rank) - holder.begin();
  EdgePoints.clear();
  EdgeOwners.clear();
  for (std::size_t k = 0; k < candidates.size(); ++k)
  {
    const vtkIdType c = classes[mineAt + k];
    if (holders[c] > 1)
    {
      EdgePoints.push_back(candidates[k]);
      EdgeOwners.push_back(lowest[c]);
    }
  }
}

std::vector<vtkBoundingBox> vtkBeltramiPieces::OtherBoxes(Index numberOfPoints, const Coordinates& point)
{
  // The pieces' bounding boxes (an empty piece's is invalid), grown by far
  // more than the tolerance of the matching of common points.
  vtkBoundingBox box;
  for (Index v = 0; v < numberOfPoints; ++v)
  {
    double x[3];
    point(v, x);
    box.AddPoint(x);
  }
  std::vector<double> mine(6, 0.0);
  if (box.IsValid())
  {
    box.GetBounds(mine.data());
  }
  else
  {
    mine = { 1.0, -1.0, 1.0, -1.0, 1.0, -1.0 };
  }
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  std::vector<vtkIdType> offsets;
  const std::vector<double> bounds = AllGather(controller, mine, offsets);
  const int rank = controller->GetLocalProcessId();
  vtkBoundingBox all;
  std::vector<vtkBoundingBox> others;
  for (std::size_t r = 0; r < bounds.size() / 6; ++r)
  {
    vtkBoundingBox b(bounds.data() + 6 * r);
    all.AddBox(b);
    if (static_cast<int>(r) != rank && b.IsValid())
    {
      others.push_back(b);
    }
  }
  const double margin = all.IsValid() ? 1e-9 * all.GetDiagonalLength() : 0.0;
  for (vtkBoundingBox& b : others)
  {
    b.Inflate(margin);
  }
  return others;
}

std::vector<Index> vtkBeltramiPieces::SharedCandidates(
  Index numberOfPoints, const Coordinates& point, const std::vector<std::uint8_t>& edge) const
{
  const std::vector<vtkBoundingBox> others = OtherBoxes(numberOfPoints, point);
  std::vector<Index> candidates;
  for (Index v = 0; v < numberOfPoints; ++v)
  {
    double x[3];
    point(v, x);
    if (edge[v] && std::any_of(others.begin(), others.end(), [&x](const vtkBoundingBox& b) { return b.ContainsPoint(x); }))
    {
      candidates.push_back(v);
    }
  }
  return candidates;
}

void vtkBeltramiPieces::RepeatedCells(int corners, const std::vector<Index>& cells, std::vector<std::uint8_t>& repeated,
  const std::function<bool(Index)>& suspect)
{
  std::vector<std::pair<std::array<Index, 4>, std::size_t>> keys;
  for (std::size_t c = 0; c < cells.size() / corners; ++c)
  {
    std::array<Index, 4> key = { -1, -1, -1, -1 };
    std::copy_n(cells.begin() + c * corners, corners, key.begin());
    if (!suspect || std::all_of(key.begin(), key.begin() + corners, suspect))
    {
      std::sort(key.begin(), key.begin() + corners);
      keys.emplace_back(key, c);
    }
  }
  std::sort(keys.begin(), keys.end());
  for (std::size_t k = 1; k < keys.size(); ++k)
  {
    if (keys[k].first == keys[k - 1].first)
    {
      repeated[keys[k].second] = 1; // (the first of equal ones stays)
    }
  }
}

void vtkBeltramiPieces::ShareCopiedCells(int corners, Index numberOfPoints, const Coordinates& point,
  const std::vector<Index>& cells, std::vector<std::uint8_t>& edge) const
{
  // Candidates: cells at the edge of the piece with every corner in another
  // piece's box (a cell copied to two pieces reaches beyond the cut in both,
  // so it has a corner at the edge of each).  Key: the centroid of the
  // corners in sorted order (matched), then the sorted corners (compared).
  const std::vector<vtkBoundingBox> others = OtherBoxes(numberOfPoints, point);
  const int width = 3 + 3 * corners;
  std::vector<double> keys, centroids;
  std::vector<std::size_t> which;
  const std::size_t numCells = cells.size() / corners;
  for (std::size_t c = 0; c < numCells; ++c)
  {
    const Index* ids = cells.data() + c * corners;
    if (std::none_of(ids, ids + corners, [&edge](Index v) { return edge[v] != 0; }))
    {
      continue; // (most cells: nothing to look up)
    }
    std::array<std::array<double, 3>, 4> x; // (corners <= 4: triangles, tetrahedra)
    bool inside = true;
    for (int k = 0; k < corners; ++k)
    {
      point(ids[k], x[k].data());
      inside = inside &&
        std::any_of(others.begin(), others.end(), [&](const vtkBoundingBox& b) { return b.ContainsPoint(x[k].data()); });
    }
    if (!inside)
    {
      continue;
    }
    std::sort(x.begin(), x.begin() + corners);
    double centroid[3] = { 0.0, 0.0, 0.0 };
    for (int k = 0; k < corners; ++k)
    {
      for (int a = 0; a < 3; ++a)
      {
        centroid[a] += x[k][a] / corners;
      }
    }
    keys.insert(keys.end(), centroid, centroid + 3);
    centroids.insert(centroids.end(), centroid, centroid + 3);
    for (int k = 0; k < corners; ++k)
    {
      keys.insert(keys.end(), x[k].begin(), x[k].end());
    }
    which.push_back(c);
  }
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const int rank = controller->GetLocalProcessId();
  std::vector<int> holder;
  const std::vector<double> all = GatherPoints(controller, keys, width, holder);
  const std::vector<vtkIdType> classes = MatchPoints(centroids, all, width);
  const vtkIdType queries = static_cast<vtkIdType>(which.size());
  std::vector<std::vector<vtkIdType>> elsewhere(classes.size()); // per class: the other ranks' cells in it
  for (vtkIdType j = 0; j < static_cast<vtkIdType>(holder.size()); ++j)
  {
    if (holder[j] != rank)
    {
      elsewhere[classes[queries + j]].push_back(j);
    }
  }
  for (vtkIdType q = 0; q < queries; ++q)
  {
    const double* mine = keys.data() + width * q + 3;
    const auto& there = elsewhere[classes[q]];
    if (std::any_of(there.begin(), there.end(),
          [&](vtkIdType j) { return std::equal(mine, mine + 3 * corners, all.data() + width * j + 3); }))
    {
      for (int k = 0; k < corners; ++k)
      {
        edge[cells[which[q] * corners + k]] = 1;
      }
    }
  }
}

bool vtkBeltramiPieces::BuildPartition(Index rows, Index pieceRows, const Coordinates& point, std::string& error)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const int rank = controller->GetLocalProcessId();
  // 1. A point that several pieces share belongs to the lowest rank among
  //    them (AddRings); every other point of a piece to its own rank.
  std::vector<int> ownerRank(static_cast<std::size_t>(rows), rank);
  std::vector<Index> ownerRow(static_cast<std::size_t>(rows));
  for (Index i = 0; i < rows; ++i)
  {
    ownerRow[i] = i;
  }
  for (std::size_t k = 0; k < EdgePoints.size(); ++k)
  {
    ownerRank[EdgePoints[k]] = EdgeOwners[k];
  }
  // 2. Each rank offers its own points among the corners of the cells it
  //    gave the others and its shared points (every point another rank
  //    holds as a ghost is one).
  std::vector<Index> offered;
  for (Index v : OfferedPoints)
  {
    if (ownerRank[v] == rank)
    {
      offered.push_back(v);
    }
  }
  std::vector<int> offeredRank;
  const std::vector<double> owned = GatherPoints(controller, CoordinatesOf(offered, point, true), 4, offeredRank);
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
  const std::vector<vtkIdType> match = MatchPoints(CoordinatesOf(foreign, point, false), owned, 4);
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
  return MakeRows(rows, ownerRank, ownerRow, error);
}

bool vtkBeltramiPieces::BuildGridPartition(const int* inExt, const int* outExt, std::string& error)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const int ranks = controller->GetNumberOfProcesses();
  int mine[12];
  std::copy(outExt, outExt + 6, mine);
  std::copy(inExt, inExt + 6, mine + 6);
  std::vector<int> all(12 * static_cast<std::size_t>(ranks));
  controller->AllGather(mine, all.data(), 12);
  const auto empty = [](const int* e) { return e[1] < e[0] || e[3] < e[2] || e[5] < e[4]; };
  const auto size = [&](const int* e, int a) { return empty(e) ? 0 : e[2 * a + 1] - e[2 * a] + 1; };
  const Index rows = static_cast<Index>(std::int64_t(size(inExt, 0)) * size(inExt, 1) * size(inExt, 2));
  Cells = 1; // the cells of the extent (pixels or voxels)
  for (int a = 0; a < 3; ++a)
  {
    Cells *= size(inExt, a) > 1 ? size(inExt, a) - 1 : size(inExt, a);
  }
  std::vector<int> ownerRank;
  std::vector<Index> ownerRow;
  ownerRank.reserve(rows);
  ownerRow.reserve(rows);
  std::vector<int> holders; // per row of samples: the ranks whose piece holds the row
  for (int k = inExt[4]; rows > 0 && error.empty() && k <= inExt[5]; ++k)
  {
    for (int j = inExt[2]; error.empty() && j <= inExt[3]; ++j)
    {
      holders.clear();
      for (int r = 0; r < ranks; ++r)
      {
        const int* e = &all[12 * r];
        if (!empty(e) && j >= e[2] && j <= e[3] && k >= e[4] && k <= e[5])
        {
          holders.push_back(r); // (in rank order: the first that holds a sample owns it)
        }
      }
      for (int i = inExt[0]; i <= inExt[1]; ++i)
      {
        const auto owner = std::find_if(holders.begin(), holders.end(), [&](int r) {
          return i >= all[12 * r] && i <= all[12 * r + 1];
        });
        if (owner == holders.end())
        {
          error = "the sample (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
            ") of this rank's input is in no rank's piece";
          break;
        }
        const int* in = &all[12 * *owner + 6];
        ownerRank.push_back(*owner);
        ownerRow.push_back(static_cast<Index>(
          (std::int64_t(k - in[4]) * size(in, 1) + (j - in[2])) * size(in, 0) + (i - in[0])));
      }
    }
  }
  if (!AllAgree(error.empty()))
  {
    error = error.empty() ? "another rank's input has samples in no rank's piece" : error;
    return false;
  }
  return MakeRows(rows, ownerRank, ownerRow, error);
}

bool vtkBeltramiPieces::MakeRows(
  Index rows, const std::vector<int>& ownerRank, const std::vector<Index>& ownerRow, std::string& error)
{
  vtkMPICommunicator* communicator =
    vtkMPICommunicator::SafeDownCast(vtkMultiProcessController::GetGlobalController()->GetCommunicator());
  try
  {
    Rows = std::make_shared<beltrami::Partition>(
      communicator->GetMPIComm()->GetHandle(), rows, ownerRank.data(), ownerRow.data());
  }
  catch (const std::exception& e)
  {
    error = e.what();
    Rows.reset();
    return false;
  }
  return true;
}

bool vtkBeltramiPieces::AllAgree(bool ok) const
{
  if (!Collective)
  {
    return ok;
  }
  int local = ok ? 1 : 0, all = 0;
  vtkMultiProcessController::GetGlobalController()->AllReduce(&local, &all, 1, vtkCommunicator::MIN_OP);
  return all == 1;
}

void vtkBeltramiPieces::AddDistribution(vtkFieldData* fd, const char* name) const
{
  const beltrami::Partition* rows = Split();
  vtkNew<vtkIdTypeArray> distribution;
  distribution->SetName(name);
  for (const std::int64_t count : { std::int64_t(rows->OwnedRows()), std::int64_t(rows->Rows() - rows->OwnedRows()),
         NumberOfCells(), rows->SentPerUpdate() })
  {
    distribution->InsertNextValue(count);
  }
  fd->AddArray(distribution);
}
