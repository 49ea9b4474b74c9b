#include "vtkDiscreteCurvatures.h"
#include "vtkBeltramiSettings.h"

#include "vtkBeltramiSurface.h"

#include "Mesh/Curvatures.h"

#include <vtkDoubleArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include <limits>
#include <vector>

BELTRAMI_SAME_ENUM(vtkDiscreteCurvatures::MEYER_2003, beltrami::CurvatureMethod::Meyer2003);
BELTRAMI_SAME_ENUM(vtkDiscreteCurvatures::TAUBIN_1995, beltrami::CurvatureMethod::Taubin1995);
BELTRAMI_SAME_ENUM(vtkDiscreteCurvatures::MEAN_CURVATURE_NORMAL, beltrami::NormalWeighting::MeanCurvatureNormal);
BELTRAMI_SAME_ENUM(vtkDiscreteCurvatures::UNIFORM, beltrami::NormalWeighting::Uniform);
BELTRAMI_SAME_ENUM(vtkDiscreteCurvatures::ANGLE, beltrami::NormalWeighting::Angle);
BELTRAMI_SAME_ENUM(vtkDiscreteCurvatures::MAX_1999, beltrami::NormalWeighting::Max1999);
BELTRAMI_SAME_ENUM(vtkDiscreteCurvatures::AREA, beltrami::NormalWeighting::Area);
BELTRAMI_SAME_ENUM(vtkDiscreteCurvatures::BOUNDARY_NAN, beltrami::BoundaryPolicy::NaN);
BELTRAMI_SAME_ENUM(vtkDiscreteCurvatures::INTERIOR_AVERAGE, beltrami::BoundaryPolicy::InteriorAverage);

vtkStandardNewMacro(vtkDiscreteCurvatures);

vtkDiscreteCurvatures::vtkDiscreteCurvatures()
{
  // The defaults have one source: the core's CurvatureOptions.
  beltrami::CurvatureOptions defaults;
  this->CopySettings(defaults, vtkBeltramiCopy::FromCore);
}

void vtkDiscreteCurvatures::CopySettings(beltrami::CurvatureOptions& o, vtkBeltramiCopy direction)
{
  BeltramiCopySetting(this->Method, o.Method, direction);
  BeltramiCopySetting(this->NormalWeighting, o.Weighting, direction);
  BeltramiCopySetting(this->BoundaryHandling, o.Boundary, direction);
  BeltramiCopySetting(this->NumberOfThreads, o.NumberOfThreads, direction);
}

int vtkDiscreteCurvatures::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Curvature at a point needs its whole 1-ring.  Streamed pieces (one
  // process) need one more ghost level from upstream.  Pieces that are the
  // ranks of a distributed run exchange their edge triangles themselves
  // (vtkBeltramiSurface::Execute): asking upstream for ghost cells there
  // would re-execute it (a RedistributeDataSet of a 4.8M-triangle surface
  // ran again for over a minute) and most sources cannot make them.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int piece = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
  const int pieces = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES());
  const int ghosts = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS());
  const bool streamed = pieces > 1 && !vtkBeltramiSurface::OnePiecePerRank(outInfo);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), piece);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), pieces);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), ghosts + (streamed ? 1 : 0));
  return 1;
}

namespace
{

vtkSmartPointer<vtkDoubleArray> AddArray(
  vtkPointData* pd, bool wanted, const char* name, int components, vtkIdType tuples)
{
  if (!wanted)
  {
    return nullptr;
  }
  vtkSmartPointer<vtkDoubleArray> array =
    vtkDoubleArray::SafeDownCast(vtkBeltramiSurface::NewArray(VTK_DOUBLE, name, components, tuples));
  pd->AddArray(array);
  return array;
}

double* Pointer(vtkDoubleArray* a)
{
  return a ? a->GetPointer(0) : nullptr;
}

} // namespace

int vtkDiscreteCurvatures::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The whole 1-rings of the points at the edge of a piece.
  return vtkBeltramiSurface::Execute(this, inputVector, outputVector, this->NumberOfThreads,
    vtkBeltramiSurface::Needs::OneRings, [this](vtkBeltramiSurface& surface) { return this->Compute(surface) != 0; });
}

int vtkDiscreteCurvatures::Compute(vtkBeltramiSurface& surface)
{
  vtkPolyData* input = surface.Input();
  vtkPolyData* output = surface.Output();
  // Computed on the topology's points (generated ghost points last), kept
  // for the input's.
  const vtkIdType numPoints = surface.NumberOfTopologyPoints();
  const int pieces = surface.PiecesWithData();
  const beltrami::MeshTopology& topo = surface.Topology();
  if (topo.NumberOfTriangles() == 0)
  {
    vtkWarningMacro("Input has no polygons or triangle strips"
      << (surface.NumberOfIgnoredCells() ? " (vertices and lines are ignored)" : "")
      << ": curvatures are undefined (NaN) at every point.");
  }
  else if (pieces <= 1 && !surface.TopologyWarning().empty())
  {
    // (A piece of distributed data has pinched fans and unused points at the
    // edge of its ghost layer: not a defect of the user's surface.)
    vtkWarningMacro(<< surface.TopologyWarning()
                    << ". Curvatures are undefined (NaN, see VertexStatus) at boundary and "
                       "non-manifold points.");
  }

  vtkPointData* pd = output->GetPointData();
  auto meanCurvatureNormal =
    AddArray(pd, this->ComputeMeanCurvatureNormal, "MeanCurvatureNormal", 3, numPoints);
  auto mixedArea = AddArray(pd, this->ComputeMixedArea, "MixedArea", 1, numPoints);
  if (mixedArea)
  {
    surface.MarkShareOfMeasure(mixedArea); // (a point's share of the area)
  }
  auto meanCurvature = AddArray(pd, this->ComputeMeanCurvature, "MeanCurvature", 1, numPoints);
  auto gaussian = AddArray(pd, this->ComputeGaussianCurvature, "GaussianCurvature", 1, numPoints);
  auto maximum = AddArray(pd, this->ComputePrincipalCurvatures, "MaximumCurvature", 1, numPoints);
  auto minimum = AddArray(pd, this->ComputePrincipalCurvatures, "MinimumCurvature", 1, numPoints);
  auto e1 = AddArray(pd, this->ComputePrincipalDirections, "PrincipalDirection1", 3, numPoints);
  auto e2 = AddArray(pd, this->ComputePrincipalDirections, "PrincipalDirection2", 3, numPoints);
  auto normals = AddArray(pd, this->ComputeNormals, "Normals", 3, numPoints);
  vtkSmartPointer<vtkUnsignedCharArray> status;
  if (this->ComputeVertexStatus)
  {
    status = vtkSmartPointer<vtkUnsignedCharArray>::New();
    status->SetName("VertexStatus");
    status->SetNumberOfTuples(numPoints);
    pd->AddArray(status);
  }
  if (normals)
  {
    pd->SetNormals(normals);
  }
  if (meanCurvature)
  {
    pd->SetActiveScalars("MeanCurvature");
  }

  beltrami::CurvatureOptions options;
  this->CopySettings(options, vtkBeltramiCopy::ToCore);
  beltrami::CurvatureOutputs out;
  out.MeanCurvatureNormal = Pointer(meanCurvatureNormal);
  out.MixedArea = Pointer(mixedArea);
  out.MeanCurvature = Pointer(meanCurvature);
  out.GaussianCurvature = Pointer(gaussian);
  out.MaximumCurvature = Pointer(maximum);
  out.MinimumCurvature = Pointer(minimum);
  out.PrincipalDirection1 = Pointer(e1);
  out.PrincipalDirection2 = Pointer(e2);
  out.Normals = Pointer(normals);
  out.Status = status ? status->GetPointer(0) : nullptr;

  this->UpdateProgress(0.0);
  const auto progress = [this](double fraction) {
    this->UpdateProgress(fraction);
    return !this->GetAbortExecute();
  };
  const beltrami::CurvatureReport report = surface.Dispatch(
    [&](const auto* points) { return beltrami::ComputeCurvatures(topo, points, options, out, progress); });
  if (!report.Completed)
  {
    // Aborted: leave a defined output (the input and no partial arrays).
    output->ShallowCopy(input);
    return 1;
  }
  if (numPoints > surface.NumberOfInputPoints())
  {
    for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
    {
      vtkDataArray* array = pd->GetArray(a);
      if (array && array->GetNumberOfTuples() == numPoints)
      {
        array->SetNumberOfTuples(surface.NumberOfInputPoints()); // drops the ghost points' values
      }
    }
  }
  if (report.NonFiniteVertices)
  {
    vtkWarningMacro(<< report.NonFiniteVertices
                    << " points have NaN or infinite coordinates in their 1-ring: their outputs are NaN.");
  }
  if (report.DegenerateTriangleVertices)
  {
    vtkWarningMacro(<< report.DegenerateTriangleVertices
                    << " points touch zero-area triangles, whose cotangents and areas were left out of "
                       "their 1-ring (their angles count: pi shared where two corners coincide; VertexStatus bit 32).");
  }
  return 1;
}

void vtkDiscreteCurvatures::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << this->Method << "\n";
  os << indent << "NormalWeighting: " << this->NormalWeighting << "\n";
  os << indent << "BoundaryHandling: " << this->BoundaryHandling << "\n";
  os << indent << "ComputeMeanCurvatureNormal: " << this->ComputeMeanCurvatureNormal << "\n";
  os << indent << "ComputeMixedArea: " << this->ComputeMixedArea << "\n";
  os << indent << "ComputeMeanCurvature: " << this->ComputeMeanCurvature << "\n";
  os << indent << "ComputeGaussianCurvature: " << this->ComputeGaussianCurvature << "\n";
  os << indent << "ComputePrincipalCurvatures: " << this->ComputePrincipalCurvatures << "\n";
  os << indent << "ComputePrincipalDirections: " << this->ComputePrincipalDirections << "\n";
  os << indent << "ComputeNormals: " << this->ComputeNormals << "\n";
  os << indent << "ComputeVertexStatus: " << this->ComputeVertexStatus << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
