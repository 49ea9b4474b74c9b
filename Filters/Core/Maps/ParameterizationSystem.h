// Beltrami core, private to Maps/: the sparse linear systems of the
// parameterization (rows over unknowns, the kinds of unknowns, constraint rows
// by Lagrange multipliers) and their solver (sparse factorization of the free
// block, dense Schur complement for the extras and constraints, impulse
// responses for the boundary basis).
#pragma once

#include "Maps/Parameterization.h"
#include "Mesh/Geometry.h"
#include "Solvers/NestedDissection.h"
#include "Solvers/SparseFactorization.h"
#include "Support/LargeBuffer.h"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

namespace beltrami::detail
{

// ---------------------------------------------------------------------------
// A sparse system over "unknowns" (one per vertex and coordinate pair, or one
// per vertex coordinate for the coupled natural map), split into
//   F: solved through a sparse factorization,
//   G: a few extra unknowns solved densely with the constraints (pins whose
//      position is left free when constraints fix the map),
//   D: fixed values.
// The equations are the rows of F and G, plus constraint rows C y = t added
// with Lagrange multipliers (section 5.4.1):
//   [A_FF A_FG C_F^T] [f]   [b_F]
//   [A_GF A_GG C_G^T] [g] = [b_G]      (b = -A_.D d)
//   [C_F  C_G  0    ] [e]   [t  ]
// f is eliminated with the factorization of A_FF, leaving a small dense system.
// Several right-hand-side columns share the matrix (u and v for the
// per-vertex systems).

// The systems' arrays are LargeVectors (2 MiB pages, reused by the next
// run): at 179k vertices they hold some 100 MB, and faulting them in 4 KiB
// pages on machines where page faults are slow cost 0.2-0.4 s of a first run.
struct RowMatrix // CSR rows over all unknowns
{
  LargeVector<std::int64_t> Offsets;
  LargeVector<int> Columns;
  LargeVector<double> Values;
};

/// A square compressed matrix (by rows or by columns) in LargeVectors.
struct CompressedMatrix
{
  int Size = 0;
  LargeVector<int> Outer, Inner;
  LargeVector<double> Values;

  SparseFactorization::MatrixView View() const
  {
    return { Size, Size, static_cast<Eigen::Index>(Values.size()), Outer.data(), Inner.data(), Values.data() };
  }

  /// The transpose (rows <-> columns), sorted within each row or column.
  CompressedMatrix Transposed() const
  {
    CompressedMatrix t;
    t.Size = Size;
    t.Outer.assign(static_cast<std::size_t>(Size) + 1, 0);
    t.Inner.resize(Inner.size());
    t.Values.resize(Values.size());
    for (int i : Inner)
    {
      ++t.Outer[i + 1];
    }
    std::partial_sum(t.Outer.begin(), t.Outer.end(), t.Outer.begin());
    std::vector<int> next(t.Outer.begin(), t.Outer.end() - 1);
    for (int r = 0; r < Size; ++r)
    {
      for (int k = Outer[r]; k < Outer[r + 1]; ++k)
      {
        const int at = next[Inner[k]]++;
        t.Inner[at] = r;
        t.Values[at] = Values[k];
      }
    }
    return t;
  }
};

struct ConstraintRow
{
  std::vector<std::pair<int, double>> Entries; ///< (unknown, coefficient)
  std::vector<double> Target;                  ///< per right-hand-side column
};

/// The fill-reducing elimination order of the mesh vertices.
inline std::vector<Index> VertexOrder(const MeshTopology& topo, const double* points, int threads)
{
  const MeshTopology::VertexGraph& edges = topo.Graph();
  return NestedDissectionOrder(
    topo.NumberOfVertices(), edges.NeighborOffsets.data(), edges.Neighbors.data(), points, threads);
}

enum UnknownKind : std::uint8_t
{
  KindFactor = 0,
  KindExtra = 1,
  KindFixed = 2,
  KindUnused = 3
};

struct ParameterizationSolver
{
  // Unknown partition.
  std::vector<std::uint8_t> Kind;
  std::vector<int> Slot; // index within its kind
  int NumberFactor = 0, NumberExtra = 0;
  SparseFactorization Factor;
  CompressedMatrix AFF; // compressed columns (the factorization refers to it)
  Eigen::MatrixXd AFD_d; // -A_FD d per column (the right-hand side b_F)
  Eigen::MatrixXd AFG, AGF, AGG, BG;

  /// Splits the rows of `rows` by the kinds, factorizes A_FF and forms the
  /// right-hand sides from `fixedValues` (columns values per unknown).
  /// `vertexOrder`: the elimination order of the mesh vertices, whose
  /// unknowns are numbered vertex-major (one or two per vertex);
  /// `twinPairs`: see SparseFactorization::Compute.
  bool Setup(const RowMatrix& rows, const std::vector<std::uint8_t>& kind,
    const Eigen::MatrixXd& fixedValues, bool symmetric, const std::vector<Index>& vertexOrder,
    bool twinPairs, int threads, std::string& error)
  {
    Kind = kind;
    const int n = static_cast<int>(kind.size());
    Slot.assign(n, -1);
    NumberFactor = NumberExtra = 0;
    for (int i = 0; i < n; ++i)
    {
      if (kind[i] == KindFactor)
      {
        Slot[i] = NumberFactor++;
      }
      else if (kind[i] == KindExtra)
      {
        Slot[i] = NumberExtra++;
      }
    }
    const int columns = static_cast<int>(fixedValues.cols());
    AFD_d = Eigen::MatrixXd::Zero(NumberFactor, columns);
    AFG = Eigen::MatrixXd::Zero(NumberFactor, NumberExtra);
    AGF = Eigen::MatrixXd::Zero(NumberExtra, NumberFactor);
    AGG = Eigen::MatrixXd::Zero(NumberExtra, NumberExtra);
    BG = Eigen::MatrixXd::Zero(NumberExtra, columns);
    // A_FF in compressed rows, each sorted by column: AFF itself when A is
    // symmetric (rows are columns), else transposed afterwards.
    CompressedMatrix byRows;
    byRows.Size = NumberFactor;
    byRows.Outer.assign(static_cast<std::size_t>(NumberFactor) + 1, 0);
    for (int r = 0; r < n; ++r)
    {
      if (kind[r] == KindFactor)
      {
        for (std::int64_t k = rows.Offsets[r]; k < rows.Offsets[r + 1]; ++k)
        {
          byRows.Outer[Slot[r] + 1] += kind[rows.Columns[k]] == KindFactor;
        }
      }
    }
    std::partial_sum(byRows.Outer.begin(), byRows.Outer.end(), byRows.Outer.begin());
    byRows.Inner.resize(static_cast<std::size_t>(byRows.Outer.back()));
    byRows.Values.resize(byRows.Inner.size());
    int* const outer = byRows.Outer.data();
    int* const inner = byRows.Inner.data();
    double* const values = byRows.Values.data();
    for (int r = 0; r < n; ++r)
    {
      if (kind[r] != KindFactor && kind[r] != KindExtra)
      {
        continue;
      }
      int out = kind[r] == KindFactor ? outer[Slot[r]] : 0;
      for (std::int64_t k = rows.Offsets[r]; k < rows.Offsets[r + 1]; ++k)
      {
        const int c = rows.Columns[k];
        const double v = rows.Values[k];
        if (kind[c] == KindFixed)
        {
          for (int col = 0; col < columns; ++col)
          {
            (kind[r] == KindFactor ? AFD_d(Slot[r], col) : BG(Slot[r], col)) -= v * fixedValues(c, col);
          }
        }
        else if (kind[r] == KindFactor && kind[c] == KindFactor)
        {
          inner[out] = Slot[c];
          values[out++] = v;
        }
        else if (kind[r] == KindFactor && kind[c] == KindExtra)
        {
          AFG(Slot[r], Slot[c]) += v;
        }
        else if (kind[r] == KindExtra && kind[c] == KindFactor)
        {
          AGF(Slot[r], Slot[c]) += v;
        }
        else if (kind[r] == KindExtra && kind[c] == KindExtra)
        {
          AGG(Slot[r], Slot[c]) += v;
        }
      }
      if (kind[r] == KindFactor) // sort the row by column (a few entries)
      {
        const int b = outer[Slot[r]], e = outer[Slot[r] + 1];
        for (int i = b + 1; i < e; ++i)
        {
          for (int j = i; j > b && inner[j - 1] > inner[j]; --j)
          {
            std::swap(inner[j - 1], inner[j]);
            std::swap(values[j - 1], values[j]);
          }
        }
      }
    }
    AFF = symmetric ? std::move(byRows) : byRows.Transposed();
    std::vector<int> order;
    order.reserve(static_cast<std::size_t>(NumberFactor));
    const std::size_t perVertex = kind.size() / std::max<std::size_t>(vertexOrder.size(), 1);
    for (Index v : vertexOrder)
    {
      for (std::size_t d = 0; d < perVertex; ++d)
      {
        const std::size_t u = perVertex * static_cast<std::size_t>(v) + d;
        if (kind[u] == KindFactor)
        {
          order.push_back(Slot[u]);
        }
      }
    }
    if (NumberFactor > 0 && !Factor.Compute(AFF.View(), symmetric, order, twinPairs, threads))
    {
      error = "the linear system is singular (degenerate triangles or a disconnected part?)";
      return false;
    }
    return true;
  }

  /// Solves with the constraint rows; returns the values of the F and G
  /// unknowns (columns as in Setup) in `solution` (rows = all unknowns; fixed
  /// and unused rows are left as they are).
  bool Solve(const std::vector<ConstraintRow>& constraints, Eigen::MatrixXd& solution,
    std::string& error) const
  {
    const int columns = static_cast<int>(AFD_d.cols());
    const int r = static_cast<int>(constraints.size());
    Eigen::MatrixXd x0 = NumberFactor ? Factor.Solve(AFD_d) : Eigen::MatrixXd(0, columns);
    Eigen::MatrixXd g = Eigen::MatrixXd::Zero(NumberExtra, columns);
    Eigen::MatrixXd eta = Eigen::MatrixXd::Zero(r, columns);
    if (NumberExtra + r > 0)
    {
      // Constraint rows split over F (dense columns, r of them) and G.
      Eigen::MatrixXd CF = Eigen::MatrixXd::Zero(NumberFactor, r); // C_F^T
      Eigen::MatrixXd CG = Eigen::MatrixXd::Zero(r, NumberExtra);
      Eigen::MatrixXd t = Eigen::MatrixXd::Zero(r, columns);
      for (int k = 0; k < r; ++k)
      {
        for (const auto& [u, coefficient] : constraints[k].Entries)
        {
          if (Kind[u] == KindFactor)
          {
            CF(Slot[u], k) += coefficient;
          }
          else if (Kind[u] == KindExtra)
          {
            CG(k, Slot[u]) += coefficient;
          }
          else if (Kind[u] == KindFixed)
          {
            for (int col = 0; col < columns; ++col)
            {
              t(k, col) -= coefficient * solution(u, col);
            }
          }
        }
        for (int col = 0; col < columns; ++col)
        {
          t(k, col) += constraints[k].Target[col];
        }
      }
      Eigen::MatrixXd rhsF(NumberFactor, NumberExtra + r);
      rhsF << AFG, CF;
      const Eigen::MatrixXd ZY = NumberFactor ? Factor.Solve(rhsF) : rhsF; // [Z Y]
      const Eigen::MatrixXd Z = ZY.leftCols(NumberExtra), Y = ZY.rightCols(r);
      const int m = NumberExtra + r;
      Eigen::MatrixXd K(m, m);
      Eigen::MatrixXd rhs(m, columns);
      K.topLeftCorner(NumberExtra, NumberExtra) = AGG - AGF * Z;
      K.topRightCorner(NumberExtra, r) = CG.transpose() - AGF * Y;
      K.bottomLeftCorner(r, NumberExtra) = CG - CF.transpose() * Z;
      K.bottomRightCorner(r, r) = -CF.transpose() * Y;
      rhs.topRows(NumberExtra) = BG - AGF * x0;
      rhs.bottomRows(r) = t - CF.transpose() * x0;
      Eigen::FullPivLU<Eigen::MatrixXd> lu(K);
      if (lu.rank() < m)
      {
        error = "the point constraints are inconsistent or redundant (two constraints on the same "
                "point, or constraints on fixed boundary points that disagree with the boundary)";
        return false;
      }
      const Eigen::MatrixXd ge = lu.solve(rhs);
      g = ge.topRows(NumberExtra);
      eta = ge.bottomRows(r);
      x0 -= Z * g + Y * eta;
    }
    for (int u = 0; u < static_cast<int>(Kind.size()); ++u)
    {
      if (Kind[u] == KindFactor)
      {
        solution.row(u) = x0.row(Slot[u]);
      }
      else if (Kind[u] == KindExtra)
      {
        solution.row(u) = g.row(Slot[u]);
      }
    }
    return true;
  }

  /// Point constraints on the factor unknowns of a system without extra
  /// unknowns, held on maps of the fixed values: with C the constraint
  /// columns, Y = A^-1 C and K = -C^T Y, a map x0 of fixed values alone
  /// becomes x0 + Y K^-1 C^T x0 (the constraints held at zero: Project), and
  /// the targets T add Offset = -Y K^-1 T.  For a symmetric A (so K too)
  /// the transpose of the projection is g + C K^-1 Y^T g (ProjectTransposed).
  struct ConstraintProjection
  {
    Eigen::MatrixXd C, Y, Offset;
    Eigen::FullPivLU<Eigen::MatrixXd> LU;
    bool Empty() const { return C.cols() == 0; }
    Eigen::MatrixXd Project(const Eigen::MatrixXd& x0) const
    {
      return Empty() ? x0 : Eigen::MatrixXd(x0 + Y * LU.solve(C.transpose() * x0));
    }
    Eigen::MatrixXd ProjectTransposed(const Eigen::MatrixXd& g) const
    {
      return Empty() ? g : Eigen::MatrixXd(g + C * LU.solve(Y.transpose() * g));
    }
  };

  /// The projection of `constraints` (see ConstraintProjection); false (with
  /// `error`) when they are redundant or touch fixed unknowns.
  bool Project(const std::vector<ConstraintRow>& constraints, ConstraintProjection& p, std::string& error) const
  {
    const int r = static_cast<int>(constraints.size());
    const int columns = static_cast<int>(AFD_d.cols());
    p.C = Eigen::MatrixXd::Zero(NumberFactor, r);
    Eigen::MatrixXd T(r, columns);
    for (int k = 0; k < r; ++k)
    {
      for (const auto& [u, coefficient] : constraints[k].Entries)
      {
        if (Kind[u] != KindFactor)
        {
          error = "point constraints on boundary points do not combine with the boundary basis";
          return false;
        }
        p.C(Slot[u], k) += coefficient;
      }
      for (int col = 0; col < columns; ++col)
      {
        T(k, col) = constraints[k].Target[col];
      }
    }
    p.Y = Factor.Solve(p.C);
    p.LU.compute(-p.C.transpose() * p.Y);
    if (p.LU.rank() < r)
    {
      error = "the point constraints are inconsistent or redundant (two constraints on the same point)";
      return false;
    }
    p.Offset = r ? Eigen::MatrixXd(-p.Y * p.LU.solve(T)) : Eigen::MatrixXd::Zero(NumberFactor, columns);
    return true;
  }

  /// The coupling A_FB of the factor rows of `rows` to the fixed unknowns
  /// `fixed` (columns in that order).
  Eigen::SparseMatrix<double> FixedCoupling(const RowMatrix& rows, const std::vector<int>& fixed) const
  {
    std::vector<int> column(Kind.size(), -1);
    for (std::size_t j = 0; j < fixed.size(); ++j)
    {
      column[fixed[j]] = static_cast<int>(j);
    }
    std::vector<Eigen::Triplet<double>> entries;
    for (int r = 0; r < static_cast<int>(Kind.size()); ++r)
    {
      if (Kind[r] != KindFactor)
      {
        continue;
      }
      for (std::int64_t k = rows.Offsets[r]; k < rows.Offsets[r + 1]; ++k)
      {
        if (column[rows.Columns[k]] >= 0)
        {
          entries.emplace_back(Slot[r], column[rows.Columns[k]], rows.Values[k]);
        }
      }
    }
    Eigen::SparseMatrix<double> coupling(NumberFactor, static_cast<Eigen::Index>(fixed.size()));
    coupling.setFromTriplets(entries.begin(), entries.end());
    return coupling;
  }

  /// Impulse responses of the fixed unknowns (section 5.4.2), for a system
  /// without extra unknowns: column j = response to fixed unknown `fixed[j]`.
  Eigen::MatrixXd ImpulseResponses(const RowMatrix& rows, const std::vector<int>& fixed) const
  {
    const Eigen::MatrixXd rhs = -Eigen::MatrixXd(FixedCoupling(rows, fixed));
    Eigen::MatrixXd basis(NumberFactor, rhs.cols());
    const int chunk = 64;
    for (int j = 0; j < rhs.cols(); j += chunk)
    {
      const int w = std::min<int>(chunk, static_cast<int>(rhs.cols()) - j);
      basis.middleCols(j, w) = Factor.Solve(rhs.middleCols(j, w));
    }
    return basis;
  }
};


/// The per-vertex system rows lambda M^A + mu h^2 M^chi (unknown = vertex).
RowMatrix VertexSystem(const MeshTopology& topo, const double* points, double lambda, double mu,
  int threads, Index& degenerate);

/// The coupled rows of the natural conformal map (eq. 5.7, halved):
/// unknowns 2i (u) and 2i+1 (v):  S (x) I_2  -  (1/2) Hess(signed area).
RowMatrix NaturalSystem(const MeshTopology& topo, const double* points, int threads,
  const std::vector<Index>& boundaryPrev, Index& degenerate);

void AddConstraintRows(const ParameterizationOptions& options, bool coupled,
  std::vector<ConstraintRow>& rows);

} // namespace beltrami::detail
