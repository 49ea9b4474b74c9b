// Beltrami core: the discrete operators of chapter 2 for 2-manifolds
// embedded in R^N (section 2.8.1), per vertex.
#pragma once

#include "Mesh/MeshTopology.h"

namespace beltrami
{

/// Raw 1-ring operators at every vertex of a triangulated 2-manifold in R^N:
///  - beltrami:    K(x_i) = 1/(2 A_Mixed) sum_j (cot a_ij + cot b_ij)(x_i - x_j)
///                 (eq. 2.8; N values per vertex; the Beltrami operator of the
///                 embedding, i.e. the mean curvature normal in R^3),
///  - mixedArea:   A_Mixed (figure 2.3),
///  - angleDefect: 2*pi - sum(theta_j), whose ratio to A_Mixed is the
///                 Gaussian curvature (eq. 2.9, valid in R^N).
/// points holds `stride` values per vertex of which the first `dimension`
/// (2 to 8) are used.  Any output may be null.  Values are the raw sums:
/// callers decide what boundary and non-manifold vertices mean (see
/// MeshTopology::VertexFlags()); vertices without area get NaN for K.
/// Returns false if the progress callback cancelled the computation.
template <typename T>
bool ComputeBeltramiOperator(const MeshTopology& topology, const T* points, int dimension,
  int stride, double* beltrami, double* mixedArea, double* angleDefect, int numThreads = 0,
  const ProgressCallback& progress = {});

} // namespace beltrami
