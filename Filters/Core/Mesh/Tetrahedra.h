// Beltrami core: tetrahedralized 3-manifolds embedded in R^n (thesis section
// 2.8.2, appendix A.4) - the volume counterpart of MeshTopology and the
// surface Laplacian, shared by every volume filter.
//
// The operator is the gradient of the 1-ring volume.  For one tetrahedron
// (P, A, B, C) with edge vectors a = A - P, b = B - P, c = C - P in R^n, the
// volume is V = sqrt(det G) / 6 with G the 3x3 Gram matrix of (a, b, c), and
// (Jacobi's formula on det G, appendix A.4)
//
//     dV/dP = sum over the edges (P, X) of w_PX (P - X),
//     w_PA = (C_11 + C_12 + C_13) / (36 V),  w_AB = -C_12 / (36 V), ...
//
// with C the cofactor matrix of G.  These weights are l cot(theta) / 6 of the
// edge opposite (P, X) - the cotangent formula with dihedral angles - and are
// computed from dot products only, so they hold in any dimension.  Summed
// over the tetrahedra sharing an edge they give the symmetric stiffness of a
// GraphLaplacian: (K x)_i = sum_j c_ij (x_i - x_j) = d(volume)/d(x_i).  The
// lumped mass of a vertex is a quarter of the volume of its tetrahedra.
#pragma once

#include "Mesh/Laplacian.h"
#include "Support/Parallel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

/// Inlined into the vectorized loops that call it (also where they are
/// compiled for several processors).
#if defined(__GNUC__)
#define BELTRAMI_ALWAYS_INLINE __attribute__((always_inline))
#else
#define BELTRAMI_ALWAYS_INLINE
#endif

namespace beltrami
{

class Partition;

/// The volume of a tetrahedron and the weights of its six edges (pairs of
/// local vertices 01, 02, 03, 12, 13, 23) from four points in R^dimension.
/// Real: double, or float where the 3D image flow evaluates them.
template <typename Real>
struct BasicTetrahedronTerms
{
  Real Volume = 0;
  Real Weights[6] = { 0, 0, 0, 0, 0, 0 };
  bool Degenerate = true; ///< no volume: weights left at 0
};
using TetrahedronTerms = BasicTetrahedronTerms<double>;
TetrahedronTerms Tetrahedron(const double* p0, const double* p1, const double* p2,
  const double* p3, int dimension);

/// The same from the Gram matrix of the edge vectors a = A - P, b = B - P,
/// c = C - P (g11 = a.a, g12 = a.b, ...): what Tetrahedron() computes.
/// Inline and without branches: the 3D image flow evaluates six per voxel
/// and step in vectorized loops.
template <typename Real>
BELTRAMI_ALWAYS_INLINE inline BasicTetrahedronTerms<Real> TetrahedronFromGram(Real g11, Real g22, Real g33, Real g12, Real g13, Real g23)
{
  BasicTetrahedronTerms<Real> t;
  // Cofactors of the symmetric Gram matrix.
  const Real c11 = g22 * g33 - g23 * g23, c22 = g11 * g33 - g13 * g13, c33 = g11 * g22 - g12 * g12;
  const Real c12 = g13 * g23 - g12 * g33, c13 = g12 * g23 - g13 * g22, c23 = g12 * g13 - g11 * g23;
  const Real det = g11 * c11 + g12 * c12 + g13 * c13;
  // det G <= (1e-8 l)^3 with l the longest edge squared: no volume (a
  // scale-free degeneracy test, also for NaN).
  const Real l2 = std::max({ g11, g22, g33, g11 + g22 - 2 * g12, g11 + g33 - 2 * g13, g22 + g33 - 2 * g23 });
  const Real small = Real(1e-8) * l2;
  const bool solid = det > small * small * small;
  const Real root = std::sqrt(solid ? det : Real(1));
  const Real inv = Real(1) / (Real(6) * root); // 1 / (36 V)
  t.Volume = solid ? root / Real(6) : Real(0);
  t.Degenerate = !solid;
  // (selects, not products with 0: NaN cofactors give no weights either)
  t.Weights[0] = solid ? (c11 + c12 + c13) * inv : Real(0); // P-A
  t.Weights[1] = solid ? (c12 + c22 + c23) * inv : Real(0); // P-B
  t.Weights[2] = solid ? (c13 + c23 + c33) * inv : Real(0); // P-C
  t.Weights[3] = solid ? -c12 * inv : Real(0);              // A-B
  t.Weights[4] = solid ? -c13 * inv : Real(0);              // A-C
  t.Weights[5] = solid ? -c23 * inv : Real(0);              // B-C
  return t;
}

/// The local vertex pairs of the six edges of a tetrahedron.
constexpr int TetrahedronEdges[6][2] = { { 0, 1 }, { 0, 2 }, { 0, 3 }, { 1, 2 }, { 1, 3 }, { 2, 3 } };

/// A tetrahedral mesh: the tetrahedra (4 vertex ids each), the tetrahedra
/// of every vertex and the vertex-neighbour graph (CSR, sorted).
class TetrahedralMesh
{
public:
  /// Tetrahedra with an out-of-range or repeated vertex id are dropped.
  TetrahedralMesh(Index numberOfVertices, std::vector<Index> tetrahedra, int numThreads = 0);

  Index NumberOfVertices() const { return NumVertices; }
  Index NumberOfTetrahedra() const { return static_cast<Index>(Tets.size() / 4); }
  Index NumberOfDroppedTetrahedra() const { return Dropped; }
  const std::vector<Index>& TetrahedronList() const { return Tets; }

  /// Tetrahedra of vertex v (ids into the list): [IncidentBegin(v), IncidentEnd(v)).
  const Index* IncidentBegin(Index v) const { return Incident.data() + IncidentOffsets[v]; }
  const Index* IncidentEnd(Index v) const { return Incident.data() + IncidentOffsets[v + 1]; }

  /// For the incident tetrahedra of v in the order above, three entries
  /// each: its edges at v (index into TetrahedronEdges, in that order) and
  /// the position of the edge's other end in v's neighbour row.
  const std::uint8_t* IncidentEdges(Index v) const { return IncidentEdge.data() + 3 * IncidentOffsets[v]; }
  const std::uint32_t* IncidentSlots(Index v) const { return IncidentSlot.data() + 3 * IncidentOffsets[v]; }

  /// The vertex-neighbour CSR (the sparsity of the Laplacian).
  const std::vector<std::int64_t>& NeighborOffsets() const { return Offsets; }
  const std::vector<Index>& Neighbors() const { return NeighborList; }

  /// Per vertex, 1 on the boundary (a face of only one tetrahedron) or in
  /// no tetrahedron, else 0.
  std::vector<std::uint8_t> BoundaryVertices() const;

  /// Mean edge length at `points` (3 doubles per vertex).  split
  /// (optional, collective): the mesh is a piece with its rings of a mesh
  /// split over processes; the mean over the whole mesh.
  double MeanEdgeLength(const double* points, const Partition* split = nullptr) const;

private:
  Index NumVertices = 0;
  Index Dropped = 0;
  std::vector<Index> Tets;
  std::vector<std::int64_t> IncidentOffsets;
  std::vector<Index> Incident;
  std::vector<std::uint8_t> IncidentEdge;
  std::vector<std::uint32_t> IncidentSlot;
  std::vector<std::int64_t> Offsets;
  std::vector<Index> NeighborList;
};

/// The six monotone paths from cell corner (0,0,0) to (1,1,1): the axes
/// stepped along, in order; each path is one tetrahedron of the Kuhn split.
constexpr int KuhnPaths[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 }, { 2, 1, 0 } };

/// The tetrahedra of an nx x ny x nz grid of points (x fastest): every cell
/// split into 6 tetrahedra around its diagonal from (0,0,0) to (1,1,1)
/// (Kuhn / Freudenthal; conforming: neighbouring cells share face diagonals).
std::vector<Index> GridTetrahedra(Index nx, Index ny, Index nz);

/// Assembles the volume Laplacian of the mesh embedded in R^dimension
/// (`points`: dimension doubles per vertex, 3 to 9): c_ij summed over the
/// tetrahedra of edge (i, j), mass = volume / 4 per tetrahedron.  Degenerate
/// tetrahedra are skipped and counted in DegenerateTriangles.  `terms`
/// (optional): where the tetrahedra's terms are kept, a buffer the caller
/// keeps between assemblies (flows: no fresh memory per step).
void AssembleTetrahedralLaplacian(const TetrahedralMesh& mesh, const double* points, int dimension,
  GraphLaplacian& laplacian, int numThreads = 0, LargeVector<TetrahedronTerms>* terms = nullptr);

} // namespace beltrami
