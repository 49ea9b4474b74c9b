#include "vtkBeltramiGraphFlow.h"

#include "vtkBeltramiSurface.h"

#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkPointData.h>

#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>

#include <sstream>

std::vector<std::uint8_t> vtkBeltramiGraphFlow::FixedMask(vtkAlgorithm* owner, vtkDataSet* input,
  vtkDataArray* smoothed, const char* what, std::string& error)
{
  std::vector<std::uint8_t> fixed;
  vtkDataArray* mask = vtkBeltramiSurface::SelectedPointArray(owner, input, 1, 1, what, error);
  if (mask && mask != smoothed)
  {
    const vtkIdType n = mask->GetNumberOfTuples();
    fixed.resize(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      fixed[i] = mask->GetComponent(i, 0) != 0.0;
    }
  }
  return fixed;
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
}

std::string vtkBeltramiGraphFlow::StabilityWarning(
  const beltrami::GraphFlowOptions& o, const beltrami::GraphFlowResult& r)
{
  if (r.UnstableSteps == 0)
  {
    return {};
  }
  std::ostringstream s;
  s << r.UnstableSteps << " explicit step(s) of " << o.TimeStep
    << " exceeded the stability limit (" << r.SmallestStableStep
    << " at the steepest point); the result may oscillate. Use AdaptiveTimeStep, the semi-implicit "
       "integration or a smaller TimeStep.";
  return s.str();
}
