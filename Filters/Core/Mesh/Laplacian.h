// Beltrami core: discrete Laplacians of a triangle mesh (or of curves on it)
// in the symmetric form every solver here uses:
//
//     L(x)_i = 1/a_i * sum_j c_ij (x_j - x_i),   i.e.  L = -M^-1 S
//
// with symmetric edge weights c_ij, the stiffness matrix S (S_ii = sum_j c_ij,
// S_ij = -c_ij) and the lumped mass M = diag(a_i).  The operators of thesis
// chapter 3 are all of this form:
//   - umbrella (eq. 3.7):                c_ij = 1,              a_i = valence
//   - scale-dependent umbrella (3.11):   c_ij = 1/|e_ij|,       a_i = E_i / 2
//     (with the factor 2 of the 1D formula of section 3.4.2, so that it
//     approximates Laplace/2 like the curvature flow and a time step has the
//     same physical meaning, length^2, for both)
//   - curvature flow (eq. 3.13):         c_ij = (cot a + cot b)/4, a_i = A_Mixed
//     so that L(x_i) = -K(x_i)/2 = -kappa_H n  (eq. 3.12).
// The parameterization of chapter 5 also uses the rows of
//   - the discrete authalic weights (eq. 5.6): c_ij = (cot g_ij + cot d_ij)/|x_i - x_j|^2
//     with g_ij, d_ij the angles at x_j of the two triangles on edge (i, j)
//     (appendix A.6).  These are NOT symmetric (c_ij != c_ji): each CSR row
//     holds the weights of its own vertex, and the mass is left at 0.
// The graph is the vertex-neighbour CSR of MeshTopology::Graph() (or of a set
// of curves), with the weights stored per CSR entry for fast products.
#pragma once

#include "Solvers/GraphSolvers.h"
#include "Solvers/SparseGraph.h"
#include "Support/LargeBuffer.h"
#include "Mesh/MeshTopology.h"

#include <vector>

namespace beltrami
{

enum class LaplacianWeights : int
{
  Umbrella = 0,
  InverseEdgeLength = 1,
  Cotangent = 2,
  Authalic = 3 ///< eq. 5.6, non-symmetric (see above); for the parameterization
};

struct GraphLaplacian
{
  Index NumberOfVertices = 0;
  const std::int64_t* Offsets = nullptr; ///< CSR rows (size V+1), not owned
  const Index* Neighbors = nullptr;      ///< CSR columns, not owned
  LargeVector<double> Weights;           ///< c_ij per CSR entry
  LargeVector<double> Diagonal;          ///< S_ii = sum_j c_ij
  LargeVector<double> Mass;              ///< a_i
  /// Zero-area triangles skipped by the cotangent weights.
  Index DegenerateTriangles = 0;

  /// y = S x for `columns` interleaved values per vertex (parallel).
  void ApplyStiffness(const double* x, double* y, int columns, int numThreads) const;
  /// A shifted-Laplacian problem on this stiffness (K = S) for `columns`
  /// interleaved values per vertex: the graph fields set, the rest default.
  ShiftedLaplacianProblem Problem(int columns) const
  {
    ShiftedLaplacianProblem pb;
    pb.Rows = NumberOfVertices;
    pb.Columns = columns;
    pb.Offsets = Offsets;
    pb.Neighbors = Neighbors;
    pb.Weights = Weights.data();
    pb.Diagonal = Diagonal.data();
    return pb;
  }
  /// Completes row i once its weights are in: the diagonal (their sum) and the mass.
  void FinishRow(Index i, double mass)
  {
    double diag = 0.0;
    for (std::int64_t k = Offsets[i]; k < Offsets[i + 1]; ++k)
    {
      diag += Weights[k];
    }
    Diagonal[i] = diag;
    Mass[i] = mass;
  }
};

/// Assembles the surface Laplacian of `weights` kind at positions `points`
/// (3 doubles per vertex).  Cotangent and authalic weights skip zero-area
/// triangles (section 3.5.3); the mass of a vertex without area is 0 (callers
/// keep it fixed).
void AssembleSurfaceLaplacian(const MeshTopology& topology, const double* points,
  LaplacianWeights weights, GraphLaplacian& laplacian, int numThreads = 0);
/// The same for a surface embedded in R^dimension (3 to 8 doubles per vertex,
/// section 2.8.1: the cotangents come from dot products, so they hold in any
/// dimension); used by the graph flows of section 3.8 on data over surfaces.
void AssembleSurfaceLaplacian(const MeshTopology& topology, const double* points, int dimension,
  LaplacianWeights weights, GraphLaplacian& laplacian, int numThreads = 0);

/// The nonconforming (Crouzeix-Raviart) Laplacian of Polthier & Preuss: one
/// unknown per edge, the value at its midpoint, of functions linear in each
/// triangle and continuous only at the edge midpoints.  In a triangle the
/// basis function of edge e is 1 - 2 phi_k (k the vertex opposite e), so the
/// coupling of two of its edges that meet at vertex m is four times that of
/// the vertices opposite them: with the normalization of eq. 3.13 above (half
/// the finite-element stiffness) c_ee' = cot(theta_m) per triangle.  The
/// mass is the lumped area/3 per edge and triangle.  Edges of zero-area
/// triangles only get no coupling (callers keep them fixed).
struct EdgeGraph
{
  LargeVector<std::int64_t> Offsets; ///< CSR rows, one per edge (MeshTopology::Edges() order)
  IndexArray Neighbors;              ///< the other edges of the edge's triangles, ascending
  IndexArray TriangleEdges;          ///< 3 per triangle: the edge opposite corner 3t + k
  /// Builds the graph of `topology`'s edges (edges in three or more
  /// triangles are coupled to all of their triangles' edges); without
  /// `neighbors`, TriangleEdges alone.
  void Build(const MeshTopology& topology, bool neighbors = true);
};
void AssembleNonconformingLaplacian(const MeshTopology& topology, const EdgeGraph& graph,
  const double* points, GraphLaplacian& laplacian, int numThreads = 0);

/// A 1D Laplacian along polylines through mesh vertices (boundary loops,
/// feature curves): the graph holds, for every vertex, its curve neighbours
/// (none for vertices on no curve).  Umbrella: c = 1, a = 2; otherwise the 1D
/// formula of section 3.4.2: c = 1/|e|, a = (|e_prev| + |e_next|)/2.
struct CurveGraph
{
  std::vector<std::int64_t> Offsets;
  std::vector<Index> Neighbors;
  /// Builds the graph from closed loops and open chains (vertex lists).
  void Build(Index numberOfVertices, const std::vector<std::vector<Index>>& loops,
    const std::vector<std::vector<Index>>& chains);
};
void AssembleCurveLaplacian(const CurveGraph& graph, const double* points,
  LaplacianWeights weights, GraphLaplacian& laplacian);

} // namespace beltrami
