#include "vtkBeltramiGraphFlow.h"

#include "vtkBeltramiSurface.h"

#include "Flows/TensorSpace.h"

#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkPointData.h>

#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>

#include <vtkAlgorithm.h>
#include <vtkSmartPointer.h>

#include <cmath>
#include <sstream>

bool vtkBeltramiGraphFlow::IsPointArray(vtkAlgorithm* owner, vtkDataArray* array, int association)
{
  if (!array || association != vtkDataObject::FIELD_ASSOCIATION_POINTS)
  {
    vtkErrorWithObjectMacro(owner, "No point array to smooth: select a point data array (input array 0). "
                                   "The output is the input.");
    return false;
  }
  return true;
}

void vtkBeltramiGraphFlow::ReplaceArray(
  vtkDataSet* input, vtkDataSet* output, vtkDataArray* original, vtkDataArray* smoothed)
{
  vtkPointData* pd = output->GetPointData();
  pd->AddArray(smoothed);
  if (input->GetPointData()->GetScalars() == original)
  {
    pd->SetScalars(smoothed);
  }
}

void vtkBeltramiGraphFlow::AddReport(vtkFieldData* fd, const beltrami::GraphFlowResult& r)
{
  const auto addInt = [fd](const char* name, int value) {
    vtkNew<vtkIntArray> a;
    a->SetName(name);
    a->InsertNextValue(value);
    fd->AddArray(a);
  };
  const auto addDouble = [fd](const char* name, std::initializer_list<double> values) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    for (double v : values)
    {
      a->InsertNextValue(v);
    }
    fd->AddArray(a);
  };
  addInt("FlowIterations", r.Iterations);
  addDouble("FlowTime", { r.Time });
  addDouble("FlowRMSChange", { r.RMSChange });
  addDouble("FlowArea", { r.InitialArea, r.FinalArea });
  addInt("FlowSolverIterations", r.SolverIterations);
  addDouble("EstimatedNoiseLevel", { r.EstimatedNoiseLevel });
  addDouble("FlowNoiseLevel", { r.NoiseLevel });
  addDouble("FlowContrastScale", { r.ContrastScale });
  if (r.InitialRisk > 0.0)
  {
    addDouble("FlowEstimatedError", { r.InitialRisk, r.FinalRisk });
  }
}

std::string vtkBeltramiGraphFlow::RunWarnings(
  const beltrami::GraphFlowOptions& o, const beltrami::GraphFlowResult& r)
{
  std::ostringstream s;
  if (r.StoppedByLimit)
  {
    s << "The flow reached its iteration limit ("
      << (o.Stop == beltrami::GraphFlowStop::Iterations ? o.NumberOfIterations : o.MaximumNumberOfIterations)
      << ") before its stopping rule"
      << (o.Stop == beltrami::GraphFlowStop::Iterations ? " (the noise level)" : "")
      << ": the data may be under-smoothed. Raise "
      << (o.Stop == beltrami::GraphFlowStop::Iterations ? "NumberOfIterations" : "MaximumNumberOfIterations")
      << " or use a larger TimeStep.";
    if (r.UnstableSteps > 0)
    {
      s << " ";
    }
  }
  if (r.UnstableSteps == 0)
  {
    return s.str();
  }
  s << r.UnstableSteps << " explicit step(s) of " << (o.TimeStep > 0.0 ? o.TimeStep : r.LastTimeStep)
    << " exceeded the stability limit (" << r.SmallestStableStep
    << " at the steepest point); the result may oscillate. Use AdaptiveTimeStep, the semi-implicit "
       "integration or a smaller TimeStep.";
  return s.str();
}

void vtkBeltramiGraphFlow::ToLogEuclidean(vtkAlgorithm* owner, const char* name, double* values, vtkIdType count,
  int numThreads, beltrami::GraphFlowOptions& options)
{
  const std::int64_t raised = beltrami::SymmetricTensorsToLog(values, count, 6, 1e-6, numThreads);
  if (raised)
  {
    vtkWarningWithObjectMacro(owner, << raised << " tensors of '" << name << "' are not positive definite (or "
      "have eigenvalues below 1e-6 of the field's largest): those eigenvalues were raised to that floor.");
  }
  options.ToNoiseSpace = [count, numThreads](double* x) { beltrami::LogToSymmetricTensors(x, count, 6, numThreads); };
  options.FromNoiseSpace = [count, numThreads](double* x) {
    beltrami::SymmetricTensorsToLog(x, count, 6, 1e-6, numThreads);
  };
}

int vtkBeltramiGraphFlow::RunOnMesh(vtkAlgorithm* owner, vtkDataSet* input, vtkDataSet* output,
  vtkDataArray* array, const double* points, bool useMask, const beltrami::GraphFlowOptions& meshOptions,
  int maxComponents, bool logEuclidean, const MeshFlow& flow)
{
  std::string error;
  const std::vector<std::uint8_t> fixed =
    useMask ? vtkBeltramiSurface::SelectedPointMask(owner, input, 1, "fixed-points", error)
            : std::vector<std::uint8_t>();
  if (!error.empty())
  {
    vtkErrorWithObjectMacro(owner, << error << " The output is the input.");
    return 0;
  }
  const int nc = array->GetNumberOfComponents();
  if (nc < 1 || nc > maxComponents)
  {
    vtkErrorWithObjectMacro(owner, "The array '" << (array->GetName() ? array->GetName() : "") << "' has "
                                                 << nc << " components; 1 to " << maxComponents
                                                 << " can be smoothed. The output is the input.");
    return 0;
  }
  const char* name = array->GetName() ? array->GetName() : "";
  if (logEuclidean && nc != 6)
  {
    vtkErrorWithObjectMacro(owner, "Log-Euclidean smoothing needs symmetric tensors of 6 components (XX, YY, ZZ, "
      "XY, YZ, XZ); '" << name << "' has " << nc << ". The output is the input.");
    return 0;
  }
  const vtkIdType numPoints = input->GetNumberOfPoints();
  std::vector<double> values(static_cast<std::size_t>(numPoints) * nc);
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    for (int k = 0; k < nc; ++k)
    {
      values[i * nc + k] = array->GetComponent(i, k);
    }
  }
  beltrami::GraphFlowOptions options = meshOptions;
  if (logEuclidean)
  {
    ToLogEuclidean(owner, name, values.data(), numPoints, options.NumberOfThreads, options);
  }
  owner->UpdateProgress(0.0);
  const beltrami::GraphFlowResult result = flow(points, nc, values.data(),
    fixed.empty() ? nullptr : fixed.data(), options, [owner](double fraction) {
      owner->UpdateProgress(fraction);
      return !owner->GetAbortExecute();
    });
  if (!result.Error.empty())
  {
    vtkErrorWithObjectMacro(owner, << result.Error << ". The output is the input.");
    return 0;
  }
  if (!result.Completed)
  {
    return 1;
  }
  const std::string warning = RunWarnings(options, result);
  if (!warning.empty())
  {
    vtkWarningWithObjectMacro(owner, << warning);
  }
  if (logEuclidean)
  {
    beltrami::LogToSymmetricTensors(values.data(), numPoints, 6, options.NumberOfThreads);
  }
  vtkSmartPointer<vtkDataArray> smoothed = vtkBeltramiSurface::NewArray(VTK_DOUBLE, array->GetName(), nc, numPoints);
  std::copy(values.begin(), values.end(), vtkDoubleArray::SafeDownCast(smoothed)->GetPointer(0));
  ReplaceArray(input, output, array, smoothed);
  AddReport(output->GetFieldData(), result);
  return 1;
}
