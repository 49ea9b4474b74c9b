#include "vtkBeltramiGather.h"

#include "vtkBeltramiSurface.h"

#include <vtkBoundingBox.h>
#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPointSet.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStaticPointLocator.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

namespace
{

constexpr int PieceTag = 731001;
constexpr int ResultTag = 731002;
const char* const LocalCellIds = "vtkBeltramiGather::CellIds";
const char* const PieceCells = "vtkBeltramiGather::NumberOfCells";
// A part of the results is one field data (a data set's point and cell data
// do not survive the transfer when it has no points or cells), sent by
// SendPart:
const char* const Status = "vtkBeltramiGather::Status";
const char* const Removed = "vtkBeltramiGather::RemovedPointArrays";
const char* const Attributes = "vtkBeltramiGather::PointAttributes"; // "type:name"
const char* const Coordinates = "vtkBeltramiGather::Coordinates";
const std::string PointPrefix = "vtkBeltramiGather::Point::";
const std::string CellPrefix = "vtkBeltramiGather::Cell::";

const char* const RawArrays = "vtkBeltramiGather::RawArrays"; // "type:name", sent after

bool StartsWith(const std::string& s, const std::string& prefix)
{
  return s.compare(0, prefix.size(), prefix) == 0;
}

/// Sends a part to rank `to`: its small arrays in one data object, the
/// per-point and per-cell arrays raw after it (a data object's field data
/// travels as text: 0.3 s for the parts of a 179k-vertex surface).
void SendPart(vtkMultiProcessController* controller, vtkFieldData* part, int to)
{
  vtkNew<vtkPolyData> small;
  vtkNew<vtkStringArray> raw;
  raw->SetName(RawArrays);
  std::vector<vtkDataArray*> arrays;
  for (int a = 0; a < part->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = part->GetAbstractArray(a);
    const std::string name = array->GetName() ? array->GetName() : "";
    vtkDataArray* data = vtkDataArray::SafeDownCast(array);
    if (data && (StartsWith(name, PointPrefix) || StartsWith(name, CellPrefix) || name == Coordinates))
    {
      raw->InsertNextValue(std::to_string(data->GetDataType()) + ":" + name);
      arrays.push_back(data);
    }
    else
    {
      small->GetFieldData()->AddArray(array);
    }
  }
  small->GetFieldData()->AddArray(raw);
  controller->Send(small, to, ResultTag);
  for (vtkDataArray* data : arrays)
  {
    controller->Send(data, to, ResultTag + 1);
  }
}

/// The part SendPart sent from rank `from`, as one field data.
vtkSmartPointer<vtkFieldData> ReceivePart(vtkMultiProcessController* controller, int from)
{
  vtkNew<vtkPolyData> small;
  controller->Receive(small, from, ResultTag);
  auto part = vtkSmartPointer<vtkFieldData>::New();
  vtkStringArray* raw = nullptr;
  for (int a = 0; a < small->GetFieldData()->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = small->GetFieldData()->GetAbstractArray(a);
    if (array->GetName() && std::string(array->GetName()) == RawArrays)
    {
      raw = vtkStringArray::SafeDownCast(array);
    }
    else
    {
      part->AddArray(array);
    }
  }
  for (vtkIdType k = 0; raw && k < raw->GetNumberOfValues(); ++k)
  {
    const std::string entry = raw->GetValue(k);
    const std::size_t colon = entry.find(':');
    auto data = vtk::TakeSmartPointer(vtkDataArray::CreateDataArray(std::stoi(entry.substr(0, colon))));
    controller->Receive(data, from, ResultTag + 1);
    data->SetName(entry.substr(colon + 1).c_str());
    part->AddArray(data);
  }
  return part;
}

/// `source`'s tuples at `ids` (-1: NaN) as a new array of its type and name.
vtkSmartPointer<vtkDataArray> Pick(vtkDataArray* source, const std::vector<vtkIdType>& ids)
{
  auto picked = vtk::TakeSmartPointer(source->NewInstance());
  picked->SetName(source->GetName());
  picked->SetNumberOfComponents(source->GetNumberOfComponents());
  picked->SetNumberOfTuples(static_cast<vtkIdType>(ids.size()));
  for (std::size_t k = 0; k < ids.size(); ++k)
  {
    if (ids[k] >= 0)
    {
      picked->SetTuple(static_cast<vtkIdType>(k), ids[k], source);
    }
    else
    {
      for (int c = 0; c < source->GetNumberOfComponents(); ++c)
      {
        picked->SetComponent(static_cast<vtkIdType>(k), c, std::nan(""));
      }
    }
  }
  return picked;
}

/// Puts a part that Distribute built into `output`; false when rank 0 failed.
bool Apply(vtkFieldData* part, vtkPointSet* output)
{
  vtkDataArray* status = part->GetArray(Status);
  if (!status || status->GetTuple1(0) == 0.0)
  {
    return false;
  }
  vtkPointData* pd = output->GetPointData();
  if (auto* removed = vtkStringArray::SafeDownCast(part->GetAbstractArray(Removed)))
  {
    for (vtkIdType k = 0; k < removed->GetNumberOfValues(); ++k)
    {
      pd->RemoveArray(removed->GetValue(k).c_str());
    }
  }
  vtkNew<vtkFieldData> own;
  for (int a = 0; a < part->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = part->GetAbstractArray(a);
    const std::string name = array->GetName() ? array->GetName() : "";
    if (StartsWith(name, PointPrefix) || StartsWith(name, CellPrefix))
    {
      const bool point = StartsWith(name, PointPrefix);
      auto copy = vtk::TakeSmartPointer(array->NewInstance());
      if (auto* data = vtkDataArray::SafeDownCast(array))
      {
        vtkDataArray::SafeDownCast(copy)->ShallowCopy(data);
      }
      else
      {
        copy->DeepCopy(array);
      }
      copy->SetName(name.substr((point ? PointPrefix : CellPrefix).size()).c_str());
      if (point)
      {
        pd->AddArray(copy);
      }
      else
      {
        output->GetCellData()->AddArray(copy);
      }
    }
    else if (name == Coordinates)
    {
      vtkNew<vtkPoints> points;
      points->SetData(vtkDataArray::SafeDownCast(array));
      output->SetPoints(points);
    }
    else if (name != Status && name != Removed && name != Attributes)
    {
      own->AddArray(array);
    }
  }
  if (auto* attributes = vtkStringArray::SafeDownCast(part->GetAbstractArray(Attributes)))
  {
    for (vtkIdType k = 0; k < attributes->GetNumberOfValues(); ++k)
    {
      const std::string entry = attributes->GetValue(k);
      const std::size_t colon = entry.find(':');
      pd->SetActiveAttribute(entry.substr(colon + 1).c_str(), std::stoi(entry.substr(0, colon)));
    }
  }
  output->SetFieldData(own);
  return true;
}

/// `input`'s cells without its ghost cells into `piece` (same type), the
/// kept cells' ids into `cellIds`.
void CopyCells(vtkPointSet* input, vtkPointSet* piece, vtkIdTypeArray* cellIds)
{
  vtkUnsignedCharArray* ghosts = input->GetCellGhostArray();
  const auto kept = [ghosts](vtkIdType cell) {
    return !ghosts || !(ghosts->GetValue(cell) & vtkDataSetAttributes::DUPLICATECELL);
  };
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(input))
  {
    auto* out = vtkUnstructuredGrid::SafeDownCast(piece);
    out->Allocate(grid->GetNumberOfCells());
    vtkNew<vtkIdList> ids;
    for (vtkIdType cell = 0; cell < grid->GetNumberOfCells(); ++cell)
    {
      if (kept(cell))
      {
        grid->GetCellPoints(cell, ids);
        out->InsertNextCell(grid->GetCellType(cell), ids);
        cellIds->InsertNextValue(cell);
      }
    }
    return;
  }
  auto* poly = vtkPolyData::SafeDownCast(input);
  auto* out = vtkPolyData::SafeDownCast(piece);
  vtkCellArray* from[4] = { poly->GetVerts(), poly->GetLines(), poly->GetPolys(), poly->GetStrips() };
  vtkNew<vtkCellArray> to[4];
  vtkIdType cell = 0; // vtkPolyData numbers verts, lines, polys, strips in turn
  for (int c = 0; c < 4; ++c)
  {
    auto it = vtk::TakeSmartPointer(from[c]->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cell)
    {
      if (kept(cell))
      {
        vtkIdType n = 0;
        const vtkIdType* ids = nullptr;
        it->GetCurrentCell(n, ids);
        to[c]->InsertNextCell(n, ids);
        cellIds->InsertNextValue(cell);
      }
    }
  }
  out->SetVerts(to[0]);
  out->SetLines(to[1]);
  out->SetPolys(to[2]);
  out->SetStrips(to[3]);
}

/// The pieces' cells, their point ids mapped by `pointIds`, appended into
/// `whole` in the pieces' order; for every piece, its cells' ids in `whole`.
std::vector<std::vector<vtkIdType>> AppendCells(const std::vector<vtkSmartPointer<vtkPointSet>>& pieces,
  const std::vector<std::vector<vtkIdType>>& pointIds, vtkPointSet* whole)
{
  std::vector<std::vector<vtkIdType>> placed(pieces.size());
  std::vector<vtkIdType> ids;
  const auto map = [&](std::size_t r, vtkIdType n, const vtkIdType* local) {
    ids.resize(static_cast<std::size_t>(n));
    for (vtkIdType j = 0; j < n; ++j)
    {
      ids[j] = pointIds[r][local[j]];
    }
  };
  // A cell that several pieces hold (copied to every piece it touches, not
  // marked as a ghost: RedistributeDataSet's "Assign to all regions", also
  // within a rank that holds two of its regions) is joined once; its copies
  // get the results of the first.
  std::map<std::pair<int, std::vector<vtkIdType>>, std::pair<std::size_t, std::size_t>> first;
  const auto copyOf = [&](int kind, std::size_t r) -> const std::pair<std::size_t, std::size_t>* {
    std::vector<vtkIdType> key(ids);
    std::sort(key.begin(), key.end());
    const auto found = first.emplace(std::make_pair(kind, std::move(key)), std::make_pair(r, placed[r].size()));
    return found.second ? nullptr : &found.first->second;
  };
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(whole))
  {
    grid->Allocate(1024);
    vtkNew<vtkIdList> local;
    for (std::size_t r = 0; r < pieces.size(); ++r)
    {
      auto* piece = vtkUnstructuredGrid::SafeDownCast(pieces[r]);
      for (vtkIdType cell = 0; piece && cell < piece->GetNumberOfCells(); ++cell)
      {
        piece->GetCellPoints(cell, local);
        map(r, local->GetNumberOfIds(), local->GetPointer(0));
        const auto* copy = copyOf(piece->GetCellType(cell), r);
        placed[r].push_back(copy ? placed[copy->first][copy->second]
                                 : grid->InsertNextCell(piece->GetCellType(cell), local->GetNumberOfIds(), ids.data()));
      }
    }
    return placed;
  }
  vtkNew<vtkCellArray> cells[4];
  std::vector<std::vector<std::pair<int, vtkIdType>>> kindAndIndex(pieces.size());
  for (std::size_t r = 0; r < pieces.size(); ++r)
  {
    auto* p = vtkPolyData::SafeDownCast(pieces[r]);
    vtkCellArray* from[4] = { p->GetVerts(), p->GetLines(), p->GetPolys(), p->GetStrips() };
    for (int c = 0; c < 4; ++c)
    {
      auto it = vtk::TakeSmartPointer(from[c]->NewIterator());
      for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
      {
        vtkIdType n = 0;
        const vtkIdType* local = nullptr;
        it->GetCurrentCell(n, local);
        map(r, n, local);
        const auto* copy = copyOf(c, r);
        placed[r].push_back(0); // (counts the piece's cells for copyOf; the whole ids follow below)
        kindAndIndex[r].push_back(copy ? kindAndIndex[copy->first][copy->second]
                                       : std::make_pair(c, cells[c]->GetNumberOfCells()));
        if (!copy)
        {
          cells[c]->InsertNextCell(n, ids.data());
        }
      }
    }
  }
  auto* poly = vtkPolyData::SafeDownCast(whole);
  poly->SetVerts(cells[0]);
  poly->SetLines(cells[1]);
  poly->SetPolys(cells[2]);
  poly->SetStrips(cells[3]);
  vtkIdType offset[4] = { 0, cells[0]->GetNumberOfCells(), 0, 0 };
  offset[2] = offset[1] + cells[1]->GetNumberOfCells();
  offset[3] = offset[2] + cells[2]->GetNumberOfCells();
  for (std::size_t r = 0; r < pieces.size(); ++r)
  {
    placed[r].clear();
    for (const auto& kind : kindAndIndex[r])
    {
      placed[r].push_back(offset[kind.first] + kind.second);
    }
  }
  return placed;
}

} // namespace

std::vector<vtkIdType> vtkBeltramiGather::CoincidentPoints(vtkPoints* points, double tolerance)
{
  const vtkIdType n = points ? points->GetNumberOfPoints() : 0;
  std::vector<vtkIdType> merged(static_cast<std::size_t>(n));
  if (n == 0)
  {
    return merged;
  }
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(points);
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(cloud);
  locator->BuildLocator();
  locator->MergePoints(tolerance, merged.data());
  for (vtkIdType i = 0; i < n; ++i)
  {
    vtkIdType rep = merged[i];
    while (merged[rep] != rep) // representatives map to themselves
    {
      rep = merged[rep];
    }
    merged[i] = rep;
  }
  return merged;
}

namespace
{

/// This rank's piece as sent to rank 0: its points and point arrays, its
/// cells without the ghost cells, the kept cells' ids and its cell count.
vtkSmartPointer<vtkPointSet> PieceToSend(vtkPointSet* input)
{
  auto piece = vtk::TakeSmartPointer(input->NewInstance());
  vtkNew<vtkIdTypeArray> cellIds;
  cellIds->SetName(LocalCellIds);
  if (input->GetNumberOfPoints() > 0)
  {
    piece->SetPoints(input->GetPoints());
    piece->GetPointData()->ShallowCopy(input->GetPointData());
    piece->GetPointData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
    CopyCells(input, piece, cellIds);
    piece->GetFieldData()->ShallowCopy(input->GetFieldData());
  }
  piece->GetCellData()->AddArray(cellIds);
  vtkNew<vtkIdTypeArray> numberOfCells; // ghost cells included
  numberOfCells->SetName(PieceCells);
  numberOfCells->InsertNextValue(input->GetNumberOfCells());
  piece->GetFieldData()->AddArray(numberOfCells);
  return piece;
}

/// The point arrays of the reference piece that every piece with points
/// has, over the whole point set (`count` points; pointIds: each piece's
/// points' whole ids): the value of a shared point from the first piece
/// that has it.
void JoinPointArrays(const std::vector<vtkSmartPointer<vtkPointSet>>& pieces,
  const std::vector<std::vector<vtkIdType>>& pointIds, vtkPointSet* reference, vtkIdType count, vtkPointSet* whole)
{
  vtkPointData* pd0 = reference->GetPointData();
  for (int a = 0; a < pd0->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array0 = pd0->GetArray(a);
    if (!array0 || !array0->GetName())
    {
      continue;
    }
    auto array = vtk::TakeSmartPointer(array0->NewInstance());
    array->SetName(array0->GetName());
    array->SetNumberOfComponents(array0->GetNumberOfComponents());
    array->SetNumberOfTuples(count);
    std::vector<char> set(static_cast<std::size_t>(count), 0);
    bool everywhere = true;
    for (std::size_t r = 0; r < pieces.size() && everywhere; ++r)
    {
      vtkDataArray* from = pieces[r]->GetPointData()->GetArray(array0->GetName());
      if (pieces[r]->GetNumberOfPoints() == 0)
      {
        continue;
      }
      everywhere = from && from->GetNumberOfComponents() == array0->GetNumberOfComponents();
      for (vtkIdType k = 0; everywhere && k < pieces[r]->GetNumberOfPoints(); ++k)
      {
        const vtkIdType id = pointIds[r][k];
        if (!set[id])
        {
          array->SetTuple(id, k, from);
          set[id] = 1;
        }
      }
    }
    if (everywhere)
    {
      whole->GetPointData()->AddArray(array);
      for (int t = 0; t < vtkDataSetAttributes::NUM_ATTRIBUTES; ++t)
      {
        if (pd0->GetAbstractAttribute(t) == array0)
        {
          whole->GetPointData()->SetActiveAttribute(array->GetName(), t);
        }
      }
    }
  }

}

} // namespace

vtkSmartPointer<vtkPointSet> vtkBeltramiGather::Collect(
  vtkMultiProcessController* controller, vtkPointSet* input)
{
  Controller = controller;
  const int rank = controller->GetLocalProcessId(), ranks = controller->GetNumberOfProcesses();
  vtkSmartPointer<vtkPointSet> piece = PieceToSend(input);
  if (rank != 0)
  {
    controller->Send(piece, 0, PieceTag);
    return nullptr;
  }
  std::vector<vtkSmartPointer<vtkPointSet>> pieces(static_cast<std::size_t>(ranks));
  pieces[0] = piece;
  for (int r = 1; r < ranks; ++r)
  {
    pieces[r] = vtk::TakeSmartPointer(input->NewInstance());
    controller->Receive(pieces[r], r, PieceTag);
  }
  // The first piece with points gives the arrays, types and field data
  // (rank 0's piece may be empty).
  vtkPointSet* reference = pieces[0];
  for (const auto& p : pieces)
  {
    if (p->GetNumberOfPoints() > 0)
    {
      reference = p;
      break;
    }
  }
  auto whole = vtk::TakeSmartPointer(input->NewInstance());
  const vtkIdType count = this->JoinPoints(pieces, reference, whole);
  JoinPointArrays(pieces, PointIds, reference, count, whole);
  this->JoinCells(pieces, whole);
  whole->GetFieldData()->ShallowCopy(reference->GetFieldData());
  whole->GetFieldData()->RemoveArray(PieceCells);
  return whole;
}

vtkIdType vtkBeltramiGather::JoinPoints(
  const std::vector<vtkSmartPointer<vtkPointSet>>& pieces, vtkPointSet* reference, vtkPointSet* whole)
{
  // All pieces' points, those within 1e-12 of the diagonal merged (pieces
  // share copies of the points on their common boundary).
  vtkIdType total = 0;
  vtkBoundingBox box;
  for (const auto& p : pieces)
  {
    total += p->GetNumberOfPoints();
    if (p->GetNumberOfPoints() > 0)
    {
      box.AddBounds(p->GetBounds());
    }
  }
  vtkNew<vtkPoints> all;
  all->SetDataTypeToDouble();
  all->SetNumberOfPoints(total);
  std::vector<vtkIdType> first(pieces.size() + 1, 0);
  for (std::size_t r = 0; r < pieces.size(); ++r)
  {
    first[r + 1] = first[r] + pieces[r]->GetNumberOfPoints();
    for (vtkIdType k = 0; k < pieces[r]->GetNumberOfPoints(); ++k)
    {
      all->SetPoint(first[r] + k, pieces[r]->GetPoint(k));
    }
  }
  const std::vector<vtkIdType> merged = CoincidentPoints(all, box.IsValid() ? 1e-12 * box.GetDiagonalLength() : 0.0);
  std::vector<vtkIdType> wholeId(static_cast<std::size_t>(total), -1);
  vtkIdType count = 0;
  for (vtkIdType i = 0; i < total; ++i)
  {
    if (wholeId[merged[i]] < 0)
    {
      wholeId[merged[i]] = count++;
    }
    wholeId[i] = wholeId[merged[i]];
  }
  vtkNew<vtkPoints> points;
  points->SetDataType(reference->GetPoints() ? reference->GetPoints()->GetDataType() : VTK_DOUBLE);
  points->SetNumberOfPoints(count);
  for (vtkIdType i = 0; i < total; ++i)
  {
    points->SetPoint(wholeId[i], all->GetPoint(i));
  }
  whole->SetPoints(points);
  PointIds.assign(pieces.size(), {});
  for (std::size_t r = 0; r < pieces.size(); ++r)
  {
    PointIds[r].assign(wholeId.begin() + first[r], wholeId.begin() + first[r + 1]);
  }
  return count;
}

void vtkBeltramiGather::JoinCells(const std::vector<vtkSmartPointer<vtkPointSet>>& pieces, vtkPointSet* whole)
{
  // Cells in the pieces' order; each piece cell's whole id.
  const std::vector<std::vector<vtkIdType>> placed = AppendCells(pieces, PointIds, whole);
  CellIds.assign(pieces.size(), {});
  for (std::size_t r = 0; r < pieces.size(); ++r)
  {
    vtkDataArray* local = pieces[r]->GetCellData()->GetArray(LocalCellIds);
    vtkDataArray* cellsOfPiece = pieces[r]->GetFieldData()->GetArray(PieceCells);
    CellIds[r].assign(cellsOfPiece ? static_cast<std::size_t>(cellsOfPiece->GetTuple1(0)) : 0, -1);
    for (std::size_t k = 0; local && k < placed[r].size(); ++k)
    {
      const auto cell = static_cast<std::size_t>(local->GetTuple1(static_cast<vtkIdType>(k)));
      if (cell < CellIds[r].size())
      {
        CellIds[r][cell] = placed[r][k];
      }
    }
  }
}

bool vtkBeltramiGather::Distribute(
  vtkPointSet* wholeInput, vtkPointSet* wholeOutput, bool ok, vtkPointSet* output)
{
  const int rank = Controller->GetLocalProcessId(), ranks = Controller->GetNumberOfProcesses();
  if (rank != 0)
  {
    return Apply(ReceivePart(Controller, 0), output);
  }
  bool result = ok;
  for (int r = ranks - 1; r >= 0; --r) // rank 0's own part last
  {
    vtkNew<vtkPolyData> part; // its field data carries everything
    vtkFieldData* fd = part->GetFieldData();
    vtkNew<vtkIntArray> status;
    status->SetName(Status);
    status->InsertNextValue(ok ? 1 : 0);
    fd->AddArray(status);
    if (ok)
    {
      fd->ShallowCopy(wholeOutput->GetFieldData());
      fd->AddArray(status);
      vtkPointData* in = wholeInput->GetPointData();
      vtkPointData* out = wholeOutput->GetPointData();
      vtkNew<vtkStringArray> attributes;
      attributes->SetName(Attributes);
      for (int a = 0; a < out->GetNumberOfArrays(); ++a)
      {
        vtkDataArray* array = out->GetArray(a);
        if (array && array->GetName() && in->GetArray(array->GetName()) != array)
        {
          auto picked = Pick(array, PointIds[r]);
          picked->SetName((PointPrefix + array->GetName()).c_str());
          fd->AddArray(picked);
          for (int t = 0; t < vtkDataSetAttributes::NUM_ATTRIBUTES; ++t)
          {
            if (out->GetAbstractAttribute(t) == array)
            {
              attributes->InsertNextValue(std::to_string(t) + ":" + array->GetName());
            }
          }
        }
      }
      fd->AddArray(attributes);
      vtkNew<vtkStringArray> removed;
      removed->SetName(Removed);
      for (int a = 0; a < in->GetNumberOfArrays(); ++a)
      {
        const char* name = in->GetArrayName(a);
        if (name && !out->GetAbstractArray(name))
        {
          removed->InsertNextValue(name);
        }
      }
      fd->AddArray(removed);
      for (int a = 0; a < wholeOutput->GetCellData()->GetNumberOfArrays(); ++a)
      {
        vtkDataArray* array = wholeOutput->GetCellData()->GetArray(a);
        if (array && array->GetName() && wholeInput->GetCellData()->GetArray(array->GetName()) != array)
        {
          auto picked = Pick(array, CellIds[r]);
          picked->SetName((CellPrefix + array->GetName()).c_str());
          fd->AddArray(picked);
        }
      }
      if (wholeOutput->GetPoints() != wholeInput->GetPoints())
      {
        auto picked = Pick(wholeOutput->GetPoints()->GetData(), PointIds[r]);
        picked->SetName(Coordinates);
        fd->AddArray(picked);
      }
    }
    if (r > 0)
    {
      SendPart(Controller, fd, r);
    }
    else
    {
      result = Apply(fd, output);
    }
  }
  return result;
}

int vtkBeltramiGather::RunWhole(vtkInformation* outInfo, vtkPointSet* input, vtkPointSet* output,
  Results results, const Run& run, const std::function<bool()>& gatherIf)
{
  const int holding = // collective in distributed runs: before any return
    vtkBeltramiSurface::PiecesHoldingData(outInfo, input);
  const bool split = holding > 1 && vtkBeltramiSurface::OnePiecePerRank(outInfo) && input && output;
  if (!split || (gatherIf && !gatherIf()))
  {
    return run(input, output, holding);
  }
  vtkBeltramiGather gather;
  vtkSmartPointer<vtkPointSet> whole = gather.Collect(vtkMultiProcessController::GetGlobalController(), input);
  if (results == Results::OnRankZero)
  {
    output->Initialize();
    return whole ? run(whole, output, 1) : 1;
  }
  output->ShallowCopy(input);
  if (!whole)
  {
    return gather.Distribute(nullptr, nullptr, true, output) ? 1 : 0; // ranks other than 0
  }
  vtkSmartPointer<vtkPointSet> wholeOutput = vtk::TakeSmartPointer(whole->NewInstance());
  const bool ok = run(whole, wholeOutput, 1) != 0;
  return gather.Distribute(whole, wholeOutput, ok, output) ? 1 : 0;
}
