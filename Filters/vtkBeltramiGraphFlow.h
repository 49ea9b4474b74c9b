// The part of the graph-flow filters (vtkImageBeltramiDenoising,
// vtkSurfaceDataDenoising) that does not depend on the data type: their
// common settings mapped to the core's options, the report written into the
// output's field data, and the warnings.  Not wrapped.
#ifndef vtkBeltramiGraphFlow_h
#define vtkBeltramiGraphFlow_h

#include "BeltramiFiltersModule.h" // export macro

#include "Core/GraphFlow.h"

#include <string>

class vtkFieldData;

class BELTRAMIFILTERS_EXPORT vtkBeltramiGraphFlow
{
public:
  /// Reads the settings every graph-flow filter has (same getter names).
  template <typename Filter>
  static beltrami::GraphFlowOptions Options(Filter* f)
  {
    beltrami::GraphFlowOptions o;
    o.ContrastScale = f->GetContrastScale();
    o.EdgeContrast = f->GetEdgeContrast();
    o.Integration = static_cast<beltrami::GraphFlowIntegration>(f->GetIntegration());
    o.TimeStep = f->GetTimeStep();
    o.AdaptiveTimeStep = f->GetAdaptiveTimeStep();
    o.NumberOfIterations = f->GetNumberOfIterations();
    o.NoiseLevel = f->GetNoiseLevel();
    o.NumberOfThreads = f->GetNumberOfThreads();
    return o;
  }

  /// Field arrays FlowIterations, FlowTime, FlowRMSChange, FlowArea (initial,
  /// final area of the graph surface), FlowSolverIterations.
  static void AddReport(vtkFieldData* fd, const beltrami::GraphFlowResult& result);

  /// A warning for explicit steps beyond the stability limit (empty if none).
  static std::string StabilityWarning(
    const beltrami::GraphFlowOptions& options, const beltrami::GraphFlowResult& result);
};

#endif
// VTK-HeaderTest-Exclude: vtkBeltramiGraphFlow.h
