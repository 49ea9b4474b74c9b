#include "Solvers/SurfaceMultigrid.h"

#include "Solvers/GraphSolversDetail.h"
#include "Solvers/SparseFactorization.h"

#include <Eigen/SparseLU>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace beltrami
{

namespace
{

/// Gauss-Seidel sweeps before and after the coarse correction: two took
/// 18 and 5 iterations where one took 25 and 7 (order-2 and order-1 steps
/// of the clean 300k-triangle bunny), 57 and 14 where one took 86 and 21
/// (with noise of 0.3% of the diagonal), in about the same time.
constexpr int Sweeps = 2;

/// Real columns cycled together (complex values count two).
constexpr int MostColumns = 8;

using Complex = std::complex<double>;

/// One level's operators D and K in one pattern (DValues empty: D is
/// diagonal there).
struct LevelPair
{
  LevelMatrix K;
  LargeVector<double> DValues, DDiagonal;
};

/// The Galerkin product R A P of a pair (R = P^T), row by coarse row with a
/// dense accumulator per block of rows.
LevelPair Galerkin(const LevelPair& fine, const LevelMatrix& p, const LevelMatrix& r, Index coarse, int threads)
{
  constexpr Index block = 1024;
  const Index blocks = (coarse + block - 1) / block;
  struct Part
  {
    std::vector<std::int64_t> Counts;
    std::vector<Index> Columns;
    std::vector<double> K, D, KDiagonal, DDiagonal;
  };
  std::vector<Part> parts(blocks);
  const bool dense = !fine.DValues.empty();
  // The accumulators are the threads' own, kept between calls; an entry is
  // current when its stamp is this call's and this row's.
  static std::atomic<std::int64_t> calls{ 0 };
  const std::int64_t call = ++calls;
  ParallelFor(blocks, threads, [&](std::int64_t b0, std::int64_t b1) {
    thread_local std::vector<double> accK, accD;
    thread_local std::vector<std::int64_t> seen;
    if (seen.size() < static_cast<std::size_t>(coarse))
    {
      accK.resize(coarse);
      accD.resize(coarse);
      seen.resize(coarse, -1);
    }
    double* ak = accK.data();
    double* ad = accD.data();
    std::int64_t* at = seen.data();
    std::vector<Index> touched;
    for (std::int64_t bl = b0; bl < b1; ++bl)
    {
      Part& part = parts[bl];
      const Index first = static_cast<Index>(bl * block), last = std::min(coarse, first + block);
      for (Index a = first; a < last; ++a)
      {
        touched.clear();
        const std::int64_t stamp = (call << 32) + a;
        // acc[c] += w (P_j)_c over row j of P; both operators where D is not
        // diagonal, else K's alone (D's diagonal below).
        const auto add = [&](Index j, double wk, double wd, bool both) {
          for (std::int64_t m = p.Offsets[j]; m < p.Offsets[j + 1]; ++m)
          {
            const Index c = p.Columns[m];
            if (at[c] != stamp)
            {
              at[c] = stamp;
              ak[c] = ad[c] = 0.0;
              touched.push_back(c);
            }
            ak[c] += wk * p.Values[m];
            if (both)
            {
              ad[c] += wd * p.Values[m];
            }
          }
        };
        for (std::int64_t q = r.Offsets[a]; q < r.Offsets[a + 1]; ++q)
        {
          const Index i = r.Columns[q];
          const double w = r.Values[q];
          add(i, w * fine.K.Diagonal[i], w * fine.DDiagonal[i], true);
          for (std::int64_t k = fine.K.Offsets[i]; k < fine.K.Offsets[i + 1]; ++k)
          {
            add(fine.K.Columns[k], w * fine.K.Values[k], dense ? w * fine.DValues[k] : 0.0, dense);
          }
        }
        double kd = 0.0, dd = 0.0;
        std::int64_t count = 0;
        for (const Index c : touched)
        {
          if (c == a)
          {
            kd = ak[c];
            dd = ad[c];
            continue;
          }
          part.Columns.push_back(c);
          part.K.push_back(ak[c]);
          part.D.push_back(ad[c]);
          ++count;
        }
        part.Counts.push_back(count);
        part.KDiagonal.push_back(kd);
        part.DDiagonal.push_back(dd);
      }
    }
  }, {}, 0, 1);
  LevelPair c;
  c.K.Offsets.assign(1, 0);
  for (Part& part : parts)
  {
    for (const std::int64_t count : part.Counts)
    {
      c.K.Offsets.push_back(c.K.Offsets.back() + count);
    }
    c.K.Columns.insert(c.K.Columns.end(), part.Columns.begin(), part.Columns.end());
    c.K.Values.insert(c.K.Values.end(), part.K.begin(), part.K.end());
    c.DValues.insert(c.DValues.end(), part.D.begin(), part.D.end());
    c.K.Diagonal.insert(c.K.Diagonal.end(), part.KDiagonal.begin(), part.KDiagonal.end());
    c.DDiagonal.insert(c.DDiagonal.end(), part.DDiagonal.begin(), part.DDiagonal.end());
  }
  return c;
}

/// One level's operator as the kernels see it: the pattern of a
/// LevelMatrix with values and diagonal of scalar type T (double; complex
/// for D + i a K) and the smoother's diagonal.
template <typename T>
struct LevelView
{
  const LevelMatrix* Pattern = nullptr;
  const T* Values = nullptr;
  const T* Diagonal = nullptr;
  const T* Extra = nullptr;   ///< the smoother's diagonal less A_ii
  const T* Inverse = nullptr; ///< 1 / the smoother's diagonal

  Index Rows() const { return Pattern->Rows(); }
};

/// a b (for complex values without the library's checks for infinities,
/// a call per product).
inline double Times(double a, double b)
{
  return a * b;
}
inline Complex Times(Complex a, Complex b)
{
  return { a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real() };
}

/// |v|; for complex v the magnitudes of its two parts.
inline double Magnitude(double v)
{
  return std::abs(v);
}
inline Complex Magnitude(Complex v)
{
  return { std::abs(v.real()), std::abs(v.imag()) };
}

/// The smoother's diagonal: A_ii plus the magnitudes of row i's entries
/// outside its block of ParallelChunkSize rows (the "l1" hybrid
/// Gauss-Seidel of Baker, Falgout, Kolev and Yang 2011: convergent for every
/// symmetric positive definite A, where plain block-hybrid sweeps diverged on
/// noisy meshes, whose cotangent weights can be large and negative; for
/// D + i a K the real and imaginary parts are each made so).
/// Kept as the diagonal's excess over A_ii and its inverse.
template <typename T>
struct Smoother
{
  LargeVector<T> Extra, Inverse;
};

template <typename T>
Smoother<T> SmootherDiagonal(const LevelMatrix& pattern, const T* values, const T* diagonal, int threads)
{
  Smoother<T> d;
  d.Extra.assign(pattern.Rows(), T(0.0));
  d.Inverse.resize(pattern.Rows());
  ParallelForStatic(pattern.Rows(), threads, [&](std::int64_t lo, std::int64_t hi) {
    for (std::int64_t i = lo; i < hi; ++i)
    {
      for (std::int64_t k = pattern.Offsets[i]; k < pattern.Offsets[i + 1]; ++k)
      {
        if (pattern.Columns[k] < lo || pattern.Columns[k] >= hi)
        {
          d.Extra[i] += Magnitude(values[k]);
        }
      }
      d.Inverse[i] = T(1.0) / (diagonal[i] + d.Extra[i]);
    }
  });
  return d;
}

/// One level's operator D + s K (s = t, or i a) of scalar type T in its
/// pattern, and its smoother's diagonal.
template <typename T>
struct LevelValues
{
  LargeVector<T> Values, Diagonal;
  Smoother<T> Smooth;
};

/// Every level's D + s K and smoother diagonal.
template <typename T>
void Combined(const std::vector<LevelPair>& pairs, T s, std::vector<LevelValues<T>>& levels, int threads)
{
  levels.resize(pairs.size());
  for (std::size_t l = 0; l < pairs.size(); ++l)
  {
    const LevelPair& p = pairs[l];
    LevelValues<T>& v = levels[l];
    v.Values.resize(p.K.Values.size());
    v.Diagonal.resize(p.K.Diagonal.size());
    ParallelFor(static_cast<std::int64_t>(v.Values.size()), threads, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t k = b; k < e; ++k)
      {
        v.Values[k] = (p.DValues.empty() ? 0.0 : p.DValues[k]) + s * p.K.Values[k];
      }
    });
    for (std::size_t i = 0; i < v.Diagonal.size(); ++i)
    {
      // A coarse row whose finer rows are all held has no operator (its
      // row is zero, its right-hand side too): an identity row.
      const bool empty = p.DDiagonal[i] == 0.0 && p.K.Diagonal[i] == 0.0;
      v.Diagonal[i] = empty ? T(1.0) : p.DDiagonal[i] + s * p.K.Diagonal[i];
    }
    v.Smooth = SmootherDiagonal(p.K, v.Values.data(), v.Diagonal.data(), threads);
  }
}

/// sum[c] += Sign (row's entries [first, last) of `values` times the
/// values at(k)[c] they multiply), in two partial sums over alternate
/// entries: half the chain of dependent additions a row waits on (the 14
/// iterations of a 1M-vertex fandisk's solve: 1.1 s with one sum, 0.85 s
/// with two, the arrays in locals as RowsOf holds them).
template <int Sign, int W, typename T, typename At>
inline void AddRow(std::int64_t first, std::int64_t last, const T* values, const At& at, T* sum)
{
  const auto accumulate = [](T& to, T product) {
    if constexpr (Sign > 0)
    {
      to += product;
    }
    else
    {
      to -= product;
    }
  };
  T other[W] = {};
  std::int64_t k = first;
  for (; k + 1 < last; k += 2)
  {
    const T* xj = at(k);
    const T* xl = at(k + 1);
    for (int c = 0; c < W; ++c)
    {
      accumulate(sum[c], Times(values[k], xj[c]));
      accumulate(other[c], Times(values[k + 1], xl[c]));
    }
  }
  if (k < last)
  {
    const T* xj = at(k);
    for (int c = 0; c < W; ++c)
    {
      accumulate(sum[c], Times(values[k], xj[c]));
    }
  }
  for (int c = 0; c < W; ++c)
  {
    sum[c] += other[c];
  }
}

/// A level's arrays as the kernels' loops read them: held in locals, the
/// compiler reloaded them from the level at every entry (a write of x may
/// alias them as far as it knows).
template <typename T>
struct RowsOf
{
  explicit RowsOf(const LevelView<T>& a)
    : Offsets(a.Pattern->Offsets.data())
    , Columns(a.Pattern->Columns.data())
    , Values(a.Values)
  {
  }
  RowsOf(const LevelMatrix& m)
    : Offsets(m.Offsets.data())
    , Columns(m.Columns.data())
    , Values(m.Values.data())
  {
  }
  const std::int64_t* Offsets;
  const Index* Columns;
  const T* Values;
};

/// One Gauss-Seidel sweep of A x = b on every block of ParallelChunkSize rows
/// (forward or backward within the block, with the smoother's diagonal)
/// from x = `in` into `out`: the rows of the block already swept read from
/// `out`, the others (and the other blocks) from `in`: the values of an
/// in-place sweep with the other blocks' from a copy of x, without the
/// copy (the 1M-vertex fandisk's decomposition: 3.30 -> 3.16 s).
template <typename T, int W>
void Sweep(const LevelView<T>& a, const T* b, const T* in, T* out, bool forward, int threads)
{
  ParallelForStatic(a.Rows(), threads, [&a, b, in, out, forward](std::int64_t lo, std::int64_t hi) {
    const RowsOf<T> m(a);
    const T* extra = a.Extra;
    const T* inverse = a.Inverse;
    for (std::int64_t s = 0; s < hi - lo; ++s)
    {
      const std::int64_t i = forward ? lo + s : hi - 1 - s;
      const std::int64_t first = forward ? lo : i + 1; // the rows swept: [first, first + s)
      const auto at = [&](std::int64_t k) {
        const std::int64_t j = m.Columns[k];
        return (static_cast<std::uint64_t>(j - first) < static_cast<std::uint64_t>(s) ? out : in) + j * W;
      };
      T sum[W];
      for (int c = 0; c < W; ++c)
      {
        sum[c] = b[i * W + c] + Times(extra[i], in[i * W + c]);
      }
      AddRow<-1, W>(m.Offsets[i], m.Offsets[i + 1], m.Values, at, sum);
      for (int c = 0; c < W; ++c)
      {
        out[i * W + c] = Times(sum[c], inverse[i]);
      }
    }
  });
}

/// `sweeps` sweeps of A x = b in one direction, x updated (through `work`).
template <typename T, int W>
void Smooth(const LevelView<T>& a, const T* b, T* x, T* work, bool forward, int sweeps, int threads)
{
  T* from = x;
  T* to = work;
  for (int s = 0; s < sweeps; ++s)
  {
    Sweep<T, W>(a, b, from, to, forward, threads);
    std::swap(from, to);
  }
  if (from != x)
  {
    std::copy(from, from + static_cast<std::int64_t>(a.Rows()) * W, x);
  }
}

/// r = b - A x.
template <typename T, int W>
void Residual(const LevelView<T>& a, const T* b, const T* x, T* r, int threads)
{
  ParallelForStatic(a.Rows(), threads, [&a, b, x, r](std::int64_t lo, std::int64_t hi) {
    const RowsOf<T> m(a);
    const T* diagonal = a.Diagonal;
    const auto at = [&](std::int64_t k) { return x + static_cast<std::int64_t>(m.Columns[k]) * W; };
    for (std::int64_t i = lo; i < hi; ++i)
    {
      T sum[W];
      for (int c = 0; c < W; ++c)
      {
        sum[c] = b[i * W + c] - Times(diagonal[i], x[i * W + c]);
      }
      AddRow<-1, W>(m.Offsets[i], m.Offsets[i + 1], m.Values, at, sum);
      std::copy(sum, sum + W, r + i * W);
    }
  });
}

/// y = A x.
template <int W>
void Product(const LevelView<double>& a, const double* x, double* y, int threads)
{
  ParallelForStatic(a.Rows(), threads, [&a, x, y](std::int64_t lo, std::int64_t hi) {
    const RowsOf<double> m(a);
    const double* diagonal = a.Diagonal;
    const auto at = [&](std::int64_t k) { return x + static_cast<std::int64_t>(m.Columns[k]) * W; };
    for (std::int64_t i = lo; i < hi; ++i)
    {
      double sum[W];
      for (int c = 0; c < W; ++c)
      {
        sum[c] = diagonal[i] * x[i * W + c];
      }
      AddRow<1, W>(m.Offsets[i], m.Offsets[i + 1], m.Values, at, sum);
      std::copy(sum, sum + W, y + i * W);
    }
  });
}

/// y = M x (M stored without diagonal: a prolongation or restriction), or
/// y += M x with `add`.
template <int W>
void Multiply(const LevelMatrix& matrix, const double* x, double* y, bool add, int threads)
{
  const std::int64_t rows = static_cast<std::int64_t>(matrix.Offsets.size()) - 1;
  ParallelForStatic(rows, threads, [&matrix, x, y, add](std::int64_t lo, std::int64_t hi) {
    const RowsOf<double> m(matrix);
    const auto at = [&](std::int64_t k) { return x + static_cast<std::int64_t>(m.Columns[k]) * W; };
    for (std::int64_t i = lo; i < hi; ++i)
    {
      double sum[W];
      for (int c = 0; c < W; ++c)
      {
        sum[c] = add ? y[i * W + c] : 0.0;
      }
      AddRow<1, W>(m.Offsets[i], m.Offsets[i + 1], m.Values, at, sum);
      std::copy(sum, sum + W, y + i * W);
    }
  });
}

} // namespace

struct SurfaceMultigrid::State
{
  using ComplexMatrix = Eigen::SparseMatrix<Complex, Eigen::ColMajor, int>;

  std::shared_ptr<const SurfaceHierarchy> H;
  int Threads = 1;
  std::vector<LevelPair> Pairs; ///< also every level's pattern
  std::vector<LevelValues<double>> Real; ///< D + t K per level
  std::vector<std::uint8_t> Held; ///< the finest level's, renumbered
  SparseFactorization::Matrix CoarsestMatrix;
  SparseFactorization Coarsest;
  bool Factored = false;
  /// D + i a K per level (SetImaginaryFactor), and the coarsest level's LU.
  std::vector<LevelValues<Complex>> Imaginary;
  ComplexMatrix ComplexCoarsestMatrix;
  Eigen::SparseLU<ComplexMatrix> ComplexCoarsest;
  bool ComplexFactored = false;
  /// Work vectors per level (Reserve): right-hand side, solution, residual.
  mutable std::vector<LargeVector<double>> B, X, R;

  void Combine(double t);
  void CombineComplex(double a);
  int Levels() const { return static_cast<int>(Pairs.size()); }
  template <typename T>
  LevelView<T> ViewOf(int l) const
  {
    const LevelValues<T>& v = [&]() -> const LevelValues<T>& {
      if constexpr (std::is_same_v<T, Complex>)
      {
        return Imaginary[l];
      }
      else
      {
        return Real[l];
      }
    }();
    return { &Pairs[l].K, v.Values.data(), v.Diagonal.data(), v.Smooth.Extra.data(), v.Smooth.Inverse.data() };
  }
  template <typename T>
  T* Work(const std::vector<LargeVector<double>>& v, int l) const
  {
    return reinterpret_cast<T*>(const_cast<double*>(v[l].data()));
  }
  /// The work vectors for `reals` real values per row.
  void Reserve(int reals) const
  {
    for (std::size_t l = 0; l < B.size(); ++l)
    {
      const std::size_t size = static_cast<std::size_t>(reals) * H->Rows(static_cast<int>(l));
      for (auto* v : { &B[l], &X[l], &R[l] })
      {
        if (v->size() < size)
        {
          v->resize(size);
        }
      }
    }
  }
  template <typename T, int W>
  void CoarsestSolve() const;
  template <typename T, int W>
  void Cycle(int level) const;
};

namespace
{

/// The sparse matrix of a level's pattern with values and diagonal.
template <typename T>
Eigen::SparseMatrix<T, Eigen::ColMajor, int> SparseOf(const LevelMatrix& pattern, const T* values, const T* diagonal)
{
  const Index n = pattern.Rows();
  std::vector<Eigen::Triplet<T, int>> entries;
  for (Index i = 0; i < n; ++i)
  {
    entries.emplace_back(i, i, diagonal[i]);
    for (std::int64_t k = pattern.Offsets[i]; k < pattern.Offsets[i + 1]; ++k)
    {
      entries.emplace_back(i, pattern.Columns[k], values[k]);
    }
  }
  Eigen::SparseMatrix<T, Eigen::ColMajor, int> m(n, n);
  m.setFromTriplets(entries.begin(), entries.end());
  m.makeCompressed();
  return m;
}

} // namespace

void SurfaceMultigrid::State::Combine(double t)
{
  Combined(Pairs, t, Real, Threads);
  // The coarsest level's sparse Cholesky.
  CoarsestMatrix = SparseOf(Pairs.back().K, Real.back().Values.data(), Real.back().Diagonal.data());
  Factored = Pairs.back().K.Rows() > 0 && Coarsest.Compute(CoarsestMatrix, true, {}, false, Threads);
}

void SurfaceMultigrid::State::CombineComplex(double a)
{
  Combined(Pairs, Complex(0.0, a), Imaginary, Threads);
  ComplexCoarsestMatrix = SparseOf(Pairs.back().K, Imaginary.back().Values.data(), Imaginary.back().Diagonal.data());
  ComplexCoarsest.compute(ComplexCoarsestMatrix);
  ComplexFactored = Pairs.back().K.Rows() > 0 && ComplexCoarsest.info() == Eigen::Success;
}

template <typename T, int W>
void SurfaceMultigrid::State::CoarsestSolve() const
{
  const int l = Levels() - 1;
  const Index n = Pairs[l].K.Rows();
  const T* b = Work<T>(B, l);
  T* x = Work<T>(X, l);
  const bool factored = std::is_same_v<T, Complex> ? ComplexFactored : Factored;
  if (factored)
  {
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> rhs(n, W);
    for (Index i = 0; i < n; ++i)
    {
      for (int c = 0; c < W; ++c)
      {
        rhs(i, c) = b[i * W + c];
      }
    }
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> solution;
    if constexpr (std::is_same_v<T, Complex>)
    {
      solution = ComplexCoarsest.solve(rhs);
    }
    else
    {
      solution = Coarsest.Solve(rhs);
    }
    const bool finite = solution.allFinite();
    for (Index i = 0; i < n; ++i)
    {
      for (int c = 0; c < W; ++c)
      {
        x[i * W + c] = finite ? solution(i, c) : T(0.0);
      }
    }
    return;
  }
  // Singular (a component of a pure Laplacian without held rows): symmetric
  // Gauss-Seidel sweeps instead (still a symmetric operator).
  std::fill(x, x + static_cast<std::int64_t>(n) * W, T(0.0));
  for (int s = 0; s < 4; ++s)
  {
    Smooth<T, W>(ViewOf<T>(l), b, x, Work<T>(R, l), true, 1, Threads);
    Smooth<T, W>(ViewOf<T>(l), b, x, Work<T>(R, l), false, 1, Threads);
  }
}

/// One V-cycle from level l down, W values of type T per row (complex
/// values pass the real prolongation as two real columns each).
template <typename T, int W>
void SurfaceMultigrid::State::Cycle(int l) const
{
  if (l + 1 == Levels())
  {
    CoarsestSolve<T, W>();
    return;
  }
  constexpr int Reals = std::is_same_v<T, Complex> ? 2 * W : W;
  const LevelView<T> a = ViewOf<T>(l);
  T* x = Work<T>(X, l);
  T* b = Work<T>(B, l);
  T* r = Work<T>(R, l);
  std::fill(x, x + static_cast<std::int64_t>(a.Rows()) * W, T(0.0));
  Smooth<T, W>(a, b, x, r, true, Sweeps, Threads);
  Residual<T, W>(a, b, x, r, Threads);
  Multiply<Reals>(H->Restriction(l), R[l].data(), B[l + 1].data(), false, Threads);
  Cycle<T, W>(l + 1);
  Multiply<Reals>(H->Prolongation(l), X[l + 1].data(), X[l].data(), true, Threads);
  Smooth<T, W>(a, b, x, r, false, Sweeps, Threads);
}

SurfaceMultigrid::SurfaceMultigrid(std::shared_ptr<const SurfaceHierarchy> hierarchy, const std::int64_t* offsets,
  const Index* neighbors, const double* weights, const double* diagonal, const double* shift, double factor,
  const std::uint8_t* held, int numThreads)
  : S(std::make_unique<State>())
{
  S->H = std::move(hierarchy);
  S->Threads = ResolveThreadCount(numThreads);
  const SurfaceHierarchy& h = *S->H;
  const Index n = h.Rows(0);
  const std::vector<Index>& order = h.Order();
  // The finest level, renumbered; held rows are identity rows, their
  // couplings zero.
  const auto isHeld = [&](Index v) { return held && held[v]; };
  LevelPair fine;
  ShiftedLaplacianProblem graph;
  graph.Rows = n;
  graph.Offsets = offsets;
  graph.Neighbors = neighbors;
  graph.NumberOfThreads = S->Threads;
  detail::RenumberEntries(graph, order.data(), [&](Index v) { return !isHeld(v); },
    [&](std::int64_t k) { return isHeld(neighbors[k]) ? 0.0 : -weights[k]; }, fine.K.Offsets, fine.K.Columns,
    fine.K.Values);
  fine.K.Diagonal.resize(n);
  fine.DDiagonal.resize(n);
  S->Held.resize(n);
  ParallelForStatic(n, S->Threads, [&](std::int64_t s, std::int64_t e) {
    for (std::int64_t i = s; i < e; ++i)
    {
      const Index v = order[i];
      S->Held[i] = isHeld(v);
      fine.K.Diagonal[i] = isHeld(v) ? 0.0 : diagonal[v];
      fine.DDiagonal[i] = isHeld(v) ? 1.0 : (shift ? shift[v] : 0.0);
    }
  });
  S->Pairs.push_back(std::move(fine));
  for (int l = 0; l + 1 < h.Levels(); ++l)
  {
    // Held rows take no part in the coarse levels.
    if (l == 0 && held)
    {
      LevelMatrix p = h.Prolongation(0), r;
      for (Index i = 0; i < n; ++i)
      {
        for (std::int64_t k = p.Offsets[i]; k < p.Offsets[i + 1]; ++k)
        {
          p.Values[k] = S->Held[i] ? 0.0 : p.Values[k];
        }
      }
      r = Transposed(p, h.Rows(1));
      S->Pairs.push_back(Galerkin(S->Pairs[0], p, r, h.Rows(1), S->Threads));
      continue;
    }
    S->Pairs.push_back(Galerkin(S->Pairs[l], h.Prolongation(l), h.Restriction(l), h.Rows(l + 1), S->Threads));
  }
  S->B.resize(h.Levels());
  S->X.resize(h.Levels());
  S->R.resize(h.Levels());
  S->Combine(factor);
}

SurfaceMultigrid::~SurfaceMultigrid() = default;

void SurfaceMultigrid::SetFactor(double factor)
{
  S->Combine(factor);
}

void SurfaceMultigrid::ApplyInOrder(const double* r, double* z, int columns) const
{
  const std::int64_t size = static_cast<std::int64_t>(S->H->Rows(0)) * columns;
  if (columns < 1 || columns > MostColumns)
  {
    throw std::invalid_argument("SurfaceMultigrid::ApplyInOrder: 1 to 8 columns");
  }
  S->Reserve(columns);
  double* b = S->B[0].data();
  const double* x = S->X[0].data();
  const std::uint8_t* held = S->Held.data();
  ParallelForStatic(size, S->Threads, [&](std::int64_t s, std::int64_t e) {
    for (std::int64_t k = s; k < e; ++k)
    {
      b[k] = held[k / columns] ? 0.0 : r[k];
    }
  });
  WithCount<MostColumns>(columns, [&](auto k) { S->Cycle<double, decltype(k)::value>(0); });
  ParallelForStatic(size, S->Threads, [&](std::int64_t s, std::int64_t e) {
    for (std::int64_t k = s; k < e; ++k)
    {
      z[k] = held[k / columns] ? 0.0 : x[k];
    }
  });
}

void SurfaceMultigrid::MultiplyInOrder(const double* x, double* y, int columns) const
{
  if (columns < 1 || columns > MostColumns)
  {
    throw std::invalid_argument("SurfaceMultigrid::MultiplyInOrder: 1 to 8 columns");
  }
  WithCount<MostColumns>(columns, [&](auto k) { Product<decltype(k)::value>(S->ViewOf<double>(0), x, y, S->Threads); });
}

void SurfaceMultigrid::SetImaginaryFactor(double a)
{
  S->CombineComplex(a);
}

void SurfaceMultigrid::ApplyComplexInOrder(const double* r, double* z, int columns) const
{
  const Index n = S->H->Rows(0);
  const int w = 2 * columns;
  S->Reserve(2 * std::min(MostColumns / 2, columns));
  for (int first = 0; first < columns; first += MostColumns / 2)
  {
    const int k = std::min(MostColumns / 2, columns - first);
    Complex* b = S->Work<Complex>(S->B, 0);
    const Complex* x = S->Work<Complex>(S->X, 0);
    ParallelForStatic(n, S->Threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        for (int c = 0; c < k; ++c)
        {
          b[i * k + c] =
            S->Held[i] ? Complex(0.0) : Complex(r[i * w + first + c], r[i * w + columns + first + c]);
        }
      }
    });
    WithCount<MostColumns / 2>(k, [&](auto count) { S->Cycle<Complex, decltype(count)::value>(0); });
    ParallelForStatic(n, S->Threads, [&](std::int64_t s, std::int64_t e) {
      for (std::int64_t i = s; i < e; ++i)
      {
        for (int c = 0; c < k; ++c)
        {
          const Complex v = S->Held[i] ? Complex(0.0) : x[i * k + c];
          z[i * w + first + c] = v.real();
          z[i * w + columns + first + c] = v.imag();
        }
      }
    });
  }
}

void SurfaceMultigrid::RestrictToLevel(int coarse, const double* r, double* rc, int reals) const
{
  const SurfaceHierarchy& h = *S->H;
  const std::int64_t n = h.Rows(0);
  if (reals < 1 || reals > MostColumns)
  {
    throw std::invalid_argument("SurfaceMultigrid::RestrictToLevel: 1 to 8 values a row");
  }
  std::vector<double> level(r, r + n * reals), coarser;
  for (std::int64_t i = 0; i < n; ++i)
  {
    std::fill_n(level.data() + i * reals, S->Held[i] ? reals : 0, 0.0);
  }
  for (int l = 0; l < coarse; ++l)
  {
    coarser.resize(static_cast<std::size_t>(h.Rows(l + 1)) * reals);
    WithCount<MostColumns>(reals, [&](auto k) {
      Multiply<decltype(k)::value>(h.Restriction(l), level.data(), coarser.data(), false, S->Threads);
    });
    level.swap(coarser);
  }
  std::copy(level.begin(), level.end(), rc);
}

void SurfaceMultigrid::AddProlongedFromLevel(int coarse, const double* yc, double* z, int reals) const
{
  const SurfaceHierarchy& h = *S->H;
  if (reals < 1 || reals > MostColumns)
  {
    throw std::invalid_argument("SurfaceMultigrid::AddProlongedFromLevel: 1 to 8 values a row");
  }
  std::vector<double> level(yc, yc + static_cast<std::int64_t>(h.Rows(coarse)) * reals), finer;
  for (int l = coarse - 1; l >= 0; --l)
  {
    finer.resize(static_cast<std::size_t>(h.Rows(l)) * reals);
    WithCount<MostColumns>(reals, [&](auto k) {
      Multiply<decltype(k)::value>(h.Prolongation(l), level.data(), finer.data(), false, S->Threads);
    });
    level.swap(finer);
  }
  const std::int64_t n = h.Rows(0);
  for (std::int64_t k = 0; k < n * reals; ++k)
  {
    z[k] += S->Held[k / reals] ? 0.0 : level[k];
  }
}

int SurfaceMultigrid::Levels() const
{
  return S->Levels();
}

LevelMatrix SurfaceMultigrid::ShiftOperator(int level) const
{
  const LevelPair& p = S->Pairs[level];
  LevelMatrix d = p.K;
  d.Values.assign(p.DValues.begin(), p.DValues.end());
  d.Values.resize(p.K.Values.size(), 0.0); // (the finest level's D is diagonal)
  d.Diagonal.assign(p.DDiagonal.begin(), p.DDiagonal.end());
  return d;
}

const LevelMatrix& SurfaceMultigrid::Operator(int level) const
{
  return S->Pairs[level].K;
}

double SurfaceMultigrid::OperatorComplexity() const
{
  double all = 0.0;
  for (const LevelPair& p : S->Pairs)
  {
    all += static_cast<double>(p.K.Values.size() + p.K.Diagonal.size());
  }
  return all / static_cast<double>(S->Pairs[0].K.Values.size() + S->Pairs[0].K.Diagonal.size());
}

} // namespace beltrami
