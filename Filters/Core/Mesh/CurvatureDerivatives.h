// Beltrami core: the derivative of the curvature tensor per vertex, for the
// line drawings (suggestive contours, ridges and valleys), which
// need the third-order quantity C = D II beyond chapter 2's operators.
//
// Method: Rusinkiewicz, "Estimating curvatures and their derivatives on
// triangle meshes" (3DPVT 2004), section 4, applied to the curvature tensors
// of ComputeCurvatures (thesis 2.5-2.6): per face, the three vertex tensors
// rotated into the face's plane, and the symmetric 3-tensor (4 unknowns in
// 2D) that best explains their differences along the three edges (9
// equations, least squares); per vertex, the faces' tensors rotated into
// the vertex's tangent plane and averaged with the corners' mixed (Voronoi)
// areas of figure 2.3.  Chosen over a least-squares fit of the 1-ring's
// tensors because it reads only the 1-ring of faces (the same ring the
// curvatures read), weights by area (so irregular sampling does not bias
// it), and is exact for tensor fields linear over each face.
#pragma once

#include "Mesh/MeshTopology.h"

namespace beltrami
{

/// A curvature tensor field, one per vertex (the outputs of ComputeCurvatures,
/// NaN where undefined): unit normals, kappa_1 >= kappa_2, e1, e2 = n x e1.
struct CurvatureTensors
{
  const double* Normals = nullptr;    ///< 3 per vertex
  const double* Maximum = nullptr;    ///< kappa_1
  const double* Minimum = nullptr;    ///< kappa_2
  const double* Direction1 = nullptr; ///< 3 per vertex
  const double* Direction2 = nullptr; ///< 3 per vertex
};

/// The 4 components of a symmetric 3-tensor in 2D: C(x, y, z) =
/// C111 x1y1z1 + C112 (x1y1z2 + x1y2z1 + x2y1z1) + C122 (...) + C222 x2y2z2.
inline double EvaluateCubicForm(const double* c, const double* x, const double* y, const double* z)
{
  return c[0] * x[0] * y[0] * z[0] + c[1] * (x[0] * y[0] * z[1] + x[0] * y[1] * z[0] + x[1] * y[0] * z[0]) +
    c[2] * (x[0] * y[1] * z[1] + x[1] * y[0] * z[1] + x[1] * y[1] * z[0]) + c[3] * x[1] * y[1] * z[1];
}

/// Per vertex, 4 values: C(e1,e1,e1), C(e1,e1,e2), C(e1,e2,e2), C(e2,e2,e2)
/// in its principal frame, so D_e1 kappa_1 is the first and D_e2 kappa_2 the
/// last.  NaN at vertices none of whose faces has three defined tensors.
/// Returns the number of such vertices.
template <typename T>
Index ComputeCurvatureDerivatives(const MeshTopology& topology, const T* points,
  const CurvatureTensors& tensors, double* derivatives, int numThreads = 0);

} // namespace beltrami
