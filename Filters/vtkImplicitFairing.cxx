#include "vtkImplicitFairing.h"
#include "vtkBeltramiSettings.h"

#include "vtkBeltramiSurface.h"

#include "Flows/Fairing.h"

#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>

#include <exception>
#include <tuple>
#include <utility>
#include <vtkFloatArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <cmath>
#include <exception>
#include <vector>

BELTRAMI_SAME_ENUM(vtkImplicitFairing::UMBRELLA, beltrami::FairingOperator::Umbrella);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::SCALE_DEPENDENT_UMBRELLA, beltrami::FairingOperator::ScaleDependentUmbrella);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::CURVATURE_FLOW, beltrami::FairingOperator::CurvatureFlow);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::CURVATURE_FLOW_AND_SAMPLING, beltrami::FairingOperator::CurvatureFlowAndSampling);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::LEAST_ESTIMATED_ERROR, beltrami::FairingOperator::LeastEstimatedError);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::IMPLICIT, beltrami::FairingIntegration::Implicit);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::EXPLICIT, beltrami::FairingIntegration::Explicit);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::TAUBIN_LAMBDA_MU, beltrami::FairingIntegration::TaubinLambdaMu);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::AUTOMATIC, beltrami::FairingInvariant::Automatic);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::NONE, beltrami::FairingInvariant::None);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::VOLUME, beltrami::FairingInvariant::Volume);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::AREA, beltrami::FairingInvariant::Area);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::HEIGHT_FIELD_VOLUME, beltrami::FairingInvariant::HeightFieldVolume);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::REVOLUTION_VOLUME, beltrami::FairingInvariant::RevolutionVolume);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::FIXED, beltrami::FairingBoundary::Fixed);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::SMOOTH_CURVE, beltrami::FairingBoundary::SmoothCurve);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::VIRTUAL_VERTEX, beltrami::FairingBoundary::VirtualVertex);

BELTRAMI_SAME_ENUM(vtkImplicitFairing::MEAN_EDGE_LENGTH, beltrami::LengthUnit::MeanEdgeLength);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::PHYSICAL, beltrami::LengthUnit::Physical);

BELTRAMI_SAME_ENUM(vtkImplicitFairing::JACOBI, beltrami::Preconditioning::Jacobi);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::MULTIGRID, beltrami::Preconditioning::Multigrid);
BELTRAMI_SAME_ENUM(vtkImplicitFairing::GEOMETRIC_MULTIGRID, beltrami::Preconditioning::GeometricMultigrid);

vtkStandardNewMacro(vtkImplicitFairing);

vtkImplicitFairing::vtkImplicitFairing()
{
  // The defaults have one source: the core's FairingOptions.
  beltrami::FairingOptions defaults;
  this->CopySettings(defaults, vtkBeltramiCopy::FromCore);
  // Input arrays 0 (fixed points) and 1 (weights) are optional: none by default.
}

void vtkImplicitFairing::CopySettings(beltrami::FairingOptions& o, vtkBeltramiCopy direction)
{
  BeltramiCopySetting(this->Operator, o.Operator, direction);
  BeltramiCopySetting(this->Order, o.Order, direction);
  for (int k = 0; k < 4; ++k)
  {
    BeltramiCopySetting(this->OrderWeights[k], o.OrderWeights[k], direction);
  }
  BeltramiCopySetting(this->OperatorMollification, o.OperatorMollification, direction);
  BeltramiCopySetting(this->Integration, o.Integration, direction);
  BeltramiCopySetting(this->TimeStep, o.TimeStep, direction);
  BeltramiCopySetting(this->Units, o.Units, direction);
  BeltramiCopySetting(this->NumberOfIterations, o.NumberOfIterations, direction);
  BeltramiCopySetting(this->SolverTolerance, o.SolverTolerance, direction);
  BeltramiCopySetting(this->MaximumSolverIterations, o.MaximumSolverIterations, direction);
  BeltramiCopySetting(this->Preconditioner, o.Preconditioner, direction);
  BeltramiCopySetting(this->Invariant, o.Invariant, direction);
  for (int k = 0; k < 3; ++k)
  {
    BeltramiCopySetting(this->ReferencePlaneNormal[k], o.ReferencePlaneNormal[k], direction);
  }
  BeltramiCopySetting(this->BoundaryHandling, o.Boundary, direction);
  BeltramiCopySetting(this->Anisotropic, o.Anisotropic, direction);
  BeltramiCopySetting(this->FeatureThreshold, o.FeatureThreshold, direction);
  BeltramiCopySetting(this->MinimumAnisotropicWeight, o.MinimumAnisotropicWeight, direction);
  BeltramiCopySetting(this->Mollification, o.Mollification, direction);
  BeltramiCopySetting(this->SmoothFeatureCurves, o.SmoothFeatureCurves, direction);
  BeltramiCopySetting(this->KeepFirstOperator, o.KeepFirstOperator, direction);
  BeltramiCopySetting(this->TaubinLambda, o.TaubinLambda, direction);
  BeltramiCopySetting(this->TaubinMu, o.TaubinMu, direction);
  BeltramiCopySetting(this->NumberOfThreads, o.NumberOfThreads, direction);
  BeltramiCopySetting(this->StepSearchPoints, o.StepSearchPoints, direction);
}


int vtkImplicitFairing::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->Iterations.clear();
  // Implicit steps and the invariants couple all points.  Data split over
  // the ranks of a distributed run are solved over the ranks, each rank
  // holding its own piece (vtkBeltramiSurface::Needs::Distributed); the
  // options that the distributed run does not cover (virtual vertices:
  // beltrami::DistributedFairingLimitation), and fixed
  // point ids (which name points of one data set), gather the pieces on
  // rank 0 (vtkBeltramiGather) and smooth the whole surface there.
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
  beltrami::FairingOptions options;
  this->CopySettings(options, vtkBeltramiCopy::ToCore);
  const bool distributes = this->FixedPointIds.empty() && beltrami::DistributedFairingLimitation(options).empty();
  return vtkBeltramiSurface::Execute(this, inputVector, outputVector, this->NumberOfThreads,
    distributes ? vtkBeltramiSurface::Needs::Distributed : vtkBeltramiSurface::Needs::WholeSurface, fair, received);
}

int vtkImplicitFairing::Fair(vtkBeltramiSurface& surface)
{
  const beltrami::MeshTopology& topo = surface.Topology();
  const beltrami::Partition* split = surface.Split(); // a distributed run: the ranks solve together
  const double triangles = static_cast<double>(topo.NumberOfTriangles());
  if ((split ? split->Sum(triangles) : triangles) == 0.0)
  {
    vtkWarningMacro("Input has no polygons or triangle strips: the points are left as they are.");
    return 1;
  }
  if (!split) // (a split piece's own defects are those of its cut: the report counts the real ones)
  {
    surface.WarnAboutInput(this, "its piece boundary fixed", "Non-manifold points are kept fixed.");
  }
  std::vector<std::uint8_t> fixed;
  std::vector<double> weights, axes, normals;
  if (!surface.AllAgree(this->GatherConstraints(surface, fixed, weights, axes, normals)))
  {
    return 0;
  }
  // Distributed: one value per point of the topology (the ghosts get their
  // owners' in the core).
  const std::size_t rows = static_cast<std::size_t>(surface.NumberOfTopologyPoints());
  if (!fixed.empty())
  {
    fixed.resize(rows, 0);
  }
  if (!weights.empty())
  {
    weights.resize(rows, 1.0);
  }
  for (std::vector<double>* directions : { &axes, &normals })
  {
    if (!directions->empty())
    {
      directions->resize(3 * rows, 0.0);
    }
  }
  beltrami::FairingConstraints constraints;
  constraints.Fixed = fixed.empty() ? nullptr : fixed.data();
  constraints.Weights = weights.empty() ? nullptr : weights.data();
  constraints.AxisDirections = axes.empty() ? nullptr : axes.data();
  constraints.PlaneNormals = normals.empty() ? nullptr : normals.data();

  // The core works in double, in place (distributed: the ghost points too).
  std::vector<double> x(3 * rows);
  surface.Dispatch([&](const auto* p) {
    std::copy(p, p + x.size(), x.begin());
    return 0;
  });
  beltrami::FairingOptions options;
  this->CopySettings(options, vtkBeltramiCopy::ToCore);
  this->UpdateProgress(0.0);
  beltrami::FairingReport report;
  try // the multigrid solver needs MPI and hypre: failures there are errors, not crashes
  {
    report = beltrami::FairSurface(topo, x.data(), options, constraints, [this](double fraction) {
      this->UpdateProgress(fraction);
      return !this->GetAbortExecute();
    }, split);
  }
  catch (const std::exception& e)
  {
    report.Error = e.what();
  }
  if (!report.Error.empty())
  {
    vtkErrorMacro(<< report.Error);
    return 0;
  }
  if (!report.Completed)
  {
    surface.Output()->ShallowCopy(surface.Input()); // aborted: a defined output, the input
    return 1;
  }
  this->Iterations = report.Iterations;
  this->WriteOutput(surface, x, report);
  return 1;
}

bool vtkImplicitFairing::GatherConstraints(vtkBeltramiSurface& surface, std::vector<std::uint8_t>& fixed,
  std::vector<double>& weights, std::vector<double>& axes, std::vector<double>& normals)
{
  vtkPolyData* input = surface.Input();
  const vtkIdType numPoints = input->GetNumberOfPoints();
  std::string error;
  if (this->UseFixedPointsArray)
  {
    fixed = vtkBeltramiSurface::SelectedPointMask(this, input, FIXED_POINTS_ARRAY, "fixed-points", error);
  }
  if (!this->FixedPointIds.empty())
  {
    fixed.resize(numPoints, 0);
    vtkIdType outside = 0;
    for (vtkIdType id : this->FixedPointIds)
    {
      const bool inside = id >= 0 && id < numPoints;
      outside += inside ? 0 : 1;
      if (inside)
      {
        fixed[id] = 1;
      }
    }
    if (outside)
    {
      vtkWarningMacro(<< outside << " fixed point id(s) are not points of the input (" << numPoints
                      << " points) and were ignored.");
    }
  }
  vtkDataArray* weightArray = error.empty() && this->UseSmoothingWeightsArray
    ? surface.SelectedPointArray(this, SMOOTHING_WEIGHTS_ARRAY, 1, "smoothing-weight", error)
    : nullptr;
  // Section 3.2.7's axis and plane constraints: 3-component point arrays.
  for (auto [use, idx, what, values] : { std::tuple{ this->UseAxisDirectionsArray, AXIS_DIRECTIONS_ARRAY,
                                           "axis-direction", &axes },
         std::tuple{ this->UsePlaneNormalsArray, PLANE_NORMALS_ARRAY, "plane-normal", &normals } })
  {
    vtkDataArray* array = error.empty() && use ? surface.SelectedPointArray(this, idx, 3, what, error) : nullptr;
    vtkIdType nonFinite = 0;
    for (vtkIdType i = 0; array && i < numPoints; ++i)
    {
      values->resize(3 * static_cast<std::size_t>(numPoints));
      double* d = values->data() + 3 * i;
      array->GetTuple(i, d);
      nonFinite += std::isfinite(d[0]) && std::isfinite(d[1]) && std::isfinite(d[2]) ? 0 : 1;
    }
    if (nonFinite > 0)
    {
      vtkWarningMacro(<< nonFinite << " " << what << " vectors are NaN or infinite: those points move freely.");
    }
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  if (weightArray)
  {
    weights.resize(numPoints);
    vtkIdType outside = 0;
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      weights[i] = weightArray->GetComponent(i, 0);
      outside += weights[i] >= 0.0 && weights[i] <= 1.0 ? 0 : 1;
    }
    if (outside > 0)
    {
      vtkWarningMacro(<< outside << " smoothing weights are outside [0, 1], NaN or infinite: clamped to [0, 1] "
                      << "(NaN and infinite values as 1).");
    }
  }
  return true;
}

void vtkImplicitFairing::WriteOutput(
  vtkBeltramiSurface& surface, const std::vector<double>& x, const beltrami::FairingReport& report)
{
  vtkPolyData* input = surface.Input();
  vtkPolyData* output = surface.Output();
  const vtkIdType numPoints = input->GetNumberOfPoints();
  // New points in the input's precision (an empty piece of a distributed run keeps its own).
  vtkNew<vtkPoints> points;
  points->SetDataType(input->GetPoints() && input->GetPoints()->GetDataType() == VTK_FLOAT ? VTK_FLOAT : VTK_DOUBLE);
  points->SetNumberOfPoints(numPoints);
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    points->SetPoint(i, x.data() + 3 * i);
  }
  if (numPoints > 0)
  {
    output->SetPoints(points);
  }
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
  if (report.MedianDihedral > 0.0 || report.Noise > 0.0)
  {
    // A chosen time step: what it was chosen from, and its estimated error.
    for (auto [name, value] : { std::pair{ "FairingNoise", report.Noise },
           std::pair{ "FairingTimeStep", report.ChosenTimeStep },
           std::pair{ "FairingTangentialNoise", report.TangentialNoise },
           std::pair{ "FairingEstimatedError", report.EstimatedError },
           std::pair{ "FairingOperator", static_cast<double>(report.OperatorUsed) },
           std::pair{ "FairingSampledPoints", static_cast<double>(report.SampledPoints) } })
    {
      vtkNew<vtkDoubleArray> a;
      a->SetName(name);
      a->InsertNextValue(value);
      fd->AddArray(a);
    }
  }
  if (report.LargestGain > 1.0)
  {
    vtkNew<vtkDoubleArray> gain;
    gain->SetName("FairingLargestGain");
    gain->InsertNextValue(report.LargestGain);
    fd->AddArray(gain);
  }
  if (surface.Split())
  {
    surface.SplitPieces().AddDistribution(fd, "FairingDistribution");
  }
  output->SetFieldData(fd);

  if (surface.Split() && surface.Split()->Rank() > 0)
  {
    return; // a distributed run's report is global: rank 0 tells it
  }
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
  os << indent << "OrderWeights: " << this->OrderWeights[0] << " " << this->OrderWeights[1] << " " << this->OrderWeights[2]
     << " " << this->OrderWeights[3] << "\n";
  os << indent << "OperatorMollification: " << this->OperatorMollification << "\n";
  os << indent << "Integration: " << this->Integration << "\n";
  os << indent << "TimeStep: " << this->TimeStep << "\n";
  os << indent << "Units: " << this->Units << "\n";
  os << indent << "NumberOfIterations: " << this->NumberOfIterations << "\n";
  os << indent << "SolverTolerance: " << this->SolverTolerance << "\n";
  os << indent << "MaximumSolverIterations: " << this->MaximumSolverIterations << "\n";
  os << indent << "Preconditioner: " << this->Preconditioner << "\n";
  os << indent << "Invariant: " << this->Invariant << "\n";
  os << indent << "ReferencePlaneNormal: " << this->ReferencePlaneNormal[0] << " " << this->ReferencePlaneNormal[1]
     << " " << this->ReferencePlaneNormal[2] << "\n";
  os << indent << "BoundaryHandling: " << this->BoundaryHandling << "\n";
  os << indent << "Anisotropic: " << this->Anisotropic << "\n";
  os << indent << "FeatureThreshold: " << this->FeatureThreshold << "\n";
  os << indent << "MinimumAnisotropicWeight: " << this->MinimumAnisotropicWeight << "\n";
  os << indent << "Mollification: " << this->Mollification << "\n";
  os << indent << "SmoothFeatureCurves: " << this->SmoothFeatureCurves << "\n";
  os << indent << "TaubinLambda: " << this->TaubinLambda << "\n";
  os << indent << "TaubinMu: " << this->TaubinMu << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "UseFixedPointsArray: " << this->UseFixedPointsArray << "\n";
  os << indent << "UseSmoothingWeightsArray: " << this->UseSmoothingWeightsArray << "\n";
  os << indent << "KeepFirstOperator: " << this->KeepFirstOperator << "\n";
  os << indent << "UseAxisDirectionsArray: " << this->UseAxisDirectionsArray << "\n";
  os << indent << "UsePlaneNormalsArray: " << this->UsePlaneNormalsArray << "\n";
  os << indent << "Fixed point ids: " << this->FixedPointIds.size() << "\n";
}
