// Beltrami core: vector fields on triangle surfaces (thesis section 6.3's
// next operators): the Helmholtz-Hodge decomposition of Polthier & Preuss
// (2003), divergence and curl.
//
// A field is one tangent vector per triangle (constant on it).  It splits
// into three parts, orthogonal in L2 (sum over the triangles of area times
// the dot product):
//   X = grad u + J grad v + H
// - grad u, the curl-free part: u piecewise linear and continuous (one value
//   per vertex), the least-squares fit S u = (X, grad phi_i), S the cotangent
//   stiffness of the shared assembler;
// - J grad v, the divergence-free part (J the rotation by +90 degrees about
//   the triangle's normal): v nonconforming (one value per edge midpoint,
//   Laplacian.h's EdgeGraph), the fit of J^T X the same way;
// - H, the harmonic part: the remainder, divergence- and curl-free.
// Where there are no harmonic fields (every component closed and of genus
// 0, or a disk), X - grad u is all of J grad v: v is then integrated across
// the triangles instead of solved (VectorFieldOptions::Integrate).
// grad u and J grad v are exactly orthogonal (on each edge u is continuous
// and v's mean is shared), so both fits are the orthogonal projections and
// on a closed surface of genus g the harmonic fields span exactly 2g
// dimensions (the space of fields per triangle has 2F = (V - 1) + (E - 1) + 2g
// of them).  On open surfaces one of the two functions is fixed at 0 on the
// boundary (VectorFieldBoundary); the harmonic fields then span 2g + b - 1
// dimensions, b the number of boundary loops (none on a disk).
//
// Per vertex: Divergence div X = -(X, grad phi_i) / A_i and Curl (vorticity,
// n . curl X) = (J^T X, grad phi_i) / A_i: the flux of X out of the vertex's
// cell and its circulation along the cell's boundary (any cell whose boundary
// runs through the midpoints of the vertex's edges: for a field constant per
// triangle they are the same), over the cell's area A_i, here the lumped
// area (a third of each triangle; integral of phi_i).  The mixed area of
// figure 2.3 would be as good for a field given per triangle, but with the
// per-triangle means of point data it overestimates by up to 4/3 at vertices
// whose triangles are thin (the poles of a latitude-longitude sphere).  For
// X = grad u + J grad v on a smooth surface: Laplace u and Laplace v.
#pragma once

#include "Mesh/MeshTopology.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace beltrami
{

class Partition;

/// Which function is fixed at 0 on the boundary of an open surface.
enum class VectorFieldBoundary : int
{
  /// The stream function: the divergence-free part carries no flux through
  /// the boundary (in the weak sense of its midpoint values), the curl-free
  /// part takes the field's flux.
  TangentDivergenceFree = 0,
  /// The potential: the curl-free part is normal to the boundary, the
  /// divergence-free part takes the field's circulation along it.
  NormalCurlFree = 1
};

/// The two Poisson systems are solved by a sparse Cholesky factorization
/// in nested-dissection order (Solvers/SparseFactorization.h: faster than
/// conjugate gradients with algebraic multigrid on these systems, 1.4x at
/// 735k vertices and 2x at 38k, with the same memory); where it fails or its
/// residual misses the tolerance, by conjugate gradients preconditioned by
/// BoomerAMG.
struct VectorFieldOptions
{
  VectorFieldBoundary Boundary = VectorFieldBoundary::TangentDivergenceFree;
  /// Relative residual of the two Poisson solves.
  double Tolerance = 1e-10;
  /// Where every component is closed and of genus 0, or a disk (no harmonic
  /// fields), X - grad u is all divergence-free and its stream function is
  /// integrated across the triangles instead of solved (the same to the
  /// first solve's accuracy, in a fraction of the time); false: solved.
  bool Integrate = true;
  /// The decomposer will take many fields on the same surface (time
  /// steps): the vertices' system is factorized once, and each field costs
  /// its triangular solves. Otherwise, on surfaces of at least
  /// MultigridVertices vertices, it is solved by conjugate gradients on the
  /// surface's geometric multigrid: less time and memory for one field (a
  /// factorization where that misses the tolerance).
  bool ManyFields = false;
  Index MultigridVertices = 50000;
  int NumberOfThreads = 0;
};

/// The parts of a field (3 values per triangle unless said otherwise).
struct VectorFieldDecomposition
{
  std::vector<double> Tangent;        ///< the input with its normal component removed
  std::vector<double> Normal;         ///< that normal component, 1 per triangle
  std::vector<double> CurlFree;       ///< grad u
  std::vector<double> DivergenceFree; ///< J grad v
  std::vector<double> Harmonic;       ///< the rest
  std::vector<double> Potential;      ///< u, 1 per vertex (0 at a vertex of each closed component)
  std::vector<double> StreamFunction; ///< v, 1 per edge (MeshTopology::Edges() order)
  /// 1 per triangle (0: zero area or NaN coordinates), the weights of
  /// point values; for coordinates far from unit size those of the points
  /// times 2^-FarScaleExponent (an area may overflow where its weight does not).
  std::vector<double> Areas;
  std::vector<double> Divergence;     ///< 1 per vertex (NaN where the vertex has no area)
  std::vector<double> Curl;           ///< 1 per vertex (NaN where the vertex has no area)
  /// Integrals over the surface: |Tangent|^2, |CurlFree|^2, |DivergenceFree|^2, |Harmonic|^2.
  double Energy[4] = { 0, 0, 0, 0 };
  /// (CurlFree, DivergenceFree), (CurlFree, Harmonic), (DivergenceFree, Harmonic).
  double InnerProducts[3] = { 0, 0, 0 };
  Index DegenerateTriangles = 0; ///< zero-area triangles: their field is left out (parts 0)
  int Iterations = 0;            ///< of the conjugate gradients (0: the direct solves met the tolerance)
  double Residual = 0.0;         ///< the larger relative residual of the two solves
  bool Converged = true;
  bool Integrated = false;       ///< the stream function integrated (VectorFieldOptions::Integrate), not solved
};

/// The decomposition prepared for one surface: the frames of its triangles,
/// its components and the two Poisson systems, factorized.  Decompose then
/// costs two triangular solves a field (the time steps of a field on a fixed
/// mesh).  `topology` and `points` must outlive it.
class VectorFieldDecomposer
{
public:
  VectorFieldDecomposer(const MeshTopology& topology, const double* points, const VectorFieldOptions& options);
  ~VectorFieldDecomposer();
  VectorFieldDecomposer(const VectorFieldDecomposer&) = delete;
  VectorFieldDecomposer& operator=(const VectorFieldDecomposer&) = delete;
  /// As DecomposeVectorField.
  void Decompose(const double* vectors, VectorFieldDecomposition& result) const;

private:
  struct Internals;
  std::unique_ptr<Internals> I;
};

/// Decomposes `vectors` (3 per triangle of `topology`; need not be tangent)
/// on the surface `points` (3 per vertex).  The topology should be manifold
/// and consistently oriented (the filter removes the triangles where it is
/// not); NaN vectors count as zero.
void DecomposeVectorField(const MeshTopology& topology, const double* points, const double* vectors,
  const VectorFieldOptions& options, VectorFieldDecomposition& result);

/// DecomposeVectorField on a surface split over processes (collective:
/// every process of `split` calls it, one whose part is empty too).
/// `topology` is this process's part: the rows of `split` its points, the
/// whole star of each point it owns among its triangles (a piece with the
/// rings of the pieces around it), and `vectors` given on every triangle
/// of it.  The systems are solved by conjugate gradients on BoomerAMG
/// spanning the processes; where there are no harmonic fields
/// (VectorFieldOptions::Integrate) the stream function is integrated, each
/// process across its part, the parts joined by constants from the edges
/// they share (ManyFields is not used: nothing is kept).  The
/// results are the serial ones to the solvers' tolerance, on every point,
/// edge and triangle of the part (the parts' values on triangles whose
/// vectors were given); the energies, inner products, degenerate triangles,
/// iterations and residual are those of the whole surface, the same on
/// every process.
void DecomposeVectorField(const MeshTopology& topology, const double* points, const double* vectors,
  const VectorFieldOptions& options, const Partition& split, VectorFieldDecomposition& result);

/// Values given per triangle (`components` each) as values per vertex: the
/// mean over the vertex's triangles weighted by `areas` (one per triangle,
/// VectorFieldDecomposition::Areas: zero-area triangles left out); 0 at a
/// vertex in none.
std::vector<double> PointValuesFromTriangles(
  const MeshTopology& topology, const std::vector<double>& areas, const double* triangleValues, int components);
/// Per vertex, the mean of a per-edge function over the vertex's edges
/// (the stream function at the vertices; NaN at a vertex in no edge).
std::vector<double> PointValuesFromEdges(const MeshTopology& topology, const double* edgeValues);

} // namespace beltrami
