#include "vtkIntrinsicParameterization.h"
#include "vtkBeltramiSettings.h"

#include "vtkBeltramiSurface.h"
#include "vtkSurfaceAtlas.h"

#include "Maps/BoundaryHandles.h"
#include "Maps/Parameterization.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

BELTRAMI_SAME_ENUM(vtkIntrinsicParameterization::CIRCLE, beltrami::ParameterizationBoundary::Circle);
BELTRAMI_SAME_ENUM(vtkIntrinsicParameterization::SQUARE, beltrami::ParameterizationBoundary::Square);
BELTRAMI_SAME_ENUM(vtkIntrinsicParameterization::GIVEN, beltrami::ParameterizationBoundary::Given);
BELTRAMI_SAME_ENUM(vtkIntrinsicParameterization::NATURAL, beltrami::ParameterizationBoundary::Natural);
BELTRAMI_SAME_ENUM(vtkIntrinsicParameterization::ARC_LENGTH, beltrami::BoundarySpacing::ArcLength);
BELTRAMI_SAME_ENUM(vtkIntrinsicParameterization::UNIFORM, beltrami::BoundarySpacing::Uniform);
BELTRAMI_SAME_ENUM(vtkIntrinsicParameterization::EDGE_LENGTH, beltrami::DistortionEnergy::EdgeLength);
BELTRAMI_SAME_ENUM(vtkIntrinsicParameterization::AREA, beltrami::DistortionEnergy::Area);

vtkStandardNewMacro(vtkIntrinsicParameterization);

struct vtkIntrinsicParameterization::Internals
{
  std::vector<beltrami::PointConstraint> Constraints;
  std::vector<beltrami::LineConstraint> Lines;
  std::unique_ptr<beltrami::BoundaryBasis> Basis;
  // Boundary handles and what a handles-only update reuses.
  std::vector<beltrami::BoundaryHandle> Handles;
  bool HandleChange = false;                  // inside a handle setter
  vtkTimeStamp SolveSettings;                 // every change but the handles'
  vtkMTimeType SolvedSettings = 0;
  std::vector<vtkMTimeType> SolvedStamp; // InputStamp of the solve's input
  vtkPolyData* SolvedInput = nullptr;
  beltrami::ParameterizationResult Solved; // the solve's map (before the handles) and report
};

vtkIntrinsicParameterization::vtkIntrinsicParameterization()
  : Internal(new Internals)
{
  // The defaults have one source: the core's ParameterizationOptions.
  beltrami::ParameterizationOptions defaults;
  this->CopySettings(defaults, vtkBeltramiCopy::FromCore);
  // Input arrays 0 (given boundary UV) and 1 (constraint targets) are optional.
}

void vtkIntrinsicParameterization::CopySettings(
  beltrami::ParameterizationOptions& o, vtkBeltramiCopy direction)
{
  BeltramiCopySetting(this->ConformalWeight, o.ConformalWeight, direction);
  BeltramiCopySetting(this->AuthalicWeight, o.AuthalicWeight, direction);
  BeltramiCopySetting(this->Boundary, o.Boundary, direction);
  BeltramiCopySetting(this->BoundarySpacing, o.Spacing, direction);
  BeltramiCopySetting(this->OptimizeMix, o.OptimizeMix, direction);
  BeltramiCopySetting(this->OptimalEnergy, o.OptimalEnergy, direction);
  BeltramiCopySetting(this->OptimalMixRange[0], o.OptimalRange[0], direction);
  BeltramiCopySetting(this->OptimalMixRange[1], o.OptimalRange[1], direction);
  BeltramiCopySetting(this->BoundaryOptimizationSteps, o.BoundaryOptimizationSteps, direction);
  BeltramiCopySetting(this->BoundaryEnergy, o.BoundaryEnergy, direction);
  BeltramiCopySetting(this->KeepBoundaryBasis, o.KeepBoundaryBasis, direction);
  BeltramiCopySetting(this->NumberOfThreads, o.NumberOfThreads, direction);
}

namespace
{

/// A point id for the core; ids beyond its range are kept invalid (the
/// core reports them).
beltrami::Index CoreIndex(vtkIdType id)
{
  return id < 0 ? -1
                : static_cast<beltrami::Index>(std::min<vtkIdType>(id, std::numeric_limits<beltrami::Index>::max()));
}

/// A result's map and report (not its basis).
void CopyReport(const beltrami::ParameterizationResult& from, beltrami::ParameterizationResult& to)
{
  to.UV = from.UV;
  to.OuterBoundary = from.OuterBoundary;
  to.PinnedVertices = from.PinnedVertices;
  to.OptimalMix = from.OptimalMix;
  to.BoundaryEnergies = from.BoundaryEnergies;
  to.DegenerateTriangles = from.DegenerateTriangles;
}

vtkNew<vtkDoubleArray> NamedValue(const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  return a;
}

} // namespace

vtkIntrinsicParameterization::~vtkIntrinsicParameterization() = default;

void vtkIntrinsicParameterization::AddPointConstraint(vtkIdType pointId, double u, double v)
{
  this->AddSurfacePointConstraint(pointId, -1, -1, 1.0, 0.0, 0.0, u, v);
}

void vtkIntrinsicParameterization::AddSurfacePointConstraint(vtkIdType a, vtkIdType b,
  vtkIdType c, double wa, double wb, double wc, double u, double v)
{
  beltrami::PointConstraint pc;
  const vtkIdType ids[3] = { a, b, c };
  for (int k = 0; k < 3; ++k)
  {
    pc.Vertices[k] = CoreIndex(ids[k]);
  }
  pc.Weights = { wa, wb, wc };
  pc.Target[0] = u;
  pc.Target[1] = v;
  this->Internal->Constraints.push_back(pc);
  this->Modified();
}

void vtkIntrinsicParameterization::AddLineConstraint(vtkIdList* pointIds, double u0, double v0, double u1, double v1)
{
  std::vector<vtkIdType> path;
  for (vtkIdType k = 0; pointIds && k < pointIds->GetNumberOfIds(); ++k)
  {
    path.push_back(pointIds->GetId(k));
  }
  this->AddLine(path, false, u0, v0, u1, v1);
}

void vtkIntrinsicParameterization::AddShortestPathLineConstraint(
  vtkIdType start, vtkIdType end, double u0, double v0, double u1, double v1)
{
  this->AddLine({ start, end }, true, u0, v0, u1, v1);
}

void vtkIntrinsicParameterization::AddLine(
  const std::vector<vtkIdType>& path, bool shortest, double u0, double v0, double u1, double v1)
{
  beltrami::LineConstraint line;
  std::transform(path.begin(), path.end(), std::back_inserter(line.Path), CoreIndex);
  line.ShortestPaths = shortest;
  line.From[0] = u0;
  line.From[1] = v0;
  line.To[0] = u1;
  line.To[1] = v1;
  this->Internal->Lines.push_back(std::move(line));
  this->Modified();
}

void vtkIntrinsicParameterization::RemoveAllConstraints()
{
  if (!this->Internal->Constraints.empty() || !this->Internal->Lines.empty())
  {
    this->Internal->Constraints.clear();
    this->Internal->Lines.clear();
    this->Modified();
  }
}

int vtkIntrinsicParameterization::GetNumberOfConstraints() const
{
  return static_cast<int>(this->Internal->Constraints.size());
}

int vtkIntrinsicParameterization::GetNumberOfLineConstraints() const
{
  return static_cast<int>(this->Internal->Lines.size());
}

void vtkIntrinsicParameterization::Modified()
{
  if (this->Internal && !this->Internal->HandleChange)
  {
    this->Internal->SolveSettings.Modified();
  }
  this->Superclass::Modified();
}

void vtkIntrinsicParameterization::AddBoundaryHandle(vtkIdType pointId, double u, double v)
{
  beltrami::BoundaryHandle h;
  h.Vertex = CoreIndex(pointId);
  h.Target[0] = u;
  h.Target[1] = v;
  this->Internal->Handles.push_back(h);
  this->Internal->HandleChange = true;
  this->Modified();
  this->Internal->HandleChange = false;
}

void vtkIntrinsicParameterization::RemoveAllBoundaryHandles()
{
  if (!this->Internal->Handles.empty())
  {
    this->Internal->Handles.clear();
    this->Internal->HandleChange = true;
    this->Modified();
    this->Internal->HandleChange = false;
  }
}

int vtkIntrinsicParameterization::GetNumberOfBoundaryHandles() const
{
  return static_cast<int>(this->Internal->Handles.size());
}

std::vector<vtkMTimeType> vtkIntrinsicParameterization::InputStamp(vtkBeltramiSurface& surface)
{
  // What a solve reads: the points, the cells and the two input arrays (the
  // data object's own time also follows changes of unused arrays, which
  // ParaView's pipeline makes on every update).
  vtkPolyData* input = surface.Input();
  std::vector<vtkMTimeType> stamp{ input->GetPoints() ? input->GetPoints()->GetMTime() : 0,
    input->GetPolys()->GetMTime(), input->GetStrips()->GetMTime() };
  for (int k = 0; k < 2; ++k)
  {
    vtkInformation* info = this->GetInputArrayInformation(k);
    const char* name = info && info->Has(vtkDataObject::FIELD_NAME()) ? info->Get(vtkDataObject::FIELD_NAME()) : nullptr;
    vtkDataArray* array = name ? input->GetPointData()->GetArray(name) : nullptr;
    stamp.push_back(array ? array->GetMTime() : 0);
  }
  return stamp;
}

bool vtkIntrinsicParameterization::CanReuseSolve(vtkBeltramiSurface& surface)
{
  const Internals& in = *this->Internal;
  return !in.Handles.empty() && in.Basis && !surface.IsGathered() && in.SolvedInput == surface.Input() &&
    in.SolvedStamp == this->InputStamp(surface) && in.SolvedSettings == in.SolveSettings.GetMTime();
}

bool vtkIntrinsicParameterization::ApplyHandles(vtkBeltramiSurface& surface, std::vector<double>& uv)
{
  std::vector<double> converted;
  const std::string error = beltrami::MoveBoundaryHandles(surface.Topology(), surface.PointsAsDouble(converted),
    *this->Internal->Basis, this->Internal->Solved.UV, this->Internal->Handles, uv);
  if (!error.empty())
  {
    vtkErrorMacro(<< error << ". The output is the input.");
    return false;
  }
  return true;
}

void vtkIntrinsicParameterization::GetBoundaryPointIds(vtkIdList* ids) const
{
  ids->Reset();
  if (this->Internal->Basis)
  {
    for (beltrami::Index v : this->Internal->Basis->BoundaryVertices())
    {
      ids->InsertNextId(v);
    }
  }
}

bool vtkIntrinsicParameterization::ComputeUV(vtkDataArray* boundaryUV, vtkDoubleArray* uv) const
{
  const beltrami::BoundaryBasis* basis = this->Internal->Basis.get();
  if (!basis || !boundaryUV || !uv || boundaryUV->GetNumberOfComponents() != 2 ||
    boundaryUV->GetNumberOfTuples() != static_cast<vtkIdType>(basis->BoundaryVertices().size()))
  {
    return false;
  }
  std::vector<double> p(2 * basis->BoundaryVertices().size());
  for (vtkIdType k = 0; k < boundaryUV->GetNumberOfTuples(); ++k)
  {
    p[2 * k] = boundaryUV->GetComponent(k, 0);
    p[2 * k + 1] = boundaryUV->GetComponent(k, 1);
  }
  uv->SetNumberOfComponents(2);
  uv->SetNumberOfTuples(basis->NumberOfVertices());
  basis->Apply(p.data(), uv->GetPointer(0));
  return true;
}


int vtkIntrinsicParameterization::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (this->Internal->Handles.empty()) // else kept for an update of the handles alone
  {
    this->Internal->Basis.reset();
  }
  this->OptimalMix = -1.0;
  this->MeanAngleDistortion = this->MeanAreaDistortion = this->MeanEdgeDistortion = 0.0;
  this->NumberOfFlippedTriangles = 0;
  // A parameterization is one solve over the whole surface.  Data split over
  // the ranks of a distributed run are solved over the ranks, each rank
  // holding its own piece (vtkBeltramiSurface::Needs::Distributed); the
  // options that need the whole surface (DistributedParameterizationLimitation,
  // constraint targets) gather the pieces on rank 0 (vtkBeltramiGather), and
  // every rank gets the results for its own points and cells.
  const auto parameterize = [this](vtkBeltramiSurface& surface) {
    if (!surface.Split() && surface.PiecesWithData() > 1) // pieces streamed one by one: no gathering
    {
      vtkWarningMacro("A parameterization needs the whole surface: this piece of " << surface.PiecesWithData()
        << " streamed pieces is passed through. Update the whole data set.");
      return true;
    }
    if (surface.IsGathered() && (!this->Internal->Constraints.empty() || !this->Internal->Lines.empty()))
    {
      vtkWarningMacro("Distributed data gathered on rank 0: the point and line constraints by vertex id refer to the "
                      "points of the gathered surface (rank 0's piece first); the constraint target array "
                      "(input array 1) is the reliable way to constrain distributed data.");
    }
    return this->Parameterize(surface) != 0;
  };
  beltrami::ParameterizationOptions options;
  this->CopySettings(options, vtkBeltramiCopy::ToCore);
  options.Constraints = this->Internal->Constraints;
  options.Lines = this->Internal->Lines;
  options.KeepBoundaryBasis = options.KeepBoundaryBasis || !this->Internal->Handles.empty();
  vtkInformation* targets = this->GetInputArrayInformation(1);
  const char* target = targets && targets->Has(vtkDataObject::FIELD_NAME()) ? targets->Get(vtkDataObject::FIELD_NAME()) : nullptr;
  const bool distributes = beltrami::DistributedParameterizationLimitation(options).empty() &&
    (!target || !*target || std::string(target) == "None");
  return vtkBeltramiSurface::Execute(this, inputVector, outputVector, this->NumberOfThreads,
    distributes ? vtkBeltramiSurface::Needs::Distributed : vtkBeltramiSurface::Needs::WholeSurface, parameterize,
    [this](vtkPolyData* output) { this->ReadReport(output->GetFieldData()); });
}

int vtkIntrinsicParameterization::Parameterize(vtkBeltramiSurface& surface)
{
  const beltrami::MeshTopology& topo = surface.Topology();
  if (surface.NumberOfInvalidCells() > 0)
  {
    vtkWarningMacro(<< surface.NumberOfInvalidCells()
                    << " cells with point ids out of range are left out of the parameterization.");
  }
  std::string notDisk;
  if (this->AtlasForNonDisks && !surface.Split() && !beltrami::CheckDiskTopology(topo, notDisk))
  {
    if (!this->Internal->Handles.empty())
    {
      vtkWarningMacro("Boundary handles are for a single chart; the atlas of this surface ignores them.");
    }
    return this->ParameterizeThroughAtlas(surface, notDisk);
  }
  beltrami::ParameterizationResult result;
  if (this->CanReuseSolve(surface)) // only the handles changed: the kept basis, no solve
  {
    CopyReport(this->Internal->Solved, result);
  }
  else if (!this->Solve(surface, result))
  {
    return 0;
  }
  if (!this->Internal->Handles.empty() && !this->ApplyHandles(surface, result.UV))
  {
    return 0;
  }
  this->UpdateProgress(0.9);
  std::vector<double> converted; // float points: one copy in double
  const beltrami::DistortionReport distortion =
    beltrami::MeasureDistortion(
      topo, surface.PointsAsDouble(converted), result.UV.data(), this->NumberOfThreads, surface.Split());
  if (distortion.FlippedTriangles > 0 && this->CanUseAtlasInstead(surface))
  {
    return this->ParameterizeThroughAtlas(surface,
      "The map of this surface flipped " + std::to_string(distortion.FlippedTriangles) +
        " triangles (the conformal weights are negative at obtuse triangles; holes are free).");
  }
  this->WriteMap(surface, result);
  this->WriteDistortion(surface, distortion, result);
  this->UpdateProgress(1.0);
  return 1;
}

bool vtkIntrinsicParameterization::Solve(vtkBeltramiSurface& surface, beltrami::ParameterizationResult& result)
{
  Internals& in = *this->Internal;
  in.Basis.reset();
  beltrami::ParameterizationOptions options;
  this->CopySettings(options, vtkBeltramiCopy::ToCore);
  options.KeepBoundaryBasis = options.KeepBoundaryBasis || !in.Handles.empty();
  std::vector<double> given;
  if (!surface.AllAgree(this->ReadInputArrays(surface, options, given))) // (split: every rank stops, none waits)
  {
    return false;
  }
  this->UpdateProgress(0.0);
  std::vector<double> converted;
  try // the split solve needs MPI and hypre: failures there are errors, not crashes
  {
    result = surface.Split() ? this->SolveSplit(surface, options, given)
                             : beltrami::Parameterize(surface.Topology(), surface.PointsAsDouble(converted), options);
  }
  catch (const std::exception& e)
  {
    result.Error = e.what();
  }
  ++this->NumberOfSolves;
  if (!result.Error.empty())
  {
    vtkErrorMacro(<< result.Error);
    return false;
  }
  if (!result.Warning.empty())
  {
    vtkWarningMacro(<< result.Warning << ".");
  }
  in.Basis = std::move(result.Basis);
  if (in.Handles.empty())
  {
    return true;
  }
  if (!in.Basis)
  {
    vtkErrorMacro("Boundary handles need a fixed boundary (CIRCLE, SQUARE or GIVEN). The output is the input.");
    return false;
  }
  CopyReport(result, in.Solved); // what an update of the handles alone reuses
  in.SolvedInput = surface.Input();
  in.SolvedStamp = this->InputStamp(surface);
  in.SolvedSettings = in.SolveSettings.GetMTime();
  return true;
}

bool vtkIntrinsicParameterization::CanUseAtlasInstead(const vtkBeltramiSurface& surface) const
{
  // The atlas splits a chart whose map flips, so it never flips; it has no
  // place for what pins a single map (constraints, handles, given UV).
  const Internals& in = *this->Internal;
  vtkInformation* targets = const_cast<vtkIntrinsicParameterization*>(this)->GetInputArrayInformation(1);
  const char* target =
    targets && targets->Has(vtkDataObject::FIELD_NAME()) ? targets->Get(vtkDataObject::FIELD_NAME()) : nullptr;
  const bool noTargets = !target || !*target || std::string(target) == "None";
  return this->AtlasForNonDisks && noTargets && !surface.Split() && !surface.IsGathered() && this->Boundary != GIVEN &&
    in.Constraints.empty() && in.Lines.empty() && in.Handles.empty() && !this->KeepBoundaryBasis &&
    this->BoundaryOptimizationSteps == 0 && !this->OptimizeMix;
}

int vtkIntrinsicParameterization::ParameterizeThroughAtlas(vtkBeltramiSurface& surface, const std::string& why)
{
  if (surface.IsGathered() || this->Boundary == GIVEN)
  {
    vtkErrorMacro(<< why << " An atlas (AtlasForNonDisks) is made in serial runs with the CIRCLE, SQUARE or "
                            "NATURAL boundary; use Surface Atlas (vtkSurfaceAtlas) for distributed data.");
    return 0;
  }
  vtkNew<vtkSurfaceAtlas> atlas;
  atlas->SetInputData(surface.Input());
  atlas->SetChartBoundary(this->Boundary);
  atlas->SetMapResolution(0);
  atlas->SetNumberOfThreads(this->NumberOfThreads);
  atlas->Update();
  vtkPolyData* cut = atlas->GetOutput();
  vtkDataArray* charts = cut->GetFieldData()->GetArray("AtlasCharts");
  if (!charts)
  {
    vtkErrorMacro(<< why << " No atlas could be made of it (see the error above).");
    return 0;
  }
  surface.Output()->ShallowCopy(cut);
  vtkWarningMacro(<< why << " It was parameterized through an atlas of " << charts->GetComponent(0, 0)
                  << " charts: the output is the surface cut along their seams (vtkOriginalPointIds).");
  // The getters: area-weighted means over the charts.
  vtkDataArray* angle = cut->GetFieldData()->GetArray("AtlasChartAngleDistortion");
  vtkDataArray* area = cut->GetFieldData()->GetArray("AtlasChartArea");
  vtkDataArray* areaDistortion = cut->GetFieldData()->GetArray("AtlasChartAreaDistortion");
  double total = 0.0, weightedAngle = 0.0, weightedArea = 0.0;
  for (vtkIdType c = 0; c < area->GetNumberOfTuples(); ++c)
  {
    total += area->GetComponent(c, 0);
    weightedAngle += angle->GetComponent(c, 0) * area->GetComponent(c, 0);
    weightedArea += areaDistortion->GetComponent(c, 0) * area->GetComponent(c, 0);
  }
  this->MeanAngleDistortion = total > 0.0 ? weightedAngle / total : 0.0;
  this->MeanAreaDistortion = total > 0.0 ? weightedArea / total : 0.0;
  this->MeanEdgeDistortion = 0.0;
  this->NumberOfFlippedTriangles = 0; // the atlas never flips a triangle
  this->OptimalMix = -1.0;
  this->Internal->Basis.reset();
  return 1;
}

bool vtkIntrinsicParameterization::ReadInputArrays(
  vtkBeltramiSurface& surface, beltrami::ParameterizationOptions& options, std::vector<double>& given)
{
  const vtkIdType numPoints = surface.Input()->GetNumberOfPoints();
  std::string error;
  vtkDataArray* givenArray = surface.SelectedPointArray(this, 0, 2, "given boundary UV", error);
  vtkDataArray* targetArray =
    error.empty() ? surface.SelectedPointArray(this, 1, 2, "constraint target", error) : nullptr;
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  if (this->Boundary == GIVEN && !(surface.Split() && numPoints == 0)) // (an empty piece of a split run: none)
  {
    if (!givenArray)
    {
      vtkErrorMacro("Boundary GIVEN needs a 2-component point array of boundary positions (input array 0).");
      return false;
    }
    given.resize(2 * static_cast<std::size_t>(numPoints));
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      given[2 * i] = givenArray->GetComponent(i, 0);
      given[2 * i + 1] = givenArray->GetComponent(i, 1);
    }
    options.GivenUV = given.data();
  }
  options.Constraints = this->Internal->Constraints;
  options.Lines = this->Internal->Lines;
  for (vtkIdType i = 0; targetArray && i < numPoints; ++i)
  {
    const double u = targetArray->GetComponent(i, 0), v = targetArray->GetComponent(i, 1);
    if (std::isfinite(u) && std::isfinite(v))
    {
      beltrami::PointConstraint pc;
      pc.Vertices[0] = static_cast<beltrami::Index>(i);
      pc.Target[0] = u;
      pc.Target[1] = v;
      options.Constraints.push_back(pc);
    }
  }
  return true;
}

beltrami::ParameterizationResult vtkIntrinsicParameterization::SolveSplit(
  vtkBeltramiSurface& surface, beltrami::ParameterizationOptions& options, std::vector<double>& given)
{
  // One row per topology point (the core gives the ghost rows their owners' values).
  const std::size_t rows = static_cast<std::size_t>(surface.NumberOfTopologyPoints());
  if (options.GivenUV)
  {
    given.resize(2 * rows, 0.0);
    options.GivenUV = given.data();
  }
  std::vector<std::int64_t> ids; // the pieces' global point ids, where they have them
  vtkDataArray* globalIds = surface.Input()->GetPointData()->GetGlobalIds();
  if (globalIds && globalIds->GetNumberOfComponents() == 1)
  {
    ids.assign(rows, 0);
    for (vtkIdType i = 0; i < globalIds->GetNumberOfTuples(); ++i)
    {
      ids[i] = static_cast<std::int64_t>(globalIds->GetComponent(i, 0));
    }
  }
  const beltrami::Partition& split = *surface.Split();
  const bool everyRankHasIds = split.Sum(ids.empty() && surface.NumberOfInputPoints() > 0 ? 1.0 : 0.0) == 0.0;
  std::vector<double> converted;
  return beltrami::Parameterize(surface.Topology(), surface.PointsAsDouble(converted), options, split,
    everyRankHasIds && !ids.empty() ? ids.data() : nullptr);
}

void vtkIntrinsicParameterization::WriteMap(
  vtkBeltramiSurface& surface, const beltrami::ParameterizationResult& result)
{
  vtkPolyData* output = surface.Output();
  const vtkIdType numPoints = surface.Input()->GetNumberOfPoints();
  // Outputs on LargeBuffer's cached pages (vtkBeltramiSurface::NewArray):
  // fresh pages for the UVs and the three cell arrays cost about as much as
  // the distortion measure itself (179k vertices: ~40 ms every run).
  vtkSmartPointer<vtkDataArray> uv = vtkBeltramiSurface::NewArray(VTK_DOUBLE, "UV", 2, numPoints);
  std::copy_n(result.UV.begin(), 2 * numPoints, static_cast<double*>(uv->GetVoidPointer(0))); // (split: the piece's rows)
  output->GetPointData()->AddArray(uv);
  output->GetPointData()->SetTCoords(uv);
  if (this->OutputFlattenedMesh)
  {
    vtkSmartPointer<vtkDataArray> xyz = vtkBeltramiSurface::NewArray(VTK_DOUBLE, "Points", 3, numPoints);
    double* p = static_cast<double*>(xyz->GetVoidPointer(0));
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      p[3 * i] = result.UV[2 * i];
      p[3 * i + 1] = result.UV[2 * i + 1];
      p[3 * i + 2] = 0.0;
    }
    vtkNew<vtkPoints> flat;
    flat->SetData(xyz);
    output->SetPoints(flat);
    if (output->GetPointData()->GetNormals()) // 3D normals do not belong to the flat mesh
    {
      vtkNew<vtkPointData> pd;
      pd->ShallowCopy(output->GetPointData());
      pd->SetNormals(nullptr);
      output->GetPointData()->ShallowCopy(pd);
    }
  }
}

void vtkIntrinsicParameterization::WriteDistortion(vtkBeltramiSurface& surface,
  const beltrami::DistortionReport& distortion, const beltrami::ParameterizationResult& result)
{
  vtkPolyData* input = surface.Input();
  vtkPolyData* output = surface.Output();
  const beltrami::MeshTopology& topo = surface.Topology();
  // Per-cell distortion: the mean over each input cell's triangles; NaN for
  // cells without triangles (vertices, lines).
  const vtkIdType numCells = input->GetNumberOfCells();
  const beltrami::IndexArray& kept = topo.OriginalTriangleIds();
  const char* names[3] = { "AngleDistortion", "AreaDistortion", "EdgeDistortion" };
  const std::vector<double>* values[3] = { &distortion.AngleDistortion, &distortion.AreaDistortion,
    &distortion.EdgeDistortion };
  std::vector<int> count(numCells, 0);
  for (std::size_t t = 0; t < kept.size(); ++t)
  {
    const vtkIdType cell = surface.TriangleCell(kept[t]);
    if (cell >= 0) // (-1: another piece's triangle of a split run)
    {
      ++count[cell];
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    vtkSmartPointer<vtkDataArray> array = vtkBeltramiSurface::NewArray(VTK_DOUBLE, names[a], 1, numCells);
    double* out = static_cast<double*>(array->GetVoidPointer(0));
    std::fill(out, out + numCells, 0.0);
    const double* value = values[a]->data();
    for (std::size_t t = 0; t < kept.size(); ++t)
    {
      const vtkIdType cell = surface.TriangleCell(kept[t]);
      if (cell >= 0)
      {
        out[cell] += value[t] / count[cell];
      }
    }
    for (vtkIdType c = 0; c < numCells; ++c)
    {
      if (count[c] == 0)
      {
        out[c] = std::nan("");
      }
    }
    output->GetCellData()->AddArray(array);
  }

  vtkNew<vtkFieldData> fd;
  fd->ShallowCopy(input->GetFieldData());
  fd->AddArray(NamedValue("MeanAngleDistortion", distortion.MeanAngle));
  fd->AddArray(NamedValue("MaxAngleDistortion", distortion.MaxAngle));
  fd->AddArray(NamedValue("MeanAreaDistortion", distortion.MeanArea));
  fd->AddArray(NamedValue("MaxAreaDistortion", distortion.MaxArea));
  fd->AddArray(NamedValue("MeanEdgeDistortion", distortion.MeanEdge));
  fd->AddArray(NamedValue("MaxEdgeDistortion", distortion.MaxEdge));
  fd->AddArray(NamedValue("FlippedTriangles", distortion.FlippedTriangles));
  if (result.OptimalMix >= 0.0 || this->OptimizeMix)
  {
    fd->AddArray(NamedValue("OptimalMix", result.OptimalMix));
  }
  if (surface.Split())
  {
    fd->AddArray(NamedValue("ParameterizationIterations", result.Iterations));
    surface.SplitPieces().AddDistribution(fd, "ParameterizationDistribution");
  }
  if (!result.BoundaryEnergies.empty())
  {
    vtkNew<vtkDoubleArray> energies;
    energies->SetName("BoundaryEnergy");
    for (double e : result.BoundaryEnergies)
    {
      energies->InsertNextValue(e);
    }
    fd->AddArray(energies);
  }
  output->SetFieldData(fd);
  if (distortion.FlippedTriangles && (!surface.Split() || surface.Split()->Rank() == 0)) // (split: one report)
  {
    vtkWarningMacro(<< distortion.FlippedTriangles
                    << " triangles are flipped in the parameterization (obtuse triangles give negative "
                       "weights; try the authalic weight, a natural boundary or a convex boundary).");
  }
  this->OptimalMix = result.OptimalMix;
  this->MeanAngleDistortion = distortion.MeanAngle;
  this->MeanAreaDistortion = distortion.MeanArea;
  this->MeanEdgeDistortion = distortion.MeanEdge;
  this->NumberOfFlippedTriangles = distortion.FlippedTriangles;
}

void vtkIntrinsicParameterization::ReadReport(vtkFieldData* fd)
{
  const auto value = [fd](const char* name, double fallback) {
    vtkDataArray* a = fd ? fd->GetArray(name) : nullptr;
    return a && a->GetNumberOfTuples() > 0 ? a->GetTuple1(0) : fallback;
  };
  this->OptimalMix = value("OptimalMix", -1.0);
  this->MeanAngleDistortion = value("MeanAngleDistortion", 0.0);
  this->MeanAreaDistortion = value("MeanAreaDistortion", 0.0);
  this->MeanEdgeDistortion = value("MeanEdgeDistortion", 0.0);
  this->NumberOfFlippedTriangles = static_cast<vtkIdType>(value("FlippedTriangles", 0.0));
}

void vtkIntrinsicParameterization::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ConformalWeight: " << this->ConformalWeight << "\n";
  os << indent << "AuthalicWeight: " << this->AuthalicWeight << "\n";
  os << indent << "Boundary: " << this->Boundary << "\n";
  os << indent << "BoundarySpacing: " << this->BoundarySpacing << "\n";
  os << indent << "Constraints: " << this->Internal->Constraints.size() << "\n";
  os << indent << "LineConstraints: " << this->Internal->Lines.size() << "\n";
  os << indent << "BoundaryHandles: " << this->Internal->Handles.size() << "\n";
  os << indent << "NumberOfSolves: " << this->NumberOfSolves << "\n";
  os << indent << "OptimizeMix: " << this->OptimizeMix << "\n";
  os << indent << "OptimalMixRange: " << this->OptimalMixRange[0] << " " << this->OptimalMixRange[1] << "\n";
  os << indent << "OptimalEnergy: " << this->OptimalEnergy << "\n";
  os << indent << "BoundaryEnergy: " << this->BoundaryEnergy << "\n";
  os << indent << "BoundaryOptimizationSteps: " << this->BoundaryOptimizationSteps << "\n";
  os << indent << "KeepBoundaryBasis: " << this->KeepBoundaryBasis << "\n";
  os << indent << "AtlasForNonDisks: " << this->AtlasForNonDisks << "\n";
  os << indent << "OutputFlattenedMesh: " << this->OutputFlattenedMesh << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
