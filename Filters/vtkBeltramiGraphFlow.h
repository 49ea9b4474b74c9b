// The part of the graph-flow filters (vtkImageBeltramiDenoising,
// vtkSurfaceDataDenoising, vtkTetrahedralBeltramiDenoising) that does not
// depend on the data type: their common settings mapped to the core's
// options, the report written into the output's field data, the warnings,
// and the body the mesh filters share.  Not wrapped.
#ifndef vtkBeltramiGraphFlow_h
#define vtkBeltramiGraphFlow_h

#include "BeltramiFiltersModule.h" // export macro

#include "vtkBeltramiSettings.h"

#include "Flows/GraphFlow.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

#include <vtkIndent.h>
#include <vtkSmartPointer.h>

class vtkAlgorithm;
class vtkBeltramiPieces;
class vtkDataArray;
class vtkDataSet;
class vtkFieldData;
class vtkImageData;
class vtkInformation;
class vtkUnstructuredGrid;
namespace beltrami
{
class TetrahedralMesh;
}

class BELTRAMIFILTERS_EXPORT vtkBeltramiGraphFlow
{
public:
  /// Copies the settings every graph-flow filter has (vtkBeltramiGraphFlow-
  /// SettingsMacro) to or from the core's options: from GraphFlowOptions{}
  /// or GraphFlowOptions::ForMeshes() in the constructors (the defaults'
  /// one source), to the options of a run.
  template <typename Filter>
  static void CopySettings(Filter* f, beltrami::GraphFlowOptions& o, vtkBeltramiCopy direction)
  {
    BeltramiCopySetting(f->ContrastScale, o.ContrastScale, direction);
    BeltramiCopySetting(f->EdgeContrast, o.EdgeContrast, direction);
    BeltramiCopySetting(f->Integration, o.Integration, direction);
    BeltramiCopySetting(f->TimeStep, o.TimeStep, direction);
    BeltramiCopySetting(f->AdaptiveTimeStep, o.AdaptiveTimeStep, direction);
    BeltramiCopySetting(f->NumberOfIterations, o.NumberOfIterations, direction);
    BeltramiCopySetting(f->StoppingRule, o.Stop, direction);
    BeltramiCopySetting(f->MaximumNumberOfIterations, o.MaximumNumberOfIterations, direction);
    BeltramiCopySetting(f->NoiseLevel, o.NoiseLevel, direction);
    BeltramiCopySetting(f->Units, o.Units, direction);
    BeltramiCopySetting(f->NumberOfThreads, o.NumberOfThreads, direction);
  }

  /// The core's options of a run.
  template <typename Filter>
  static beltrami::GraphFlowOptions Options(Filter* f)
  {
    beltrami::GraphFlowOptions o;
    CopySettings(f, o, vtkBeltramiCopy::ToCore);
    return o;
  }

  /// The settings every graph-flow filter has, for PrintSelf.
  template <typename Filter>
  static void PrintSettings(Filter* f, std::ostream& os, vtkIndent indent)
  {
    os << indent << "ContrastScale: " << f->ContrastScale << "\n";
    os << indent << "EdgeContrast: " << f->EdgeContrast << "\n";
    os << indent << "Integration: " << f->Integration << "\n";
    os << indent << "TimeStep: " << f->TimeStep << "\n";
    os << indent << "AdaptiveTimeStep: " << f->AdaptiveTimeStep << "\n";
    os << indent << "NumberOfIterations: " << f->NumberOfIterations << "\n";
    os << indent << "StoppingRule: " << f->StoppingRule << "\n";
    os << indent << "MaximumNumberOfIterations: " << f->MaximumNumberOfIterations << "\n";
    os << indent << "NoiseLevel: " << f->NoiseLevel << "\n";
    os << indent << "NumberOfThreads: " << f->NumberOfThreads << "\n";
    os << indent << "UseFixedPointsArray: " << f->UseFixedPointsArray << "\n";
  }

  /// True when `array` (the owner's input array 0) is a point array; else
  /// reports the error on the owner (the output stays the input).
  static bool IsPointArray(vtkAlgorithm* owner, vtkDataArray* array, int association);

  /// Puts `smoothed` into the output's point data in place of `original`
  /// (same name), keeping it the active scalars if it was.
  static void ReplaceArray(
    vtkDataSet* input, vtkDataSet* output, vtkDataArray* original, vtkDataArray* smoothed);

  /// v as a value of type T: integers rounded and clamped to T's range.
  template <typename T>
  static T ToValue(double v)
  {
    if (std::is_integral<T>::value)
    {
      v = std::round(v);
      v = std::min<double>(std::max<double>(v, std::numeric_limits<T>::lowest()), std::numeric_limits<T>::max());
    }
    return static_cast<T>(v);
  }

  /// A new array of the type, name and components of `like` holding
  /// `values` (`tuples` of them): the smoothed data keep their type (a
  /// scan's colours stay unsigned char, which ParaView shows as colours),
  /// integers rounded and clamped.
  static vtkSmartPointer<vtkDataArray> ArrayLike(vtkDataArray* like, const double* values, vtkIdType tuples);

  /// Field arrays FlowIterations, FlowTime, FlowRMSChange, FlowArea (initial,
  /// final area of the graph surface), FlowSolverIterations,
  /// EstimatedNoiseLevel (from the input alone), and the settings the run
  /// used: FlowNoiseLevel, FlowContrastScale; with the least-risk stop
  /// FlowEstimatedError (estimated RMS error to the clean data: input, result).
  static void AddReport(vtkFieldData* fd, const beltrami::GraphFlowResult& result);

  /// Warnings for explicit steps beyond the stability limit, for a
  /// rule-based stop cut short by the iteration limit and for semi-implicit
  /// solves that stopped short of their tolerance (empty if none).
  static std::string RunWarnings(
    const beltrami::GraphFlowOptions& options, const beltrami::GraphFlowResult& result);

  /// Runs the flow on (points, components, values in place, fixed mask).
  using MeshFlow = std::function<beltrami::GraphFlowResult(const double* points, int components,
    double* values, const std::uint8_t* fixed, const beltrami::GraphFlowOptions& options,
    const beltrami::ProgressCallback& progress)>;

  /// The body the mesh filters share (vtkSurfaceDataDenoising,
  /// vtkTetrahedralBeltramiDenoising): checks `array` (the owner's input
  /// array 0: point data, 1 to maxComponents components) and the optional
  /// mask (input array 1, when useMask), runs `flow` (the core measures the
  /// mesh in the options' Units), and writes the smoothed array (double,
  /// same name) and the report.  Returns the value for RequestData; errors
  /// and warnings go to the owner, and on error the output stays the input.
  /// split (optional): the pieces of a distributed run (vtkBeltramiPieces:
  /// a surface's from Execute's Needs::Distributed, or tetrahedra); with
  /// Split(), every rank calls this (an empty piece too), the errors are
  /// agreed, the values and mask get one entry per point of the piece with
  /// its rings (the ghosts' from their owners) before `flow`, and the
  /// report gets FlowDistribution (this rank's owned points, ghost points,
  /// cells, values sent per exchange).
  static int RunOnMesh(vtkAlgorithm* owner, vtkDataSet* input, vtkDataSet* output, vtkDataArray* array,
    const double* points, bool useMask, const beltrami::GraphFlowOptions& options, int maxComponents,
    bool logEuclidean, const MeshFlow& flow, const vtkBeltramiPieces* split = nullptr);
  /// RunOnMesh's input checks: the mask (input array 1, when useMask) and the
  /// array's values (1 to maxComponents, 6 for log-Euclidean); false after
  /// an error on `owner`.
  static bool ReadMeshInput(vtkAlgorithm* owner, vtkDataSet* input, vtkDataArray* array, bool useMask,
    int maxComponents, bool logEuclidean, std::vector<double>& values, std::vector<std::uint8_t>& fixed);

  /// Log-Euclidean smoothing of `count` 6-component symmetric tensors:
  /// `values` to log coordinates (a warning to `owner`, naming the array as
  /// `name`, for tensors not positive definite: their eigenvalues raised to
  /// 1e-6 of the field's largest), and `options` measuring the noise and the
  /// error on the tensors.  LogToSymmetricTensors maps the result back.
  /// split (optional, collective): `values` are the rows of a split piece
  /// with its rings (the floor and the warning's count over all ranks).
  static void ToLogEuclidean(vtkAlgorithm* owner, const char* name, double* values, vtkIdType count,
    int numThreads, beltrami::GraphFlowOptions& options, const beltrami::Partition* split = nullptr);

  /// A vtkImageData as the core sees it: a 2D image (in any of the XY, XZ
  /// and YZ planes: the VTK axes of its grid's x and y) or a 3D image.
  struct ImageGrid
  {
    bool Volume = false;
    int Axis0 = 0, Axis1 = 1;   ///< 2D: VTK axes of the pixel grid's x and y
    beltrami::PixelGrid Pixels; ///< 2D
    beltrami::VoxelGrid Voxels; ///< 3D
  };
  /// The grid of `image` over its extent `ext` (absolute spacing); whether
  /// it is 2D or 3D comes from the whole extent `whole`.
  static ImageGrid GridOf(vtkImageData* image, const int* whole, const int* ext);
  /// Index in an image of extent `e` of the point with structured index ijk.
  static vtkIdType ExtentIndex(const int* e, const int* ijk);
  /// RequestUpdateExtent of the image filters (which set
  /// CAN_PRODUCE_SUB_EXTENT): the update extent of a piece request is split
  /// as the executive will split it, and the input is asked for it grown by
  /// `rings` samples within the whole extent (a local filter), or for the
  /// whole extent (rings < 0: a filter that needs all of it).
  static void RequestImageExtent(vtkInformation* inInfo, vtkInformation* outInfo, int rings);

  /// The tetrahedra of `input` (4 point ids each): its tetrahedra, and its
  /// voxels (VTK_VOXEL, e.g. the active voxels of a sparse OpenVDB grid)
  /// split into their six Kuhn tetrahedra (as the 3D image path:
  /// conforming, since all voxels share the axes).  Other cells are ignored
  /// with a warning to `owner`.  voxels (optional): the voxels' 8 point ids
  /// each, appended.
  static std::vector<beltrami::Index> Tetrahedra(
    vtkAlgorithm* owner, vtkUnstructuredGrid* input, std::vector<beltrami::Index>* voxels = nullptr);

  /// A tetrahedral piece of a run split over the ranks, grown by the other
  /// pieces' tetrahedra around its points (collective: every rank calls
  /// it, an empty piece's too): its tetrahedra (a copy within the piece kept
  /// once, copies other pieces hold too joined once), those of the rings
  /// around the points `stars` names (vtkBeltramiPieces::AddRings), the
  /// points (the piece's, then the ghost points) and `pieces`' partition.
  /// False (an error on `owner`, on every rank) where it cannot be split.
  struct SplitMesh
  {
    std::vector<double> Points;                     ///< 3 per point
    std::unique_ptr<beltrami::TetrahedralMesh> Mesh; ///< the piece with its rings
    double OwnTetrahedra = 0.0;                     ///< the piece's own (not the rings')
  };
  static bool SplitTetrahedra(vtkAlgorithm* owner, vtkUnstructuredGrid* input, vtkBeltramiPieces& pieces,
    bool allStars, int numberOfThreads, SplitMesh& split);
  /// The warning about tetrahedra with repeated or invalid point ids.
  static void WarnDropped(vtkAlgorithm* owner, const beltrami::TetrahedralMesh& mesh);
  /// The points of `input` as 3 doubles each.
  static std::vector<double> PointsOf(vtkDataSet* input);
};

#endif
// VTK-HeaderTest-Exclude: vtkBeltramiGraphFlow.h
