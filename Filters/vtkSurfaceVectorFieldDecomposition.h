/**
 * @class   vtkSurfaceVectorFieldDecomposition
 * @brief   Helmholtz-Hodge decomposition of a vector field on a triangle
 *          surface: curl-free, divergence-free and harmonic parts, potentials,
 *          divergence and curl (Polthier & Preuss 2003; thesis section 6.3).
 *
 * The selected 3-component point or cell array is a field on the surface;
 * its component along the surface normal is removed (NormalComponent) and
 * the tangent rest (TangentField) is split into three parts that sum to it
 * and are orthogonal in L2:
 *  - CurlFreePart = grad Potential (Potential continuous, linear per triangle),
 *  - DivergenceFreePart = J grad StreamFunction (J: the rotation by +90
 *    degrees about the normal; the stream function is linear per triangle
 *    and continuous at the edge midpoints),
 *  - HarmonicPart: the rest, divergence- and curl-free: a field of the
 *    2g-dimensional space of harmonic fields of a closed surface of genus g
 *    (2g + b - 1 dimensions with b boundary loops).
 * The decomposition is exact on the field taken per triangle: cell data as
 * given, point data as the mean of each triangle's corners.  The parts come
 * back with the input's association: per cell (an input polygon's triangles
 * averaged by area), or per point as the area-weighted mean of the point's
 * triangles (then TangentField is that mean of the tangent input, and the
 * parts still sum to it).  Point arrays in every case: Potential,
 * StreamFunction (the mean of its edge values), Divergence and Curl (n . curl,
 * the vorticity), per unit area (the mixed area of thesis figure 2.3).
 * Field data: the parts' energies (integrals of |X|^2), their mutual inner
 * products, the triangles left out, and the solver's iterations.
 *
 * When the surface and the settings are those of the previous run (the
 * time steps of a field on a fixed mesh), the factorized systems of that
 * run are reused: such a run costs a fraction of the first.
 *
 * Triangles at non-manifold points, with inconsistent orientation or
 * duplicated are left out (their parts NaN, with a warning), as are
 * zero-area triangles and NaN vectors (parts 0).  Data split over the ranks
 * of a distributed run are decomposed over the ranks, each holding its piece
 * and the rings of triangles around it (the systems solved by multigrids
 * that span the ranks): every rank gets the serial values of its piece, to
 * the solvers' tolerance.  Pieces that come with ghost cells are gathered
 * on rank 0 and decomposed there.
 */
#ifndef vtkSurfaceVectorFieldDecomposition_h
#define vtkSurfaceVectorFieldDecomposition_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // the prepared decomposition
#include <vector> // the triangles' cells

class vtkBeltramiSurface;
enum class vtkBeltramiCopy;
namespace beltrami
{
class MeshTopology;
struct VectorFieldDecomposition;
struct VectorFieldOptions;
}

class BELTRAMIFILTERS_EXPORT vtkSurfaceVectorFieldDecomposition : public vtkPolyDataAlgorithm
{
public:
  static vtkSurfaceVectorFieldDecomposition* New();
  vtkTypeMacro(vtkSurfaceVectorFieldDecomposition, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum BoundaryConditionType
  {
    TANGENT_DIVERGENCE_FREE = 0,
    NORMAL_CURL_FREE = 1
  };

  ///@{
  /// On open surfaces, which part is held at the boundary. Tangent divergence-free fixes the stream
  /// function at 0 on the boundary: the divergence-free part carries no flux through it and the
  /// curl-free part takes the field's flux. Normal curl-free fixes the potential at 0 on the
  /// boundary: the curl-free part is normal to it and the divergence-free part takes the
  /// circulation along it. Either way the three parts stay orthogonal. Values: 0 Tangent
  /// divergence-free, 1 Normal curl-free. Default: Tangent divergence-free.
  vtkSetClampMacro(BoundaryCondition, int, TANGENT_DIVERGENCE_FREE, NORMAL_CURL_FREE);
  vtkGetMacro(BoundaryCondition, int);
  ///@}

  ///@{
  /// Threads used per process; 0 uses all cores, shared among the processes of an MPI job on the
  /// node (or BELTRAMI_NUM_THREADS). Default: 0.
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

protected:
  vtkSurfaceVectorFieldDecomposition();
  ~vtkSurfaceVectorFieldDecomposition() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // Defaults: the core's VectorFieldOptions{} (set in the constructor).
  int BoundaryCondition;
  int NumberOfThreads;

private:
  void CopySettings(beltrami::VectorFieldOptions& options, vtkBeltramiCopy direction);
  /// The decomposition prepared for the last surface seen twice in a row
  /// (its factorized systems: the time steps of a field on a fixed mesh
  /// cost two triangular solves each).
  struct vtkPrepared;
  std::unique_ptr<vtkPrepared> Prepared;
  /// Set by a split run whose pieces do not hold the stars of their points
  /// (beltrami::InconsistentOwnership, on every rank): RequestData then
  /// gathers the surface instead.
  bool PiecesDisagree = false;
  /// RequestData's work on the prepared surface (vtkBeltramiSurface::Execute).
  bool Compute(vtkBeltramiSurface& surface);
  /// The serial decomposition, with the systems of a surface seen twice in
  /// a row kept (Prepared); true when they were reused.
  bool Decompose(const beltrami::MeshTopology& topology, const double* points, const double* vectors,
    const beltrami::VectorFieldOptions& options, beltrami::VectorFieldDecomposition& result);
  /// The output arrays from the decomposition on `topology`, whose triangle
  /// k came from the input cell cellOf[k] (-1: a triangle of another
  /// piece's, in a distributed run).
  void AddArrays(vtkBeltramiSurface& surface, const beltrami::MeshTopology& topology,
    const std::vector<vtkIdType>& cellOf, const beltrami::VectorFieldDecomposition& result, bool onPoints);
  vtkSurfaceVectorFieldDecomposition(const vtkSurfaceVectorFieldDecomposition&) = delete;
  void operator=(const vtkSurfaceVectorFieldDecomposition&) = delete;
};

#endif
