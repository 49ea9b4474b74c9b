#include "vtkImplicitFairing.h"
#include "vtkBeltramiEnumCheck.h"

#include "vtkBeltramiSurface.h"

#include "Flows/Fairing.h"

#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <cmath>
#include <vector>

BELTRAMI_SAME_ENUM(vtkImplicitFairing::UMBRELLA, beltrami::FairingOperator::Umbrella);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::SCALE_DEPENDENT_UMBRELLA, beltrami::FairingOperator::ScaleDependentUmbrella);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::CURVATURE_FLOW, beltrami::FairingOperator::CurvatureFlow);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::CURVATURE_FLOW_AND_SAMPLING, beltrami::FairingOperator::CurvatureFlowAndSampling);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::IMPLICIT, beltrami::FairingIntegration::Implicit);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::EXPLICIT, beltrami::FairingIntegration::Explicit);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::TAUBIN_LAMBDA_MU, beltrami::FairingIntegration::TaubinLambdaMu);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::AUTOMATIC, beltrami::FairingInvariant::Automatic);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::NONE, beltrami::FairingInvariant::None);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::VOLUME, beltrami::FairingInvariant::Volume);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::AREA, beltrami::FairingInvariant::Area);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::HEIGHT_FIELD_VOLUME, beltrami::FairingInvariant::HeightFieldVolume);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::FIXED, beltrami::FairingBoundary::Fixed);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::SMOOTH_CURVE, beltrami::FairingBoundary::SmoothCurve);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::VIRTUAL_VERTEX, beltrami::FairingBoundary::VirtualVertex);

vtkStandardNewMacro(vtkImplicitFairing);

vtkImplicitFairing::vtkImplicitFairing()
{
  // Input arrays 0 (fixed points) and 1 (weights) are optional: none by default.
}


int vtkImplicitFairing::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->Iterations.clear();
  // Implicit steps and the invariants couple all points: data split over the
  // ranks of a distributed run are smoothed whole on rank 0
  // (vtkBeltramiGather), as in a serial run.
  const auto fair = [this](vtkBeltramiSurface& surface) {
    if (surface.IsGathered() && !this->FixedPointIds.empty())
    {
      vtkWarningMacro("Distributed data gathered on rank 0: the fixed point ids refer to the points of the "
                      "gathered surface (rank 0's piece first); a fixed-points array (input array 0) is the "
                      "reliable way to fix points of distributed data.");
    }
    return this->Fair(surface) != 0;
  };
  const auto received = [this](vtkPolyData* output) { // the solver iterations of rank 0's run
    if (vtkDataArray* iterations = output->GetFieldData()->GetArray("FairingIterations"))
    {
      for (vtkIdType k = 0; k < iterations->GetNumberOfTuples(); ++k)
      {
        this->Iterations.push_back(static_cast<int>(iterations->GetTuple1(k)));
      }
    }
  };
  return vtkBeltramiSurface::Execute(this, inputVector, outputVector, this->NumberOfThreads,
    vtkBeltramiSurface::Needs::WholeSurface, fair, received);
}

int vtkImplicitFairing::Fair(vtkBeltramiSurface& surface)
{
  vtkPolyData* input = surface.Input();
  vtkPolyData* output = surface.Output();
  const vtkIdType numPoints = input->GetNumberOfPoints();
  const beltrami::MeshTopology& topo = surface.Topology();
  if (topo.NumberOfTriangles() == 0)
  {
    vtkWarningMacro("Input has no polygons or triangle strips: the points are left as they are.");
    return 1;
  }
  surface.WarnAboutInput(this, "its piece boundary fixed", "Non-manifold points are kept fixed.");

  std::string error;
  std::vector<std::uint8_t> fixed = this->UseFixedPointsArray
    ? vtkBeltramiSurface::SelectedPointMask(this, input, 0, "fixed-points", error)
    : std::vector<std::uint8_t>();
  if (!this->FixedPointIds.empty())
  {
    fixed.resize(numPoints, 0);
    vtkIdType outside = 0;
    for (vtkIdType id : this->FixedPointIds)
    {
      if (id >= 0 && id < numPoints)
      {
        fixed[id] = 1;
      }
      else
      {
        ++outside;
      }
    }
    if (outside)
    {
      vtkWarningMacro(<< outside << " fixed point id(s) are not points of the input (" << numPoints
                      << " points) and were ignored.");
    }
  }
  vtkDataArray* weightArray = error.empty() && this->UseSmoothingWeightsArray
    ? surface.SelectedPointArray(this, 1, 1, "smoothing-weight", error)
    : nullptr;
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  std::vector<double> weights;
  beltrami::FairingConstraints constraints;
  if (!fixed.empty())
  {
    constraints.Fixed = fixed.data();
  }
  if (weightArray)
  {
    weights.resize(numPoints);
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      weights[i] = weightArray->GetComponent(i, 0);
    }
    constraints.Weights = weights.data();
  }

  // The core works in double, in place.
  std::vector<double> x(3 * static_cast<std::size_t>(numPoints));
  surface.Dispatch([&](const auto* p) {
    std::copy(p, p + x.size(), x.begin());
    return 0;
  });

  beltrami::FairingOptions options;
  options.Operator = static_cast<beltrami::FairingOperator>(this->Operator);
  options.Order = this->Order;
  options.OperatorMollification = this->OperatorMollification;
  options.Integration = static_cast<beltrami::FairingIntegration>(this->Integration);
  options.NumberOfSteps = this->NumberOfSteps;
  options.Tolerance = this->Tolerance;
  options.MaximumIterations = this->MaximumNumberOfIterations;
  options.Invariant = static_cast<beltrami::FairingInvariant>(this->Invariant);
  std::copy(this->ReferencePlaneNormal, this->ReferencePlaneNormal + 3, options.ReferencePlaneNormal);
  options.Boundary = static_cast<beltrami::FairingBoundary>(this->BoundaryHandling);
  options.Anisotropic = this->Anisotropic;
  options.MinimumAnisotropicWeight = this->MinimumAnisotropicWeight;
  options.Mollification = this->Mollification;
  options.SmoothFeatureCurves = this->SmoothFeatureCurves;
  options.TaubinLambda = this->TaubinLambda;
  options.TaubinMu = this->TaubinMu;
  options.NumberOfThreads = this->NumberOfThreads;
  options.TimeStep = this->TimeStep;
  options.FeatureThreshold = this->FeatureThreshold;
  if (this->TimeStepUnits == MEAN_EDGE_LENGTH)
  {
    const double h = beltrami::MeanEdgeLength(topo, x.data());
    if (!(h > 0.0) || !std::isfinite(h))
    {
      vtkErrorMacro("The mean edge length of the input is " << h
                                                            << ": cannot scale the time step.");
      return 0;
    }
    if (this->Operator != UMBRELLA)
    {
      // L has units 1/length^2, L^2 1/length^4.
      options.TimeStep *= this->Order == 2 ? h * h * h * h : h * h;
    }
    options.FeatureThreshold /= h;
  }

  this->UpdateProgress(0.0);
  const beltrami::FairingReport report = beltrami::FairSurface(topo, x.data(), options, constraints,
    [this](double fraction) {
      this->UpdateProgress(fraction);
      return !this->GetAbortExecute();
    });
  if (!report.Completed)
  {
    output->ShallowCopy(input); // aborted: a defined output, the input
    return 1;
  }
  this->Iterations = report.Iterations;

  // New points in the input's precision.
  vtkNew<vtkPoints> points;
  points->SetDataType(input->GetPoints()->GetDataType() == VTK_FLOAT ? VTK_FLOAT : VTK_DOUBLE);
  points->SetNumberOfPoints(numPoints);
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    points->SetPoint(i, x.data() + 3 * i);
  }
  output->SetPoints(points);
  // Normals of the input no longer match the smoothed surface.
  if (output->GetPointData()->GetNormals())
  {
    vtkNew<vtkPointData> pd;
    pd->ShallowCopy(output->GetPointData());
    pd->SetNormals(nullptr);
    output->GetPointData()->ShallowCopy(pd);
  }

  vtkNew<vtkIntArray> iterations;
  iterations->SetName("FairingIterations");
  for (int it : report.Iterations)
  {
    iterations->InsertNextValue(it);
  }
  vtkNew<vtkFieldData> fd;
  fd->ShallowCopy(input->GetFieldData());
  fd->AddArray(iterations);
  if (report.InvariantUsed != beltrami::FairingInvariant::None)
  {
    vtkNew<vtkDoubleArray> inv;
    inv->SetName("FairingInvariant");
    inv->InsertNextValue(report.InitialInvariant);
    inv->InsertNextValue(report.FinalInvariant);
    fd->AddArray(inv);
  }
  output->SetFieldData(fd);

  if (!report.Warning.empty())
  {
    vtkWarningMacro(<< report.Warning);
  }
  if (report.UnusableVertices)
  {
    vtkWarningMacro(<< report.UnusableVertices
                    << " points are non-manifold or have invalid coordinates: they were kept fixed.");
  }
  if (report.DegenerateTriangles)
  {
    vtkWarningMacro(<< report.DegenerateTriangles << " zero-area triangles were skipped (section 3.5.3).");
  }
  return 1;
}

void vtkImplicitFairing::AddFixedPoint(vtkIdType pointId)
{
  this->FixedPointIds.push_back(pointId);
  this->Modified();
}

void vtkImplicitFairing::RemoveAllFixedPoints()
{
  if (!this->FixedPointIds.empty())
  {
    this->FixedPointIds.clear();
    this->Modified();
  }
}

void vtkImplicitFairing::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Operator: " << this->Operator << "\n";
  os << indent << "Order: " << this->Order << "\n";
  os << indent << "OperatorMollification: " << this->OperatorMollification << "\n";
  os << indent << "Integration: " << this->Integration << "\n";
  os << indent << "TimeStep: " << this->TimeStep << "\n";
  os << indent << "TimeStepUnits: " << this->TimeStepUnits << "\n";
  os << indent << "NumberOfSteps: " << this->NumberOfSteps << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "MaximumNumberOfIterations: " << this->MaximumNumberOfIterations << "\n";
  os << indent << "Invariant: " << this->Invariant << "\n";
  os << indent << "ReferencePlaneNormal: " << this->ReferencePlaneNormal[0] << " " << this->ReferencePlaneNormal[1]
     << " " << this->ReferencePlaneNormal[2] << "\n";
  os << indent << "BoundaryHandling: " << this->BoundaryHandling << "\n";
  os << indent << "Anisotropic: " << this->Anisotropic << "\n";
  os << indent << "FeatureThreshold: " << this->FeatureThreshold << "\n";
  os << indent << "Mollification: " << this->Mollification << "\n";
  os << indent << "SmoothFeatureCurves: " << this->SmoothFeatureCurves << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "UseFixedPointsArray: " << this->UseFixedPointsArray << "\n";
  os << indent << "UseSmoothingWeightsArray: " << this->UseSmoothingWeightsArray << "\n";
  os << indent << "Fixed point ids: " << this->FixedPointIds.size() << "\n";
}
