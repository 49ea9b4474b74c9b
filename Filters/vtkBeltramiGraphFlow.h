// The part of the graph-flow filters (vtkImageBeltramiDenoising,
// vtkSurfaceDataDenoising, vtkTetrahedralBeltramiDenoising) that does not
// depend on the data type: their common settings mapped to the core's
// options, the report written into the output's field data, the warnings,
// and the body the mesh filters share.  Not wrapped.
#ifndef vtkBeltramiGraphFlow_h
#define vtkBeltramiGraphFlow_h

#include "BeltramiFiltersModule.h" // export macro

#include "Flows/GraphFlow.h"

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <vtkIndent.h>

class vtkAlgorithm;
class vtkDataArray;
class vtkDataSet;
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

  /// The settings every graph-flow filter has, for PrintSelf.
  template <typename Filter>
  static void PrintSettings(Filter* f, std::ostream& os, vtkIndent indent)
  {
    os << indent << "ContrastScale: " << f->GetContrastScale() << "\n";
    os << indent << "EdgeContrast: " << f->GetEdgeContrast() << "\n";
    os << indent << "Integration: " << f->GetIntegration() << "\n";
    os << indent << "TimeStep: " << f->GetTimeStep() << "\n";
    os << indent << "AdaptiveTimeStep: " << f->GetAdaptiveTimeStep() << "\n";
    os << indent << "NumberOfIterations: " << f->GetNumberOfIterations() << "\n";
    os << indent << "NoiseLevel: " << f->GetNoiseLevel() << "\n";
    os << indent << "NumberOfThreads: " << f->GetNumberOfThreads() << "\n";
  }

  /// True when `array` (the owner's input array 0) is a point array; else
  /// reports the error on the owner (the output stays the input).
  static bool IsPointArray(vtkAlgorithm* owner, vtkDataArray* array, int association);

  /// Puts `smoothed` into the output's point data in place of `original`
  /// (same name), keeping it the active scalars if it was.
  static void ReplaceArray(
    vtkDataSet* input, vtkDataSet* output, vtkDataArray* original, vtkDataArray* smoothed);

  /// Field arrays FlowIterations, FlowTime, FlowRMSChange, FlowArea (initial,
  /// final area of the graph surface), FlowSolverIterations.
  static void AddReport(vtkFieldData* fd, const beltrami::GraphFlowResult& result);

  /// A warning for explicit steps beyond the stability limit (empty if none).
  static std::string StabilityWarning(
    const beltrami::GraphFlowOptions& options, const beltrami::GraphFlowResult& result);

  /// Runs the flow on (points, components, values in place, fixed mask).
  using MeshFlow = std::function<beltrami::GraphFlowResult(const double* points, int components,
    double* values, const std::uint8_t* fixed, const beltrami::GraphFlowOptions& options,
    const beltrami::ProgressCallback& progress)>;

  /// The body the mesh filters share (vtkSurfaceDataDenoising,
  /// vtkTetrahedralBeltramiDenoising): checks `array` (the owner's input
  /// array 0: point data, 1 to maxComponents components) and the optional
  /// mask (input array 1, when useMask), measures the mesh in units of
  /// `unit` (its mean edge length, or 1 for physical units), runs `flow`,
  /// and writes the smoothed array (double, same name) and the report
  /// (measures of dimension measureDimension and the time back in the mesh's
  /// units).  Returns the value for RequestData; errors and warnings go to
  /// the owner, and on error the output stays the input.
  static int RunOnMesh(vtkAlgorithm* owner, vtkDataSet* input, vtkDataSet* output, vtkDataArray* array,
    const double* points, bool useMask, const beltrami::GraphFlowOptions& options, int maxComponents,
    double unit, int measureDimension, const MeshFlow& flow);
};

#endif
// VTK-HeaderTest-Exclude: vtkBeltramiGraphFlow.h
