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
 * gamma, Integration, TimeStep, AdaptiveTimeStep, StoppingRule,
 * NumberOfIterations, MaximumNumberOfIterations, NoiseLevel,
 * NumberOfThreads), with the same automatic defaults (noise level estimated
 * from the data: the residual of each value about its neighbours' mean,
 * over the half of the points with the smallest gradient of the
 * neighbours' values; contrast scale 1.5 h / sigma; least-estimated-error
 * stop), except that the integration is SEMI_IMPLICIT with steps of 0.1 h^2
 * by default: on irregular meshes a few small triangles make the explicit
 * stability limit tiny (with the least-error stop the main run solves to
 * 1e-8, so that split runs stop at the same step, and the probe run solves
 * its difference to the main run to the solver tolerance).  Units: with
 * MEAN_EDGE_LENGTH (default) the mesh is measured in units of its mean
 * edge length h, so TimeStep is in h^2 and alpha maps data units to h (as
 * pixels do for images); with PHYSICAL both are in the mesh's own units.
 *
 * Input array 0: the point array to smooth (default: the active scalars; any
 * numeric type, written back in its own type under the same name, integers rounded and clamped).  Input array 1
 * (optional, with UseFixedPointsArray): non-zero = point kept.  Non-manifold and isolated points, and
 * points without area, keep their values.  Polygons and strips are
 * triangulated internally; the output is the input with the new array.
 * Field data as vtkImageBeltramiDenoising.
 * Distributed runs (pvbatch, pvserver): data split over several ranks are
 * smoothed where they are: the ranks exchange the triangles around their
 * common points and agree on each point's owner; the mean edge length, the
 * noise estimate (an exact median over the ranks), the stops' sums and the
 * semi-implicit solves (conjugate gradient over the ranks) run over all of
 * them: the serial numbers to the solver's tolerance, the same steps, no
 * rank holding more than its piece and a ring (an empty piece is fine).
 * Pieces that come with ghost cells are gathered on rank 0 and smoothed
 * there.  The risk estimate's probe signs follow the points' positions (in
 * mean edge lengths), so every layout and scale draws the same.
 */
#ifndef vtkSurfaceDataDenoising_h
#define vtkSurfaceDataDenoising_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkBeltramiGraphFlowSettings.h" // the shared settings
#include "vtkPolyDataAlgorithm.h"

class BELTRAMIFILTERS_EXPORT vtkSurfaceDataDenoising : public vtkPolyDataAlgorithm
{
public:
  static vtkSurfaceDataDenoising* New();
  vtkTypeMacro(vtkSurfaceDataDenoising, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkBeltramiGraphFlowSettingsMacro();
  vtkBeltramiMeshUnitsMacro();

protected:
  vtkSurfaceDataDenoising();
  ~vtkSurfaceDataDenoising() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkBeltramiGraphFlowMembersMacro();

private:
  vtkSurfaceDataDenoising(const vtkSurfaceDataDenoising&) = delete;
  void operator=(const vtkSurfaceDataDenoising&) = delete;
};

#endif
