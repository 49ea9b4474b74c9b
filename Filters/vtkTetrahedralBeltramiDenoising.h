/**
 * @class   vtkTetrahedralBeltramiDenoising
 * @brief   Edge-preserving smoothing of point data on a tetrahedral mesh: the
 *          graph flows of thesis section 3.8 on 3-manifolds (section 2.8.2).
 *
 * A scalar, vector or tensor point array f (1 to 6 components) on the
 * tetrahedra of an unstructured grid is the 3-manifold (x, y, z, alpha f) in
 * R^(3+n); the flow changes the data only, d(alpha f)/dt =
 * E^(gamma - 1) Delta_g(alpha f), with Delta_g the Beltrami operator of that
 * manifold - the gradient of the 1-ring volume over the vertex volume, with
 * cotangents of dihedral angles computed from dot products in R^(3+n)
 * (appendix A.4) - and E = V_mesh / V_graph the edge indicator (1/W).  The
 * mesh does not move.  The lumped vertex volume is a quarter of the volume of
 * its tetrahedra (a choice: the thesis gives no mixed volume).
 *
 * Settings as vtkSurfaceDataDenoising (ContrastScale alpha, EdgeContrast
 * gamma, Integration (SEMI_IMPLICIT by default), TimeStep, AdaptiveTimeStep,
 * StoppingRule, NumberOfIterations, MaximumNumberOfIterations, NoiseLevel,
 * Units, NumberOfThreads; the same automatic defaults).  With
 * MEAN_EDGE_LENGTH units (default) the mesh is measured in its mean edge
 * length h: TimeStep in h^2, the automatic alpha 1.5 h / sigma.  The
 * boundary is free (natural boundary condition): constants are fixed points;
 * linear fields are fixed points where the boundary values are held (mask).
 *
 * Input array 0: the point array to smooth (default: the active scalars;
 * written back in its own type under the same name, integers rounded and
 * clamped).  Input array 1 (optional,
 * with UseFixedPointsArray): non-zero = point kept.  VTK_TETRA cells are
 * used, and VTK_VOXEL cells split into their six Kuhn tetrahedra (the split
 * of the 3D image path; e.g. the active voxels of a sparse OpenVDB grid from
 * vtkOpenVDBActiveVoxelReader; an input of voxels alone on one lattice runs
 * on the dense 3D kernel's arithmetic, several times faster, to single-
 * precision round-off); other cells are reported and ignored
 * (tetrahedralize first, e.g. with vtkDataSetTriangleFilter).  Points in no
 * tetrahedron with volume keep their values.  Field data: FlowIterations, FlowTime, FlowRMSChange,
 * FlowArea (the volume of the graph manifold, initial and final),
 * FlowSolverIterations.
 * Distributed runs (pvbatch, pvserver): the flow couples all points.  Data
 * split over several ranks are smoothed where they are: each rank grows its
 * piece by the other pieces' tetrahedra around the points it owns
 * (vtkBeltramiPieces), and the noise estimate, the mean edge length, the
 * stops' sums and the semi-implicit solves run over all ranks - the numbers
 * of a serial run to the solver's tolerance, no rank holding more than its
 * piece and a ring (field data FlowDistribution: owned points, ghost
 * points, tetrahedra, values sent per exchange; log-Euclidean tensors
 * too).  Pieces that come with ghost cells are gathered on rank 0
 * (vtkBeltramiGather), smoothed there as one mesh, and every rank gets the
 * values of its own points.
 */
#ifndef vtkTetrahedralBeltramiDenoising_h
#define vtkTetrahedralBeltramiDenoising_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkBeltramiGraphFlowSettings.h" // the shared settings
#include "vtkUnstructuredGridAlgorithm.h"

#include <cstdint> // for Run
#include <vector>  // for Run

class vtkBeltramiPieces;
namespace beltrami
{
class TetrahedralMesh;
}

class BELTRAMIFILTERS_EXPORT vtkTetrahedralBeltramiDenoising : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkTetrahedralBeltramiDenoising* New();
  vtkTypeMacro(vtkTetrahedralBeltramiDenoising, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkBeltramiGraphFlowSettingsMacro();
  vtkBeltramiMeshUnitsMacro();

  /// 6-component symmetric tensors (XX, YY, ZZ, XY, YZ, XZ; e.g. diffusion tensors) smoothed as
  /// their matrix logarithms (log-Euclidean): the result stays positive definite and does not swell
  /// (equal determinants are kept exactly); eigenvalues below 1e-6 of the largest are raised to it
  /// with a warning. Off: the components as they are. Default: off.
  vtkSetMacro(LogEuclideanTensors, bool);
  vtkGetMacro(LogEuclideanTensors, bool);
  vtkBooleanMacro(LogEuclideanTensors, bool);

protected:
  vtkTetrahedralBeltramiDenoising();
  ~vtkTetrahedralBeltramiDenoising() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkBeltramiGraphFlowMembersMacro();
  bool LogEuclideanTensors = false;

private:
  vtkTetrahedralBeltramiDenoising(const vtkTetrahedralBeltramiDenoising&) = delete;
  void operator=(const vtkTetrahedralBeltramiDenoising&) = delete;

  /// Smooths `input` into `output` (RequestData's value); `holding`: how
  /// many pieces hold points (more than 1: a streamed piece, smoothed on its
  /// own).
  int Smooth(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output, int holding);
  /// Smooths this rank's piece of data split over the ranks, solving with
  /// the others (collective: every rank calls it, an empty piece's too).
  int SmoothSplit(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output);
  /// Their common end: the array checked and the flow run on `mesh` (the
  /// input's points, then a split piece's ghost points, at `points`);
  /// voxels: the voxel cells (beltrami::Index ids) of an input of voxels
  /// alone; pieces: the split.
  int Run(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output, const double* points,
    const beltrami::TetrahedralMesh& mesh, const std::vector<std::int32_t>* voxels,
    const vtkBeltramiPieces* pieces);
  /// An error (false) when `numPoints` do not fit the core's indices.
  bool FitsIndex(vtkIdType numPoints);
};

#endif
