/**
 * @class   vtkSurfaceDataDenoising
 * @brief   Edge-preserving smoothing of point data on a triangle mesh: the
 *          graph flows of thesis section 3.8 over a surface.
 *
 * A scalar or vector point array f (1 to 5 components) on a triangle mesh is
 * the 2-manifold (x, y, z, alpha f) in R^(3+n); the flow changes the data
 * only, d(alpha f)/dt = E^(gamma - 1) Delta_g(alpha f), with Delta_g the
 * Laplace-Beltrami operator of that manifold (cotangent formula in R^(3+n),
 * section 2.8.1) and E = A_mesh / A_graph the edge indicator (1/W of eq.
 * 3.17, from the mixed areas).  gamma = 1 (default) is the Beltrami flow;
 * jumps in the data are steep cliffs of the graph surface, across which the
 * flow hardly diffuses, so discontinuities are kept while noise is removed.
 * The mesh itself does not move.
 *
 * Settings as vtkImageBeltramiDenoising (ContrastScale alpha, EdgeContrast
 * gamma, Integration, TimeStep, AdaptiveTimeStep, NumberOfIterations,
 * NoiseLevel, NumberOfThreads), except that the integration is
 * SEMI_IMPLICIT by default: on irregular meshes a few small triangles make
 * the explicit stability limit tiny.  Units: with MEAN_EDGE_LENGTH (default) the
 * mesh is measured in units of its mean edge length h, so TimeStep is in h^2
 * and alpha maps data units to h (as pixels do for images: alpha = 1.5/sigma
 * for noise sigma); with PHYSICAL both are in the mesh's own units.
 *
 * Input array 0: the point array to smooth (default: the active scalars; any
 * numeric type, written back as double under the same name).  Input array 1
 * (optional, with UseFixedPointsArray): non-zero = point kept.  Non-manifold and isolated points, and
 * points without area, keep their values.  Polygons and strips are
 * triangulated internally; the output is the input with the new array.
 * Field data as vtkImageBeltramiDenoising.
 * Distributed runs (pvbatch, pvserver): the flow couples all points, so
 * data split over several ranks are gathered on rank 0 (vtkBeltramiGather),
 * smoothed there as one surface, and every rank gets the values of its own
 * points: the numbers of a serial run, with the memory and time of one
 * process.
 */
#ifndef vtkSurfaceDataDenoising_h
#define vtkSurfaceDataDenoising_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkPolyDataAlgorithm.h"

class BELTRAMIFILTERS_EXPORT vtkSurfaceDataDenoising : public vtkPolyDataAlgorithm
{
public:
  static vtkSurfaceDataDenoising* New();
  vtkTypeMacro(vtkSurfaceDataDenoising, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum IntegrationType
  {
    EXPLICIT = 0,
    SEMI_IMPLICIT = 1
  };
  enum UnitsType
  {
    MEAN_EDGE_LENGTH = 0,
    PHYSICAL = 1
  };

  vtkSetClampMacro(ContrastScale, double, 1e-12, VTK_DOUBLE_MAX);
  vtkGetMacro(ContrastScale, double);
  vtkSetClampMacro(EdgeContrast, double, -1.0, 10.0);
  vtkGetMacro(EdgeContrast, double);
  vtkSetClampMacro(Integration, int, EXPLICIT, SEMI_IMPLICIT);
  vtkGetMacro(Integration, int);
  vtkSetClampMacro(TimeStep, double, 1e-12, VTK_DOUBLE_MAX);
  vtkGetMacro(TimeStep, double);
  vtkSetMacro(AdaptiveTimeStep, bool);
  vtkGetMacro(AdaptiveTimeStep, bool);
  vtkBooleanMacro(AdaptiveTimeStep, bool);
  vtkSetClampMacro(NumberOfIterations, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfIterations, int);
  vtkSetClampMacro(NoiseLevel, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(NoiseLevel, double);
  vtkSetClampMacro(Units, int, MEAN_EDGE_LENGTH, PHYSICAL);
  vtkGetMacro(Units, int);
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);
  /// Whether the mask selected as input array 1 is used (default on; nothing
  /// selected = no mask).  ParaView's panel starts with it off, because it
  /// preselects an array of the input for every array selection.
  vtkSetMacro(UseFixedPointsArray, bool);
  vtkGetMacro(UseFixedPointsArray, bool);
  vtkBooleanMacro(UseFixedPointsArray, bool);

protected:
  vtkSurfaceDataDenoising();
  ~vtkSurfaceDataDenoising() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double ContrastScale = 1.0;
  double EdgeContrast = 1.0;
  int Integration = SEMI_IMPLICIT;
  double TimeStep = 0.1;
  bool AdaptiveTimeStep = false;
  int NumberOfIterations = 10;
  double NoiseLevel = 0.0;
  int Units = MEAN_EDGE_LENGTH;
  int NumberOfThreads = 0;
  bool UseFixedPointsArray = true;

private:
  vtkSurfaceDataDenoising(const vtkSurfaceDataDenoising&) = delete;
  void operator=(const vtkSurfaceDataDenoising&) = delete;
};

#endif
