/**
 * @class   vtkDiscreteCurvatures
 * @brief   Discrete differential-geometry operators of a triangle mesh
 *          (Meyer, Desbrun, Schroeder & Barr; thesis chapter 2).
 *
 * For every point of a surface mesh it adds point arrays:
 *  - MeanCurvatureNormal (3): K(x_i) of eq. 2.8, cotangent formula over A_Mixed.
 *  - MixedArea: A_Mixed of figure 2.3 (sums to the surface area).
 *  - MeanCurvature: signed kappa_H, positive on a sphere oriented outward.
 *  - GaussianCurvature: kappa_G of eq. 2.9 (angles from atan2).
 *  - MaximumCurvature, MinimumCurvature: kappa_1 >= kappa_2 (eq. 2.10-2.11,
 *    Delta clamped at 0).
 *  - PrincipalDirection1, PrincipalDirection2: unit e1 (along kappa_1) and
 *    e2 = n x e1 from the least-squares curvature tensor (section 2.6.2).
 *  - Normals: unit normals, K/|K| oriented like the triangles, with the
 *    area-weighted face-normal fallback where K vanishes (section 2.4.5) or
 *    is more than 60 degrees away from the face normals (a few vertices of
 *    noisy scans); or another weighting (NormalWeighting).  Set as the
 *    active normals.
 *  - VertexStatus (unsigned char bit field): 0 regular interior vertex;
 *    1 boundary; 2 non-manifold (edge in 3+ triangles, or a pinched fan);
 *    4 inconsistent triangle orientation; 8 in a duplicate triangle;
 *    16 used by no triangle; 32 invalid geometry (a zero-area triangle,
 *    whose cotangents and area were left out and whose angles count, pi
 *    shared where two of its corners coincide, so that Gauss-Bonnet holds;
 *    or NaN/inf coordinates in the 1-ring).
 *
 * Boundary and non-manifold points: the thesis' operators need a closed
 * 1-ring, so curvatures there are undefined.  By default they are NaN
 * (ParaView shows the NaN colour and range computations skip them); with
 * BoundaryHandling = INTERIOR_AVERAGE they get the mean of the adjacent
 * points that have a value, filled ring by ring from the interior
 * (principal directions stay NaN).  Normals and MixedArea
 * are always defined there.
 *
 * Polygons and triangle strips are triangulated internally; the output keeps
 * the input's cells and arrays.  Float and double points are read in place;
 * all computation is in double.  The work runs on NumberOfThreads threads
 * (0: all cores, shared among the processes of an MPI job on the node, or
 * BELTRAMI_NUM_THREADS), reports progress and honours
 * AbortExecute.  In a distributed pipeline (pvbatch, pvserver: one piece
 * per rank) every point of a piece gets its full 1-ring: pieces that come
 * with ghost cells use them; otherwise the ranks exchange the triangles
 * around their common points (every piece sends those at its edge points,
 * each keeps those touching its own), also where three or more pieces meet.
 * No ghost level is requested upstream there (it would re-execute the
 * upstream pipeline, and most sources and readers cannot make ghost cells);
 * pieces streamed one by one in one process ask for one ghost level.  The
 * values equal those of a serial run.
 */
#ifndef vtkDiscreteCurvatures_h
#define vtkDiscreteCurvatures_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkPolyDataAlgorithm.h"

class vtkBeltramiSurface;
enum class vtkBeltramiCopy;
namespace beltrami
{
struct CurvatureOptions;
}

class BELTRAMIFILTERS_EXPORT vtkDiscreteCurvatures : public vtkPolyDataAlgorithm
{
public:
  static vtkDiscreteCurvatures* New();
  vtkTypeMacro(vtkDiscreteCurvatures, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum MethodType
  {
    MEYER_2003 = 0, ///< the thesis' operators (default)
    TAUBIN_1995 = 1 ///< Taubin's curvature tensor, for comparison
  };
  enum NormalWeightingType
  {
    MEAN_CURVATURE_NORMAL = 0, ///< K/|K| (default)
    UNIFORM = 1,
    ANGLE = 2,
    MAX_1999 = 3,
    AREA = 4
  };
  enum BoundaryHandlingType
  {
    BOUNDARY_NAN = 0,
    INTERIOR_AVERAGE = 1
  };

  ///@{
  /// Curvature estimator. Meyer 2003 uses the cotangent mean-curvature normal, the angle-defect
  /// Gaussian curvature and the least-squares principal directions of the thesis. Taubin 1995
  /// (section 2.2.4) is offered to compare both in one pipeline. Values: 0 Meyer 2003 (thesis
  /// operators), 1 Taubin 1995 (curvature tensor). Default: Meyer 2003 (thesis operators).
  vtkSetClampMacro(Method, int, MEYER_2003, TAUBIN_1995);
  vtkGetMacro(Method, int);
  void SetMethodToMeyer2003() { this->SetMethod(MEYER_2003); }
  void SetMethodToTaubin1995() { this->SetMethod(TAUBIN_1995); }
  ///@}

  ///@{
  /// How vertex normals are computed (section 2.2.1). The default is the direction of the mean
  /// curvature normal, oriented like the triangles, with the area-weighted face normals where it
  /// vanishes (flat or saddle points, section 2.4.5) or lies more than 60 degrees from them (a few
  /// vertices of noisy scans). The normal also defines the tangent plane of the principal
  /// directions. Values: 0 Mean curvature normal, 1 Uniform (Gouraud), 2 Angle
  /// (Thuermer-Wuethrich), 3 Sphere (Max 1999), 4 Area. Default: Mean curvature normal.
  vtkSetClampMacro(NormalWeighting, int, MEAN_CURVATURE_NORMAL, AREA);
  vtkGetMacro(NormalWeighting, int);
  ///@}

  ///@{
  /// Curvature is undefined at boundary and non-manifold points (their 1-ring is not a closed
  /// disk). NaN marks them as such; Interior average gives them the mean value of their neighbours
  /// that have one, filled ring by ring from the interior (principal directions stay NaN).
  /// MixedArea and Normals are always computed. Values: 0 NaN (undefined), 1 Interior average.
  /// Default: NaN (undefined).
  vtkSetClampMacro(BoundaryHandling, int, BOUNDARY_NAN, INTERIOR_AVERAGE);
  vtkGetMacro(BoundaryHandling, int);
  ///@}

  ///@{
  /// Output MeanCurvatureNormal (3 components, K = 2 kappa_H n). Default: on.
  vtkSetMacro(ComputeMeanCurvatureNormal, bool);
  vtkGetMacro(ComputeMeanCurvatureNormal, bool);
  vtkBooleanMacro(ComputeMeanCurvatureNormal, bool);
  /// Output MixedArea (the Voronoi/mixed area of each point). Default: on.
  vtkSetMacro(ComputeMixedArea, bool);
  vtkGetMacro(ComputeMixedArea, bool);
  vtkBooleanMacro(ComputeMixedArea, bool);
  /// Output MeanCurvature (signed). Default: on.
  vtkSetMacro(ComputeMeanCurvature, bool);
  vtkGetMacro(ComputeMeanCurvature, bool);
  vtkBooleanMacro(ComputeMeanCurvature, bool);
  /// Output GaussianCurvature. Default: on.
  vtkSetMacro(ComputeGaussianCurvature, bool);
  vtkGetMacro(ComputeGaussianCurvature, bool);
  vtkBooleanMacro(ComputeGaussianCurvature, bool);
  /// Output MaximumCurvature and MinimumCurvature. Default: on.
  vtkSetMacro(ComputePrincipalCurvatures, bool);
  vtkGetMacro(ComputePrincipalCurvatures, bool);
  vtkBooleanMacro(ComputePrincipalCurvatures, bool);
  /// Output PrincipalDirection1 and PrincipalDirection2 (unit, tangent, orthogonal). Default: on.
  vtkSetMacro(ComputePrincipalDirections, bool);
  vtkGetMacro(ComputePrincipalDirections, bool);
  vtkBooleanMacro(ComputePrincipalDirections, bool);
  /// Output Normals (set as the active normals). Default: on.
  vtkSetMacro(ComputeNormals, bool);
  vtkGetMacro(ComputeNormals, bool);
  vtkBooleanMacro(ComputeNormals, bool);
  /// Output VertexStatus, the bit field that says why a point has no curvature. Default: on.
  vtkSetMacro(ComputeVertexStatus, bool);
  vtkGetMacro(ComputeVertexStatus, bool);
  vtkBooleanMacro(ComputeVertexStatus, bool);
  ///@}

  ///@{
  /// Threads used per process; 0 uses all cores, shared among the processes of an MPI job on the
  /// node (or BELTRAMI_NUM_THREADS). Default: 0.
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

protected:
  vtkDiscreteCurvatures();
  ~vtkDiscreteCurvatures() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // Defaults: the core's CurvatureOptions{} (set in the constructor).
  int Method;
  int NormalWeighting;
  int BoundaryHandling;
  bool ComputeMeanCurvatureNormal = true;
  bool ComputeMixedArea = true;
  bool ComputeMeanCurvature = true;
  bool ComputeGaussianCurvature = true;
  bool ComputePrincipalCurvatures = true;
  bool ComputePrincipalDirections = true;
  bool ComputeNormals = true;
  bool ComputeVertexStatus = true;
  int NumberOfThreads;

private:
  /// Copies the settings to or from the core's options (one list of pairs).
  void CopySettings(beltrami::CurvatureOptions& options, vtkBeltramiCopy direction);
  /// RequestData's work on the prepared surface (vtkBeltramiSurface::Execute).
  int Compute(vtkBeltramiSurface& surface);
  vtkDiscreteCurvatures(const vtkDiscreteCurvatures&) = delete;
  void operator=(const vtkDiscreteCurvatures&) = delete;
};

#endif
