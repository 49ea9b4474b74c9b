#include "vtkBeltramiSurface.h"

#include "Mesh/SurfaceRepair.h"

#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkMath.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPointSet.h>
#include <vtkPolyData.h>
#include <vtkPolygon.h>

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

vtkIdType vtkBeltramiSurface::WarnNonFinitePoints(vtkAlgorithm* owner, vtkDataSet* input, const char* consequence)
{
  vtkPointSet* set = vtkPointSet::SafeDownCast(input);
  vtkDataArray* data = set && set->GetPoints() ? set->GetPoints()->GetData() : nullptr;
  vtkIdType count = 0;
  for (vtkIdType i = 0; data && i < data->GetNumberOfTuples(); ++i)
  {
    double p[3];
    data->GetTuple(i, p);
    count += !(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]));
  }
  if (count > 0)
  {
    vtkWarningWithObjectMacro(owner, << count << " points have NaN or infinite coordinates: " << consequence);
  }
  return count;
}

vtkBeltramiSurface::Readiness vtkBeltramiSurface::BuildWhole(
  vtkAlgorithm* owner, vtkPolyData* input, int numberOfThreads, const char* product)
{
  if (!input || input->GetNumberOfPoints() == 0)
  {
    vtkWarningWithObjectMacro(owner, << "Input has no points: " << product << " is empty.");
    return Readiness::Empty;
  }
  if (!this->Build(input, numberOfThreads))
  {
    vtkErrorWithObjectMacro(owner, << "Cannot process the input surface: " << this->Error());
    return Readiness::Failed;
  }
  if (!RepairText.empty())
  {
    vtkWarningWithObjectMacro(owner, << RepairText);
  }
  if (this->Topology().NumberOfTriangles() == 0)
  {
    vtkWarningWithObjectMacro(owner, << "Input has no polygons or triangle strips: " << product << " is empty.");
    return Readiness::Empty;
  }
  if (this->InvalidCells > 0)
  {
    vtkWarningWithObjectMacro(owner, << this->InvalidCells << " cells with point ids out of range are left out of "
                                     << product << ".");
  }
  return Readiness::Ready;
}

bool vtkBeltramiSurface::Build(vtkPolyData* input, int numberOfThreads)
{
  InputData = input; // the lookups read it
  Mesh.reset();
  CellOfTriangle.clear();
  Floats = nullptr;
  Doubles = nullptr;
  ErrorText.clear();
  Merge.clear();
  RepairText.clear();
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
    if (Holding <= 1 || Gathered) // a piece of split data is not the whole surface
    {
      Repair(numberOfThreads);
    }
  }
  catch (const std::exception& e)
  {
    ErrorText = e.what();
    return false;
  }
  return true;
}

void vtkBeltramiSurface::Repair(int numberOfThreads)
{
  std::ostringstream said;
  const auto also = [&said]() -> std::ostream& { return said << (said.tellp() > 0 ? "; " : ""); };
  std::vector<vtkIdType> cells(static_cast<std::size_t>(Mesh->NumberOfTriangles())); // per kept triangle
  for (Index t = 0; t < Mesh->NumberOfTriangles(); ++t)
  {
    cells[t] = TriangleCell(Mesh->OriginalTriangleIds()[t]);
  }
  // The repaired topology, made of the triangles whose cells are `listed`,
  // replaces Mesh; `cells` follows its kept triangles (the topology drops
  // those a merge made degenerate: a parametric surface's seam and poles),
  // and `listed` is what TriangleCell gives (by the index into its list).
  std::vector<vtkIdType> listed;
  bool adopted = false;
  const auto adopt = [&](std::unique_ptr<beltrami::MeshTopology> repaired, std::vector<vtkIdType> byList) {
    cells.resize(static_cast<std::size_t>(repaired->NumberOfTriangles()));
    for (Index t = 0; t < repaired->NumberOfTriangles(); ++t)
    {
      cells[t] = byList[repaired->OriginalTriangleIds()[t]];
    }
    listed = std::move(byList);
    Mesh = std::move(repaired);
    adopted = true;
  };
  // A merge of points (`into`: per point, the point it joins) adopted where
  // `gains` holds for the summaries before and after it and it makes the
  // surface no less manifold (two sheets that touch at a point, a triangle
  // and its copy); Merge then goes on to where `into` takes its points.
  const auto mergeWhere = [&](std::vector<Index> into, const auto& gains) {
    if (into.empty())
    {
      return false;
    }
    auto joined = std::make_unique<beltrami::MeshTopology>(
      Mesh->NumberOfVertices(), beltrami::MergePoints(Mesh->TriangleList(), into), numberOfThreads);
    const beltrami::TopologySummary &now = Mesh->Summary(), &after = joined->Summary();
    if (!gains(now, after) || after.NumberOfNonManifoldEdges > now.NumberOfNonManifoldEdges ||
      after.NumberOfNonManifoldVertices > now.NumberOfNonManifoldVertices ||
      after.NumberOfDuplicateTriangles > now.NumberOfDuplicateTriangles)
    {
      return false;
    }
    adopt(std::move(joined), cells);
    for (Index& p : Merge)
    {
      p = into[p];
    }
    if (Merge.empty())
    {
      Merge = std::move(into);
    }
    return true;
  };
  using Summary = beltrami::TopologySummary;
  Index merged = 0;
  if (Mesh->Summary().NumberOfBoundaryEdges > 0 &&
    mergeWhere(Dispatch([&](const auto* x) { return beltrami::CoincidentBoundaryPoints(*Mesh, x, merged); }),
      [](const Summary& now, const Summary& after) { return after.NumberOfBoundaryEdges < now.NumberOfBoundaryEdges; }))
  {
    also() << merged << " coincident points were merged (an unwelded surface)";
  }
  // (Each collapse keeps the surface manifold and its Euler characteristic by
  // the link condition: checked as a whole all the same.)
  Index collapsed = 0;
  if (mergeWhere(Dispatch([&](const auto* x) { return beltrami::CollapsedEdges(*Mesh, x, collapsed); }),
        [](const Summary& now, const Summary& after) { return after.EulerCharacteristic == now.EulerCharacteristic; }))
  {
    also() << collapsed << " edges of zero length were collapsed (coincident points joined by an edge)";
  }
  if (Mesh->Summary().NumberOfDuplicateTriangles > 0)
  {
    const beltrami::IndexArray& list = Mesh->TriangleList();
    const std::vector<Index> repeated = beltrami::RepeatedTriangles(list);
    beltrami::IndexArray triangles;
    std::vector<vtkIdType> keptCells;
    for (Index t = 0, r = 0; t < Mesh->NumberOfTriangles(); ++t)
    {
      if (r < static_cast<Index>(repeated.size()) && repeated[r] == t)
      {
        ++r;
        continue;
      }
      triangles.insert(triangles.end(), list.begin() + 3 * static_cast<std::ptrdiff_t>(t),
        list.begin() + 3 * static_cast<std::ptrdiff_t>(t) + 3);
      keptCells.push_back(cells[t]);
    }
    adopt(std::make_unique<beltrami::MeshTopology>(Mesh->NumberOfVertices(), std::move(triangles), numberOfThreads),
      std::move(keptCells));
    also() << repeated.size() << " repeated triangles were dropped (the three points of an earlier one)";
  }
  if (Mesh->Summary().NumberOfInconsistentEdges > 0)
  {
    std::vector<double> storage;
    beltrami::IndexArray triangles;
    const beltrami::OrientationRepair turned = beltrami::OrientConsistently(*Mesh, PointsAsDouble(storage), triangles);
    if (turned.Changed())
    {
      adopt(std::make_unique<beltrami::MeshTopology>(Mesh->NumberOfVertices(), std::move(triangles), numberOfThreads),
        cells);
      also() << turned.FlippedTriangles << " triangles were turned to orient the surface consistently";
    }
    if (turned.NonOrientableComponents > 0)
    {
      also() << turned.NonOrientableComponents
             << (turned.NonOrientableComponents == 1 ? " component is" : " components are")
             << " not orientable (as a Moebius strip) and left as it is";
    }
  }
  if (adopted)
  {
    CellOfTriangle = std::move(listed);
  }
  if (said.tellp() > 0)
  {
    RepairText = "The input surface was repaired: " + said.str() + ".";
  }
}

void vtkBeltramiSurface::SpreadToMergedPoints() const
{
  if (Merge.empty() || !InputData || !OutputData || OutputData->GetNumberOfPoints() != InputData->GetNumberOfPoints())
  {
    return;
  }
  std::vector<vtkDataArray*> targets;
  vtkPointData* out = OutputData->GetPointData();
  for (int a = 0; a < out->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = out->GetArray(a);
    bool passed = false;
    for (int b = 0; array && b < InputData->GetPointData()->GetNumberOfArrays(); ++b)
    {
      passed = passed || InputData->GetPointData()->GetAbstractArray(b) == array;
    }
    if (array && !passed)
    {
      targets.push_back(array);
    }
  }
  if (OutputData->GetPoints() && OutputData->GetPoints() != InputData->GetPoints())
  {
    targets.push_back(OutputData->GetPoints()->GetData());
  }
  for (vtkDataArray* array : targets)
  {
    // A point's share of a measure stays with the point it was merged into,
    // so that sums over the points (Gauss-Bonnet, the total area) count it
    // once.
    const bool share = std::find(Shares.begin(), Shares.end(), array) != Shares.end();
    for (std::size_t p = 0; p < Merge.size(); ++p)
    {
      for (int k = 0; share && Merge[p] != static_cast<Index>(p) && k < array->GetNumberOfComponents(); ++k)
      {
        array->SetComponent(static_cast<vtkIdType>(p), k, 0.0);
      }
      if (!share && Merge[p] != static_cast<Index>(p))
      {
        array->SetTuple(static_cast<vtkIdType>(p), Merge[p], array);
      }
    }
  }
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

vtkIdType vtkBeltramiSurface::NumberOfInputPoints() const
{
  return InputData ? InputData->GetNumberOfPoints() : 0;
}

vtkIdType vtkBeltramiSurface::NumberOfTopologyPoints() const
{
  return Mesh ? Mesh->NumberOfVertices() : NumberOfInputPoints();
}

const double* vtkBeltramiSurface::PointsAsDouble(std::vector<double>& storage) const
{
  if (Doubles && Copied.empty())
  {
    return Doubles;
  }
  const std::size_t n = Mesh ? static_cast<std::size_t>(Mesh->NumberOfVertices()) : 0;
  if (Copied.empty())
  {
    storage.assign(Floats, Floats + 3 * n);
    return storage.data();
  }
  storage.resize(3 * n);
  for (std::size_t v = 0; v < n; ++v)
  {
    const std::size_t p = static_cast<std::size_t>(InputPoint(static_cast<Index>(v)));
    for (std::size_t k = 0; k < 3; ++k)
    {
      storage[3 * v + k] = Doubles ? Doubles[3 * p + k] : static_cast<double>(Floats[3 * p + k]);
    }
  }
  return storage.data();
}

std::string vtkBeltramiSurface::SplitNonManifold(int numberOfThreads)
{
  beltrami::IndexArray triangles;
  Index cut = 0;
  std::vector<Index> copied = Mesh && Mesh->Summary().NumberOfNonManifoldVertices > 0 && Copied.empty()
    ? beltrami::SplitPinchedVertices(*Mesh, triangles, cut)
    : std::vector<Index>();
  if (copied.empty())
  {
    return {};
  }
  // (No triangle is dropped: the cells follow the topology's triangles.)
  std::vector<vtkIdType> cells(static_cast<std::size_t>(Mesh->NumberOfTriangles()));
  for (Index t = 0; t < Mesh->NumberOfTriangles(); ++t)
  {
    cells[t] = TriangleCell(Mesh->OriginalTriangleIds()[t]);
  }
  Mesh = std::make_unique<beltrami::MeshTopology>(
    Mesh->NumberOfVertices() + static_cast<Index>(copied.size()), std::move(triangles), numberOfThreads);
  CellOfTriangle = std::move(cells);
  Copied = std::move(copied);
  std::vector<Index> distinct(Copied);
  std::sort(distinct.begin(), distinct.end());
  const auto split = std::unique(distinct.begin(), distinct.end()) - distinct.begin();
  std::ostringstream os;
  os << split << (split == 1 ? " point is" : " points are") << " shared by separate parts of the surface";
  if (cut > 0)
  {
    os << " (at the ends of " << cut << (cut == 1 ? " edge" : " edges")
       << " of three or more triangles, or pinched: parts meet there)";
  }
  else
  {
    os << " (pinched: they meet there)";
  }
  os << ": each part got its own copy of them";
  return os.str();
}

std::string vtkBeltramiSurface::TopologyWarning() const
{
  if (!Mesh)
  {
    return {};
  }
  const beltrami::TopologySummary& s = Mesh->Summary();
  // (The points merged into others are unused on purpose: RepairWarning.)
  const Index mergedAway = static_cast<Index>(
    std::count_if(Merge.begin(), Merge.end(), [&, p = Index(0)](Index into) mutable { return into != p++; }));
  const Index isolated = s.NumberOfIsolatedVertices - mergedAway;
  if (s.IsManifold() && s.IsOriented() && Mesh->NumberOfDroppedTriangles() == 0 && isolated == 0 &&
    InvalidCells == 0)
  {
    return {};
  }
  std::ostringstream os;
  os << "Input surface has defects: " << Mesh->Describe();
  if (isolated)
  {
    os << ", " << isolated << " points used by no triangle";
  }
  if (InvalidCells)
  {
    os << ", " << InvalidCells << " cells with point ids out of range (ignored)";
  }
  return os.str();
}
// VTK-HeaderTest-Exclude: vtkBeltramiSurface.cxx
