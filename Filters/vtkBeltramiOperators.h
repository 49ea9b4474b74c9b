/**
 * @class   vtkBeltramiOperators
 * @brief   The operators of thesis section 2.8 on data seen as a graph, as
 *          point arrays: mean curvature normal, Laplace-Beltrami operator,
 *          mean and Gaussian curvature and edge indicator, for edge and
 *          feature maps.
 *
 * A point array f (1 to 6 components; 5 on surfaces) makes its domain a
 * graph: a 2D image or point data on a triangle mesh the 2-manifold
 * (x, y[, z], alpha f), a 3D image or point data on tetrahedra (or voxels)
 * the 3-manifold (x, y, z, alpha f) (section 2.8.2).  These are the
 * operators the Beltrami denoising filters move the data by; here they are
 * output:
 *  - MeanCurvatureNormal (3 + n components: x, y, z, then the data axes):
 *    K = -Delta_g of the embedding (eq. 2.8 with cotangents from dot
 *    products, section 2.8.1; on 3-manifolds the volume gradient of
 *    appendix A.4), |K| = d H with d the manifold's dimension.
 *  - BeltramiOperator (n components): Delta_g f = -K_data / alpha, in data
 *    units per length^2 (for greyscale (1/W) div(grad(alpha f) / W) / alpha,
 *    W = sqrt(1 + alpha^2 |grad f|^2)); zero on linear data, changes sign
 *    across edges.
 *  - MeanCurvature: |K| / d (unsigned: a graph in R^N has no side).
 *  - GaussianCurvature (2-manifolds): angle defect over mixed area (eq. 2.9,
 *    intrinsic, so valid in R^N): large at corners and junctions.
 *  - EdgeIndicator: 1/W, the ratio of the base's to the graph's measure
 *    (eq. 3.17): 1 where the data are flat, small on edges.
 *
 * ContrastScale alpha maps data units to lengths; 0 (default) chooses it as
 * the denoising filters do at their defaults: 1.5 h / sigma (1.0 on 3D
 * images), h the spacing's geometric mean or the mesh's mean edge length,
 * sigma the NoiseLevel (0, default: estimated from the data,
 * Flows/NoiseEstimation; alpha = 1 where no noise is found, e.g. synthetic
 * data: set ContrastScale there).  Images: the grid is triangulated along
 * both diagonals (3D: Kuhn tetrahedra, as the denoising flows) and continued
 * one sample beyond its border by BoundaryHandling (LINEAR, default: linear
 * extrapolation, so ramps give zero at the border too; REFLECT: mirror), so
 * every pixel is defined.  Meshes: at boundary and non-manifold points (a
 * face of one tetrahedron on volume meshes) and points without area the
 * operators are not defined: NaN.  Each output is switchable
 * (Compute... settings).
 *
 * Field data: GraphContrastScale (alpha used), GraphNoiseLevel (sigma behind
 * an automatic alpha), EstimatedNoiseLevel (0 when not estimated),
 * GraphUndefinedPoints.
 *
 * Distributed runs (pvbatch, pvserver): images with a given ContrastScale
 * are computed per piece with one ring of neighbours (the serial numbers);
 * with the automatic ContrastScale every rank reads the whole image (the
 * noise estimate is a median over all of it) and keeps its piece.  Surfaces
 * and tetrahedral meshes split over ranks stay distributed: the ranks
 * exchange the triangles (tetrahedra) at the edges of their pieces
 * (1-rings), and the automatic contrast's mean edge length and noise
 * estimate (an exact median over the ranks) are taken over all ranks: the
 * serial numbers, no rank holding more than its piece and one ring.  Pieces
 * that come with ghost cells are gathered on rank 0 (vtkBeltramiGather),
 * and every rank gets the values of its own points.
 */
#ifndef vtkBeltramiOperators_h
#define vtkBeltramiOperators_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkDataSetAlgorithm.h"

class vtkBeltramiSurface;
class vtkDataArray;
class vtkImageData;
class vtkUnstructuredGrid;
enum class vtkBeltramiCopy;
namespace beltrami
{
struct GraphOperatorOptions;
}

class BELTRAMIFILTERS_EXPORT vtkBeltramiOperators : public vtkDataSetAlgorithm
{
public:
  static vtkBeltramiOperators* New();
  vtkTypeMacro(vtkBeltramiOperators, vtkDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Input array 0: the data seen as a graph (default: the active scalars).
  enum InputArrays
  {
    DATA_ARRAY = 0
  };

  enum BoundaryHandlings
  {
    REFLECT = 0,
    LINEAR = 1
  };

  ///@{
  /// alpha: maps data units to lengths. 0 (default): automatic, as the denoising filters at their
  /// defaults: 1.5 h / sigma (1.0 on 3D images), h the spacing's geometric mean or the mesh's mean
  /// edge length, sigma the noise level; 1 where no noise is found (synthetic data: set it). For
  /// height fields in physical units use 1. Default: 0.
  vtkSetClampMacro(ContrastScale, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(ContrastScale, double);
  ///@}

  ///@{
  /// sigma of the automatic contrast scale, in data units. 0 (default): estimated from the data
  /// (EstimatedNoiseLevel in the field data). Default: 0.
  vtkSetClampMacro(NoiseLevel, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(NoiseLevel, double);
  ///@}

  ///@{
  /// Images: values assumed one sample beyond the border: mirrored, or linearly extrapolated (ramps
  /// give zero at the border too). Values: 0 Reflect, 1 Linear. Default: Linear.
  vtkSetClampMacro(BoundaryHandling, int, REFLECT, LINEAR);
  vtkGetMacro(BoundaryHandling, int);
  ///@}

  ///@{
  /// Output MeanCurvatureNormal (3 + n components). Default: on.
  vtkSetMacro(ComputeMeanCurvatureNormal, bool);
  vtkGetMacro(ComputeMeanCurvatureNormal, bool);
  vtkBooleanMacro(ComputeMeanCurvatureNormal, bool);
  /// Output BeltramiOperator (n components). Default: on.
  vtkSetMacro(ComputeBeltramiOperator, bool);
  vtkGetMacro(ComputeBeltramiOperator, bool);
  vtkBooleanMacro(ComputeBeltramiOperator, bool);
  /// Output MeanCurvature. Default: on.
  vtkSetMacro(ComputeMeanCurvature, bool);
  vtkGetMacro(ComputeMeanCurvature, bool);
  vtkBooleanMacro(ComputeMeanCurvature, bool);
  /// Output GaussianCurvature (2D images and surfaces only). Default: on.
  vtkSetMacro(ComputeGaussianCurvature, bool);
  vtkGetMacro(ComputeGaussianCurvature, bool);
  vtkBooleanMacro(ComputeGaussianCurvature, bool);
  /// Output EdgeIndicator. Default: on.
  vtkSetMacro(ComputeEdgeIndicator, bool);
  vtkGetMacro(ComputeEdgeIndicator, bool);
  vtkBooleanMacro(ComputeEdgeIndicator, bool);
  ///@}

  ///@{
  /// Threads (0: all); the result does not depend on it. Default: 0.
  vtkSetClampMacro(NumberOfThreads, int, 0, 1024);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

protected:
  vtkBeltramiOperators();
  ~vtkBeltramiOperators() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double ContrastScale = 0.0;
  double NoiseLevel = 0.0;
  int BoundaryHandling = LINEAR;
  bool ComputeMeanCurvatureNormal = true;
  bool ComputeBeltramiOperator = true;
  bool ComputeMeanCurvature = true;
  bool ComputeGaussianCurvature = true;
  bool ComputeEdgeIndicator = true;
  int NumberOfThreads = 0;

private:
  vtkBeltramiOperators(const vtkBeltramiOperators&) = delete;
  void operator=(const vtkBeltramiOperators&) = delete;

  /// The settings to or from the core's options (their one source of defaults).
  void CopySettings(beltrami::GraphOperatorOptions& options, vtkBeltramiCopy direction);
  int RunImage(vtkImageData* input, vtkImageData* output, const int* whole, const int* outExt);
  int RunMesh(vtkDataSet* input, vtkDataSet* output, vtkUnstructuredGrid* volume, int holding);
  /// Tetrahedra split over the ranks, each rank on its piece and the
  /// tetrahedra around its points (collective).
  int RunMeshSplit(vtkUnstructuredGrid* input, vtkUnstructuredGrid* output);
  /// A surface, serial or split over the ranks (each rank its piece; collective).
  bool RunSurface(vtkBeltramiSurface& surface);
};

#endif
