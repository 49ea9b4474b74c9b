// Beltrami core: curvatures of a triangulated surface in R^3 (thesis 2.4-2.6).
#pragma once

#include "Mesh/MeshTopology.h"

#include <cstdint>

namespace beltrami
{

enum class CurvatureMethod : int
{
  Meyer2003 = 0, ///< the operators of the thesis (eq. 2.8-2.11, section 2.6.2)
  Taubin1995 = 1 ///< Taubin's curvature tensor (section 2.2.4), for comparison
};

enum class NormalWeighting : int
{
  MeanCurvatureNormal = 0, ///< K/|K| with the face-normal fallback (section 2.4.5) where K
                           ///< vanishes or is more than 60 degrees from the face normals
  Uniform = 1,             ///< Gouraud: unit face normals, weight 1
  Angle = 2,               ///< Thuermer & Wuethrich: weight = incident angle
  Max1999 = 3,             ///< Max: sin(theta) / (|e1| |e2|), section 2.2.1
  Area = 4                 ///< face area
};

/// What boundary and non-manifold vertices get, where curvature is not
/// defined by the thesis' operators (their 1-ring is not a closed disk).
enum class BoundaryPolicy : int
{
  NaN = 0,            ///< undefined: NaN (shown as the NaN colour, skipped by ranges)
  InteriorAverage = 1 ///< average of the adjacent regular vertices, propagated ring by ring
                      ///< (NaN only on components without a regular vertex)
};

struct CurvatureOptions
{
  CurvatureMethod Method = CurvatureMethod::Meyer2003;
  NormalWeighting Weighting = NormalWeighting::MeanCurvatureNormal;
  BoundaryPolicy Boundary = BoundaryPolicy::NaN;
  int NumberOfThreads = 0; ///< 0: all (see DefaultThreadCount())
};

/// Caller-owned outputs, one value (or 3) per vertex; null ones are skipped.
struct CurvatureOutputs
{
  double* MeanCurvatureNormal = nullptr; ///< 3 per vertex, K = 2 kappa_H n
  double* MixedArea = nullptr;
  double* MeanCurvature = nullptr; ///< signed kappa_H, > 0 on an outward sphere
  double* GaussianCurvature = nullptr;
  double* MaximumCurvature = nullptr; ///< kappa_1 >= kappa_2
  double* MinimumCurvature = nullptr;
  double* PrincipalDirection1 = nullptr; ///< 3 per vertex, unit, along kappa_1
  double* PrincipalDirection2 = nullptr; ///< 3 per vertex, unit, n x e1
  double* Normals = nullptr;             ///< 3 per vertex, unit
  std::uint8_t* Status = nullptr;        ///< VertexFlag bits per vertex
  /// Per vertex whose triangles form one closed, consistently oriented fan
  /// (VertexRegular): the smallest NormalCosine of two of its triangles
  /// that share an edge (1 if none is defined); NaN at the other vertices.
  /// (The line drawing's creases: read off the 1-ring loop, which has the
  /// triangles' normals at hand.)
  float* SharpestEdgeCosine = nullptr;
};

struct CurvatureReport
{
  bool Completed = true;              ///< false if the progress callback cancelled
  Index UndefinedVertices = 0;        ///< boundary / non-manifold / isolated
  Index DegenerateTriangleVertices = 0; ///< vertices touching a zero-area triangle
  Index NonFiniteVertices = 0;        ///< vertices with a NaN/inf coordinate in their 1-ring
};

/// points: 3 interleaved coordinates per vertex (float or double).  Surfaces
/// far from unit size (extent or offset beyond 2^+-60: a 1e100 sphere's
/// squared areas overflow, a 1e-100 one's vanish) are computed on their
/// points scaled by a power of two (exact) and the outputs scaled back.
template <typename T>
CurvatureReport ComputeCurvatures(const MeshTopology& topology, const T* points,
  const CurvatureOptions& options, const CurvatureOutputs& outputs,
  const ProgressCallback& progress = {});

} // namespace beltrami
