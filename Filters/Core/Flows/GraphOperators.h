// Beltrami core: the operators of section 2.8 on data seen as a graph, as
// outputs: for images and point data on surfaces, the 2-manifold
// S = (base point, alpha f) in R^(2+n) or R^(3+n) (section 2.8.1); for 3D
// images and point data on tetrahedra, the 3-manifold one dimension up
// (section 2.8.2).  The same operators the graph flows move the data by,
// for edge and feature maps:
//
//  - K = the mean curvature normal of the graph (eq. 2.8 with cotangents
//    from dot products in R^N; on 3-manifolds the volume gradient of
//    appendix A.4 over the vertex volume): K = -Delta_g S, |K| = d H with d
//    the manifold's dimension and H the mean of its principal curvatures;
//  - Delta_g f = -K_data / alpha, the Laplace-Beltrami operator of the data
//    (data units per length^2): for greyscale data (1/W) div(grad(alpha f) / W) / alpha
//    with W = sqrt(1 + |grad(alpha f)|^2); 0 on linear data;
//  - the Gaussian curvature of the 2-manifold (eq. 2.9: intrinsic, so it
//    holds in R^N): (K_xx K_yy - K_xy^2) / W^4 for a greyscale image;
//  - the edge indicator 1/W (eq. 3.17): the ratio of the base's and the
//    graph's measures (mixed areas, vertex volumes), 1 where the data are
//    flat and small across edges.
//
// Images are the flows' discretizations made explicit: the pixel grid
// triangulated along both diagonals (the two triangulations' sums added),
// voxels split into Kuhn tetrahedra; the grid is continued by one ring of
// values the flows' boundary rule gives (GridBoundary), so every pixel has
// its whole 1-ring.  Grids are processed in bands of rows (planes): memory
// stays bounded for any image.  Meshes use the shared assemblers
// (ComputeBeltramiOperator, AssembleTetrahedralLaplacian); at their boundary,
// non-manifold points and points without measure the operators are not
// defined (NaN).
#pragma once

#include "Flows/GraphFlow.h"

#include <cstdint>
#include <string>

namespace beltrami
{

struct GraphOperatorOptions
{
  /// alpha: data units -> embedding units.  0: automatic, as the flows at
  /// their defaults (c h / sigma, GraphFlowOptions::ContrastScale), so the
  /// maps show the operator the denoising filters start from.
  double ContrastScale = 0.0;
  /// sigma for the automatic contrast scale; 0: estimated (NoiseEstimation).
  double NoiseLevel = 0.0;
  GridBoundary Boundary = GridBoundary::Linear; ///< images
  int NumberOfThreads = 0;
};

/// Caller-owned outputs per vertex (pixel, voxel, point); null ones are skipped.
struct GraphOperatorOutputs
{
  double* MeanCurvatureNormal = nullptr; ///< base dimension + components values: K (base axes first)
  double* BeltramiOperator = nullptr;    ///< components values: Delta_g f
  double* MeanCurvature = nullptr;       ///< |K| / d (unsigned: R^N has no side)
  double* GaussianCurvature = nullptr;   ///< 2-manifolds only
  double* EdgeIndicator = nullptr;       ///< base measure / graph measure = 1/W
  /// Per vertex, 1 where the operators are not defined (meshes: boundary and
  /// non-manifold vertices, vertices without measure; NaN written), else 0.
  std::uint8_t* Undefined = nullptr;
};

struct GraphOperatorReport
{
  std::string Error;                 ///< non-empty: nothing was written
  double ContrastScale = 0.0;        ///< alpha used
  double NoiseLevel = 0.0;           ///< sigma behind an automatic alpha (given or estimated)
  double EstimatedNoiseLevel = 0.0;  ///< from the data (0 when not needed or too small)
  Index UndefinedVertices = 0;       ///< meshes: NaN written (boundary, non-manifold, no measure)
  /// Points (of the undefined ones, on meshes) where the data's graph has
  /// no finite measure though the domain's has: data so large (beyond about
  /// 1e150) that the graph metric's squares overflow.  NaN written.
  Index OverflowVertices = 0;
};

/// `components` (1 to 6) interleaved values per pixel, row-major.
GraphOperatorReport ComputeImageGraphOperators(const PixelGrid& grid, int components, const double* values,
  const GraphOperatorOptions& options, const GraphOperatorOutputs& outputs);

/// `components` (1 to 6) interleaved values per voxel (x fastest).
GraphOperatorReport ComputeVolumeGraphOperators(const VoxelGrid& grid, int components, const double* values,
  const GraphOperatorOptions& options, const GraphOperatorOutputs& outputs);

/// Point data over a triangle mesh: points 3 doubles per vertex,
/// `components` (1 to 5) values per vertex.  split (optional, collective):
/// a surface split over processes (each holding the 1-rings of its rows,
/// Solvers/Partition; the values of ghost rows are its owners'): the
/// contrast scale, noise level and undefined count over all of them, as in
/// a serial run; every process, an empty one too, must call it.
GraphOperatorReport ComputeSurfaceGraphOperators(const MeshTopology& topology, const double* points,
  int components, const double* values, const GraphOperatorOptions& options, const GraphOperatorOutputs& outputs,
  const Partition* split = nullptr);

class TetrahedralMesh;

/// Point data over a tetrahedral mesh (components 1 to 6); no Gaussian
/// curvature.  split (optional, collective): a mesh split over processes
/// (each holding the 1-rings of its rows' points), as for surfaces.
GraphOperatorReport ComputeTetrahedralGraphOperators(const TetrahedralMesh& mesh, const double* points,
  int components, const double* values, const GraphOperatorOptions& options, const GraphOperatorOutputs& outputs,
  const Partition* split = nullptr);

} // namespace beltrami
