#include "Solvers/SupernodalLU.h"

#include "Solvers/DenseBlocks.h"

#include "Support/LargeBuffer.h"
#include "Support/Parallel.h"

#include <cholmod.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <queue>
#include <thread>
#include <utility>

namespace beltrami
{

using namespace detail;

struct SupernodalLU::Internals
{
  cholmod_common Common; // for the symbolic analysis
  bool Symmetric = false; // Cholesky: U = Lᵀ, no Ux
  int Size = 0;
  int Supernodes = 0;
  // The supernodal structure (CHOLMOD's analysis): supernode t holds columns
  // [Super[t], Super[t+1]) and rows Rows[RowStart[t] .. RowStart[t+1]) (its
  // own columns first, then ascending); its values are the column-major
  // height x width block at Lx + ValueStart[t] (L, and the
  // diagonal block's L and U) and the (height - width) x width block at
  // Ux + UpperStart[t] (Uᵀ below the diagonal block).
  std::vector<int> Super, RowStart, Rows, SuperOf, Perm, Swaps;
  std::vector<std::int64_t> ValueStart, UpperStart;
  LargeVector<double> Lx, Ux;
  double Ratio = 0.0;
  // Updates: supernode t receives from each descendant d = From[u] for u in
  // [UpdateStart[t], UpdateStart[t+1]) the rows First[u] .. of d, of which
  // those before Last[u] are t's own columns.
  std::vector<int> UpdateStart, From, First, Last;
  std::size_t Workspace = 0;

  Internals()
  {
    cholmod_start(&Common);
    Common.print = 0;
    Common.nmethods = 1;
    Common.method[0].ordering = CHOLMOD_GIVEN;
    Common.supernodal = CHOLMOD_SUPERNODAL;
    // CHOLMOD's default relaxed amalgamation.  (SparseFactorization's
    // coarser one for its Cholesky costs the LU a third more memory for no
    // speed: 179k vertices, 12.4M vs 15.9M entries in L, 0.16 s either way.)
    Common.nrelax[0] = 4;
    Common.nrelax[1] = 16;
    Common.nrelax[2] = 48;
    Common.zrelax[0] = 0.8;
    Common.zrelax[1] = 0.1;
    Common.zrelax[2] = 0.05;
  }
  ~Internals() { cholmod_finish(&Common); }

  int Width(int t) const { return Super[t + 1] - Super[t]; }
  int Height(int t) const { return RowStart[t + 1] - RowStart[t]; }

  bool Analyze(const MatrixView& a, const std::vector<int>& order, bool keepOrder)
  {
    const int n = Size;
    const int* p = a.outerIndexPtr();
    const int* rows = a.innerIndexPtr();
    // The lower triangle of pattern(A + Aᵀ) with the diagonal, by columns.
    std::vector<int> offsets(static_cast<std::size_t>(n) + 1, 1);
    offsets[0] = 0;
    for (int j = 0; j < n; ++j)
    {
      for (int e = p[j]; e < p[j + 1]; ++e)
      {
        offsets[std::min(rows[e], j) + 1] += rows[e] != j;
      }
    }
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    std::vector<int> inner(static_cast<std::size_t>(offsets[n]));
    std::vector<int> next(offsets.begin(), offsets.end() - 1);
    for (int j = 0; j < n; ++j)
    {
      inner[next[j]++] = j;
      for (int e = p[j]; e < p[j + 1]; ++e)
      {
        if (rows[e] != j)
        {
          const int lo = std::min(rows[e], j), hi = std::max(rows[e], j);
          inner[next[lo]++] = hi;
        }
      }
    }
    int out = 0;
    for (int j = 0; j < n; ++j) // sort and merge each column (the two halves)
    {
      const int begin = offsets[j];
      std::sort(inner.begin() + begin, inner.begin() + offsets[j + 1]);
      const int end = static_cast<int>(std::unique(inner.begin() + begin, inner.begin() + offsets[j + 1]) - inner.begin());
      offsets[j] = out;
      for (int e = begin; e < end; ++e)
      {
        inner[out++] = inner[e];
      }
    }
    offsets[n] = out;
    cholmod_sparse pattern{};
    pattern.nrow = pattern.ncol = static_cast<std::size_t>(n);
    pattern.nzmax = static_cast<std::size_t>(out);
    pattern.p = offsets.data();
    pattern.i = inner.data();
    pattern.stype = -1;
    pattern.itype = CHOLMOD_INT;
    pattern.xtype = CHOLMOD_PATTERN;
    pattern.dtype = CHOLMOD_DOUBLE;
    pattern.sorted = 1;
    pattern.packed = 1;
    Common.postorder = !keepOrder;
    cholmod_factor* symbolic = cholmod_analyze_p(&pattern, const_cast<int*>(order.data()), nullptr, 0, &Common);
    if (!symbolic)
    {
      return false;
    }
    const bool ok = symbolic->is_super && symbolic->itype == CHOLMOD_INT;
    if (ok)
    {
      Supernodes = static_cast<int>(symbolic->nsuper);
      const int* super = static_cast<const int*>(symbolic->super);
      const int* pi = static_cast<const int*>(symbolic->pi);
      const int* px = static_cast<const int*>(symbolic->px);
      const int* s = static_cast<const int*>(symbolic->s);
      const int* perm = static_cast<const int*>(symbolic->Perm);
      Super.assign(super, super + Supernodes + 1);
      RowStart.assign(pi, pi + Supernodes + 1);
      ValueStart.assign(px, px + Supernodes + 1);
      Rows.assign(s, s + RowStart.back());
      Perm.assign(perm, perm + n);
    }
    cholmod_free_factor(&symbolic, &Common);
    return ok;
  }

  /// The update lists, the elimination tree of the supernodes and the
  /// workspace size.  False when the structure is not the expected one.
  bool Connect(std::vector<int>& parent)
  {
    SuperOf.resize(static_cast<std::size_t>(Size));
    parent.assign(static_cast<std::size_t>(Supernodes), -1);
    for (int t = 0; t < Supernodes; ++t)
    {
      std::fill(SuperOf.begin() + Super[t], SuperOf.begin() + Super[t + 1], t);
      int* rows = Rows.data() + RowStart[t];
      const int w = Width(t), h = Height(t);
      for (int q = 0; q < w; ++q)
      {
        if (q >= h || rows[q] != Super[t] + q)
        {
          return false;
        }
      }
      std::sort(rows + w, rows + h);
    }
    UpdateStart.assign(static_cast<std::size_t>(Supernodes) + 1, 0);
    for (int pass = 0; pass < 2; ++pass)
    {
      std::vector<int> fill;
      if (pass == 1)
      {
        std::partial_sum(UpdateStart.begin(), UpdateStart.end(), UpdateStart.begin());
        From.resize(static_cast<std::size_t>(UpdateStart.back()));
        First.resize(From.size());
        Last.resize(From.size());
        fill.assign(UpdateStart.begin(), UpdateStart.end() - 1);
      }
      for (int d = 0; d < Supernodes; ++d)
      {
        const int* rows = Rows.data() + RowStart[d];
        const int h = Height(d);
        for (int r = Width(d); r < h;)
        {
          const int t = SuperOf[rows[r]];
          if (t <= d)
          {
            return false;
          }
          int end = r;
          while (end < h && rows[end] < Super[t + 1])
          {
            ++end;
          }
          if (pass == 0)
          {
            ++UpdateStart[t + 1];
            parent[d] = parent[d] < 0 ? t : parent[d];
            Workspace = std::max(Workspace, static_cast<std::size_t>(h - r) * static_cast<std::size_t>(end - r));
          }
          else
          {
            const int u = fill[t]++;
            From[u] = d;
            First[u] = r;
            Last[u] = end;
          }
          r = end;
        }
      }
    }
    return true;
  }

  void Assemble(const MatrixView& a, int threads, std::atomic<bool>& failed)
  {
    std::vector<int> inverse(static_cast<std::size_t>(Size));
    for (int k = 0; k < Size; ++k)
    {
      inverse[Perm[k]] = k;
    }
    const int* p = a.outerIndexPtr();
    const int* rows = a.innerIndexPtr();
    const double* values = a.valuePtr();
    ParallelFor(Size, threads, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t column = begin; column < end; ++column)
      {
        const int j = inverse[column];
        for (int e = p[column]; e < p[column + 1]; ++e)
        {
          if (Symmetric && rows[e] < column)
          {
            continue; // the lower triangle only
          }
          const int i = inverse[rows[e]];
          const int lo = std::min(i, j), hi = std::max(i, j);
          const int t = SuperOf[lo], k1 = Super[t], h = Height(t);
          const std::int64_t base = ValueStart[t];
          if (hi < Super[t + 1])
          {
            Lx[base + (Symmetric ? static_cast<std::int64_t>(lo - k1) * h + (hi - k1)
                                 : static_cast<std::int64_t>(j - k1) * h + (i - k1))] += values[e];
            continue;
          }
          const int* first = Rows.data() + RowStart[t];
          const int* at = std::lower_bound(first + Super[t + 1] - k1, first + h, hi);
          if (at == first + h || *at != hi)
          {
            failed = true;
            return;
          }
          const int r = static_cast<int>(at - first), w = Super[t + 1] - k1;
          if (i > j || Symmetric)
          {
            Lx[base + static_cast<std::int64_t>(lo - k1) * h + r] += values[e];
          }
          else
          {
            Ux[UpperStart[t] + static_cast<std::int64_t>(lo - k1) * (h - w) + (r - w)] += values[e];
          }
        }
      }
    });
  }

  /// Factorizes supernode t (its descendants done); `map` (Size entries)
  /// and `work` are this thread's.  Returns the largest |multiplier|, or -1
  /// on a zero pivot.
  double FactorizeSupernode(int t, std::vector<int>& map, std::vector<double>& work, std::vector<int>& positions)
  {
    const int k1 = Super[t], w = Width(t), h = Height(t);
    const int* rows = Rows.data() + RowStart[t];
    for (int r = 0; r < h; ++r)
    {
      map[rows[r]] = r;
    }
    double* lt = Lx.data() + ValueStart[t];
    double* ut = Symmetric ? nullptr : Ux.data() + UpperStart[t];
    const int below = h - w;
    for (int u = UpdateStart[t]; u < UpdateStart[t + 1]; ++u)
    {
      const int d = From[u], first = First[u], last = Last[u];
      const int wd = Width(d), hd = Height(d), m = hd - first, wc = last - first;
      const int* rd = Rows.data() + RowStart[d];
      const double* ld = Lx.data() + ValueStart[d];
      // Row r of Uᵀ at ud + r (r >= wd); Lᵀ's for a Cholesky factorization.
      const double* ud = Symmetric ? ld : Ux.data() + UpperStart[d] - wd;
      const int hu = Symmetric ? hd : hd - wd;
      for (int r = 0; r < m; ++r)
      {
        positions[r] = map[rd[first + r]];
      }
      // L (and the diagonal block): rows first.. of d times U's columns in t.
      MultiplyTransposed(m, wc, wd, ld + first, hd, ud + first, hu, work.data());
      for (int q = 0; q < wc; ++q)
      {
        double* target = lt + static_cast<std::ptrdiff_t>(rd[first + q] - k1) * h;
        const double* c = work.data() + static_cast<std::ptrdiff_t>(q) * m;
        for (int r = 0; r < m; ++r)
        {
          target[positions[r]] -= c[r];
        }
      }
      // U: t's rows times the columns of U beyond t.
      const int mu = m - wc;
      if (mu > 0 && !Symmetric)
      {
        MultiplyTransposed(mu, wc, wd, ud + last, hu, ld + first, hd, work.data());
        for (int q = 0; q < wc; ++q)
        {
          double* target = ut + static_cast<std::ptrdiff_t>(rd[first + q] - k1) * below - w;
          const double* c = work.data() + static_cast<std::ptrdiff_t>(q) * mu;
          for (int r = 0; r < mu; ++r)
          {
            target[positions[wc + r]] -= c[r];
          }
        }
      }
    }
    if (Symmetric)
    {
      if (!FactorizeDenseSymmetric(w, lt, h))
      {
        return -1.0;
      }
      SolveOnTheRight(Triangle::LowerT, below, w, lt, h, lt + w, h); // L below: A L^-T
      return 0.0;
    }
    int* swaps = Swaps.data() + k1;
    if (!FactorizeDense(w, lt, h, swaps))
    {
      return -1.0;
    }
    // The row exchanges of the diagonal block are exchanges of U's rows:
    // columns of the stored Uᵀ.
    for (int q = 0; q < w; ++q)
    {
      if (swaps[q] != q)
      {
        std::swap_ranges(ut + static_cast<std::ptrdiff_t>(q) * below, ut + static_cast<std::ptrdiff_t>(q + 1) * below,
          ut + static_cast<std::ptrdiff_t>(swaps[q]) * below);
      }
    }
    SolveOnTheRight(Triangle::Upper, below, w, lt, h, lt + w, h);     // L below: A U^-1
    SolveOnTheRight(Triangle::UnitLowerT, below, w, lt, h, ut, below); // Uᵀ below: Aᵀ L^-T
    double largest = 0.0;
    for (int q = 0; q < w; ++q)
    {
      const double* column = lt + static_cast<std::ptrdiff_t>(q) * h;
      for (int r = q + 1; r < h; ++r)
      {
        largest = std::max(largest, std::abs(column[r]));
      }
    }
    return largest;
  }

  bool Factorize(const std::vector<int>& parent, int threads)
  {
    // Subtrees for the threads: split the costliest subtree into its
    // children (its root joins the serial top part) until every subtree is
    // below a quarter of a thread's share.
    std::vector<double> cost(static_cast<std::size_t>(Supernodes));
    std::vector<std::vector<int>> children(static_cast<std::size_t>(Supernodes));
    std::vector<int> roots;
    double total = 0.0;
    for (int t = 0; t < Supernodes; ++t)
    {
      const double w = Width(t), h = Height(t);
      cost[t] += w * h * h;
      total += w * h * h;
      if (parent[t] >= 0)
      {
        cost[parent[t]] += cost[t];
        children[parent[t]].push_back(t);
      }
      else
      {
        roots.push_back(t);
      }
    }
    std::vector<int> subtrees;
    std::vector<std::uint8_t> top(static_cast<std::size_t>(Supernodes), 0);
    if (threads > 1)
    {
      auto cheaper = [&](int x, int y) { return cost[x] < cost[y]; };
      std::priority_queue<int, std::vector<int>, decltype(cheaper)> queue(cheaper, roots);
      while (!queue.empty() && cost[queue.top()] > total / (4.0 * threads) && !children[queue.top()].empty() &&
        queue.size() < 256)
      {
        const int t = queue.top();
        queue.pop();
        top[t] = 1;
        for (int c : children[t])
        {
          queue.push(c);
        }
      }
      for (; !queue.empty(); queue.pop())
      {
        subtrees.push_back(queue.top()); // costliest first
      }
    }
    // Each subtree's supernodes in ascending order (children come before
    // their parents; a postorder would make them contiguous, but an order
    // kept as given need not be).
    std::vector<std::vector<int>> members(subtrees.size());
    for (std::size_t k = 0; k < subtrees.size(); ++k)
    {
      for (std::vector<int> stack(1, subtrees[k]); !stack.empty();)
      {
        const int t = stack.back();
        stack.pop_back();
        members[k].push_back(t);
        stack.insert(stack.end(), children[t].begin(), children[t].end());
      }
      std::sort(members[k].begin(), members[k].end());
    }
    Swaps.assign(static_cast<std::size_t>(Size), 0);
    std::atomic<bool> failed{ false };
    std::atomic<int> nextSubtree{ 0 };
    std::vector<double> largest(static_cast<std::size_t>(std::max(threads, 1)), 0.0);
    // Factorizes `nodes` in order on thread `id`, with that thread's
    // workspace, made once per thread: a subtree per decoupled row (the
    // fixed rows of a Poisson system) made thousands of subtrees, whose
    // zeroed workspaces of the matrix's size took 27 of 30 s (1.7M rows).
    struct Scratch
    {
      std::vector<int> map, positions;
      std::vector<double> work;
    };
    const auto scratch = [&]() {
      return Scratch{ std::vector<int>(static_cast<std::size_t>(Size)),
        std::vector<int>(static_cast<std::size_t>(Size)), std::vector<double>(Workspace) };
    };
    auto factorize = [&](const std::vector<int>& nodes, int id, Scratch& s) {
      std::vector<int>& map = s.map;
      std::vector<int>& positions = s.positions;
      std::vector<double>& work = s.work;
      for (std::size_t i = 0; i < nodes.size() && !failed; ++i)
      {
        const double g = FactorizeSupernode(nodes[i], map, work, positions);
        failed = failed || g < 0.0;
        largest[id] = std::max(largest[id], g);
      }
    };
    if (!subtrees.empty())
    {
      SingleThreadedBlas serialBlas;
      auto worker = [&](int id) {
        Scratch s = scratch();
        for (int k = nextSubtree++; k < static_cast<int>(subtrees.size()) && !failed; k = nextSubtree++)
        {
          factorize(members[k], id, s);
        }
      };
      std::vector<std::thread> pool;
      for (int id = 1; id < threads; ++id)
      {
        pool.emplace_back(worker, id);
      }
      worker(0);
      for (std::thread& thread : pool)
      {
        thread.join();
      }
    }
    // The top part (everything on one thread), with the BLAS's threads.
    std::vector<int> rest;
    for (int t = 0; t < Supernodes; ++t)
    {
      if (subtrees.empty() || top[t])
      {
        rest.push_back(t);
      }
    }
    Scratch s = scratch();
    factorize(rest, 0, s);
    if (failed || *std::max_element(largest.begin(), largest.end()) > 1e8)
    {
      return false;
    }
    double smallest = HUGE_VAL, biggest = 0.0;
    for (int t = 0; t < Supernodes; ++t)
    {
      const double* lt = Lx.data() + ValueStart[t];
      for (int q = 0; q < Width(t); ++q)
      {
        const double pivot = std::abs(lt[static_cast<std::ptrdiff_t>(q) * Height(t) + q]);
        smallest = std::min(smallest, pivot);
        biggest = std::max(biggest, pivot);
      }
    }
    Ratio = Size == 0 ? 1.0 : smallest / biggest;
    Ratio = Symmetric ? Ratio * Ratio : Ratio; // as the pivots of A
    return std::isfinite(Ratio);
  }
};

SupernodalLU::SupernodalLU()
  : Internal(std::make_unique<Internals>())
{
}

SupernodalLU::~SupernodalLU() = default;

bool SupernodalLU::Compute(
  const MatrixView& a, const std::vector<int>& order, int numThreads, bool symmetric, bool keepOrder)
{
  Internal = std::make_unique<Internals>();
  Internals& in = *Internal;
  in.Size = static_cast<int>(a.rows());
  in.Symmetric = symmetric;
  if (a.rows() != a.cols() || order.size() != static_cast<std::size_t>(in.Size) ||
    !in.Analyze(a, order, keepOrder))
  {
    return false;
  }
  std::vector<int> parent;
  if (!in.Connect(parent))
  {
    return false;
  }
  in.Lx.assign(static_cast<std::size_t>(in.ValueStart.back()), 0.0);
  in.UpperStart.assign(static_cast<std::size_t>(in.Supernodes) + 1, 0);
  for (int t = 0; t < in.Supernodes && !symmetric; ++t)
  {
    in.UpperStart[t + 1] = in.UpperStart[t] + static_cast<std::int64_t>(in.Height(t) - in.Width(t)) * in.Width(t);
  }
  in.Ux.assign(static_cast<std::size_t>(in.UpperStart.back()), 0.0);
  std::atomic<bool> failed{ false };
  const int threads = ResolveThreadCount(numThreads);
  in.Assemble(a, threads, failed);
  return !failed && in.Factorize(parent, threads);
}

double SupernodalLU::PivotRatio() const
{
  return Internal->Ratio;
}

const std::vector<int>& SupernodalLU::Order() const
{
  return Internal->Perm;
}

void SupernodalLU::TrailingBlock(Eigen::Ref<Eigen::MatrixXd> block) const
{
  const Internals& in = *Internal;
  const int m = static_cast<int>(block.rows()), first = in.Size - m;
  for (int t = m > 0 ? in.SuperOf[first] : in.Supernodes; t < in.Supernodes; ++t)
  {
    const int k1 = in.Super[t], h = in.Height(t);
    const int* rows = in.Rows.data() + in.RowStart[t];
    const double* lt = in.Lx.data() + in.ValueStart[t];
    for (int j = std::max(k1, first); j < in.Super[t + 1]; ++j)
    {
      for (int r = j - k1; r < h; ++r) // from the diagonal down
      {
        block(rows[r] - first, j - first) = lt[static_cast<std::ptrdiff_t>(j - k1) * h + r];
      }
    }
  }
}

void SupernodalLU::SolveLower(Eigen::MatrixXd& b) const
{
  const Internals& in = *Internal;
  Eigen::MatrixXd y(b.rows(), b.cols()), gathered;
  for (int k = 0; k < in.Size; ++k)
  {
    y.row(k) = b.row(in.Perm[k]);
  }
  for (int t = 0; t < in.Supernodes; ++t)
  {
    const int k1 = in.Super[t], w = in.Width(t), h = in.Height(t), below = h - w;
    const int* rows = in.Rows.data() + in.RowStart[t];
    const double* lt = in.Lx.data() + in.ValueStart[t];
    auto yt = y.middleRows(k1, w);
    if (in.Symmetric)
    {
      ConstStrided(lt, w, w, Eigen::OuterStride<>(h)).triangularView<Eigen::Lower>().solveInPlace(yt);
    }
    else
    {
      for (int q = 0; q < w; ++q)
      {
        if (in.Swaps[k1 + q] != q)
        {
          y.row(k1 + q).swap(y.row(k1 + in.Swaps[k1 + q]));
        }
      }
      ConstStrided(lt, w, w, Eigen::OuterStride<>(h)).triangularView<Eigen::UnitLower>().solveInPlace(yt);
    }
    if (below > 0)
    {
      gathered.noalias() = ConstStrided(lt + w, below, w, Eigen::OuterStride<>(h)) * yt;
      for (int r = 0; r < below; ++r)
      {
        y.row(rows[w + r]) -= gathered.row(r);
      }
    }
  }
  b.swap(y);
}

void SupernodalLU::SolveUpper(Eigen::MatrixXd& b) const
{
  const Internals& in = *Internal;
  Eigen::MatrixXd& y = b;
  Eigen::MatrixXd gathered;
  for (int t = in.Supernodes - 1; t >= 0; --t)
  {
    const int k1 = in.Super[t], w = in.Width(t), h = in.Height(t), below = h - w;
    const int* rows = in.Rows.data() + in.RowStart[t];
    const double* lt = in.Lx.data() + in.ValueStart[t];
    auto yt = y.middleRows(k1, w);
    if (below > 0)
    {
      gathered.resize(below, y.cols());
      for (int r = 0; r < below; ++r)
      {
        gathered.row(r) = y.row(rows[w + r]);
      }
      if (in.Symmetric)
      {
        yt.noalias() -= ConstStrided(lt + w, below, w, Eigen::OuterStride<>(h)).transpose() * gathered;
      }
      else
      {
        const double* ut = in.Ux.data() + in.UpperStart[t];
        yt.noalias() -= ConstStrided(ut, below, w, Eigen::OuterStride<>(below)).transpose() * gathered;
      }
    }
    if (in.Symmetric)
    {
      const ConstStrided diagonal(lt, w, w, Eigen::OuterStride<>(h));
      diagonal.triangularView<Eigen::Lower>().transpose().solveInPlace(yt);
    }
    else
    {
      ConstStrided(lt, w, w, Eigen::OuterStride<>(h)).triangularView<Eigen::Upper>().solveInPlace(yt);
    }
  }
  Eigen::MatrixXd x(y.rows(), y.cols());
  for (int k = 0; k < in.Size; ++k)
  {
    x.row(in.Perm[k]) = y.row(k);
  }
  b.swap(x);
}

void SupernodalLU::Solve(Eigen::MatrixXd& b) const
{
  if (b.cols() == 0 || b.rows() == 0)
  {
    return; // nothing to solve (Eigen's triangular solves would bind a reference to no data)
  }
  SolveLower(b);
  SolveUpper(b);
}

} // namespace beltrami
