#include "Solvers/AlgebraicMultigrid.h"

#include "Solvers/Partition.h"

#include <mpi.h>

#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <_hypre_parcsr_ls.h>

#include <cmath>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace beltrami
{

namespace
{

/// hypre's state (its error flag, memory bookkeeping) is global: one thread
/// in hypre at a time.
std::mutex& HypreMutex()
{
  static std::mutex m;
  return m;
}

void FinalizeMpi()
{
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized)
  {
    MPI_Finalize();
  }
}

/// MPI initialised (by ParaView or mpirun, or here as a singleton) and hypre.
void EnsureRuntime()
{
  static const bool ready = [] {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized)
    {
      int provided = 0;
      if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_MULTIPLE, &provided) != MPI_SUCCESS)
      {
        return false;
      }
      std::atexit(FinalizeMpi);
    }
    HYPRE_Init();
    return true;
  }();
  if (!ready)
  {
    throw std::runtime_error("AlgebraicMultigrid: MPI could not be initialised");
  }
}

HYPRE_ParVector VectorObject(HYPRE_IJVector v)
{
  void* object = nullptr;
  HYPRE_IJVectorGetObject(v, &object);
  return static_cast<HYPRE_ParVector>(object);
}

double* VectorData(HYPRE_IJVector v)
{
  return hypre_VectorData(hypre_ParVectorLocalVector(static_cast<hypre_ParVector*>(VectorObject(v))));
}

} // namespace

struct AlgebraicMultigrid::Hierarchy
{
  Index Rows = 0;
  std::vector<Index> Owned; ///< distributed: the local rows this process owns, in global order
  HYPRE_IJMatrix Matrix = nullptr;
  HYPRE_IJVector B = nullptr, X = nullptr;
  HYPRE_Solver Solver = nullptr;
  HYPRE_ParCSRMatrix ParMatrix() const
  {
    void* object = nullptr;
    HYPRE_IJMatrixGetObject(Matrix, &object);
    return static_cast<HYPRE_ParCSRMatrix>(object);
  }
  ~Hierarchy()
  {
    if (Solver)
    {
      HYPRE_BoomerAMGDestroy(Solver);
    }
    if (B)
    {
      HYPRE_IJVectorDestroy(B);
    }
    if (X)
    {
      HYPRE_IJVectorDestroy(X);
    }
    if (Matrix)
    {
      HYPRE_IJMatrixDestroy(Matrix);
    }
  }
};

namespace
{

/// Where the hierarchy lives: this process alone, or the processes of a
/// Partition (its owned rows, numbered globally).
struct Layout
{
  MPI_Comm Comm = MPI_COMM_SELF;
  std::int64_t First = 0;
  const Partition* Split = nullptr;
  std::int64_t Global(Index i) const { return Split ? Split->GlobalRow(i) : i; }
};

/// The IJ matrix of D + t K on the free rows (`owned`: the local rows of
/// this process), identity rows elsewhere; rows are assembled in blocks to
/// bound the staging memory.
HYPRE_IJMatrix AssembleMatrix(const Layout& at, const std::vector<Index>& owned, const std::int64_t* offsets,
  const Index* neighbors, const double* weights, const double* diagonal, const double* shift, double factor,
  const std::uint8_t* fixed)
{
  const auto isFree = [&](Index i) { return !fixed || !fixed[i]; };
  const Index n = static_cast<Index>(owned.size());
  HYPRE_IJMatrix m = nullptr;
  HYPRE_IJMatrixCreate(at.Comm, at.First, at.First + n - 1, at.First, at.First + n - 1, &m);
  HYPRE_IJMatrixSetObjectType(m, HYPRE_PARCSR);
  std::vector<HYPRE_Int> sizes(static_cast<std::size_t>(n));
  for (Index k = 0; k < n; ++k)
  {
    const Index i = owned[k];
    sizes[k] = isFree(i) ? static_cast<HYPRE_Int>(offsets[i + 1] - offsets[i] + 1) : 1;
  }
  HYPRE_IJMatrixSetRowSizes(m, sizes.data());
  HYPRE_IJMatrixInitialize(m);
  std::vector<HYPRE_BigInt> rows, cols;
  std::vector<HYPRE_Int> counts;
  std::vector<double> values;
  const Index block = 65536;
  for (Index first = 0; first < n; first += block)
  {
    rows.clear();
    cols.clear();
    counts.clear();
    values.clear();
    for (Index k = first; k < std::min<Index>(n, first + block); ++k)
    {
      const Index i = owned[k];
      rows.push_back(at.Global(i));
      cols.push_back(at.Global(i));
      const bool free = isFree(i);
      values.push_back(free ? (shift ? shift[i] : 0.0) + factor * diagonal[i] : 1.0);
      HYPRE_Int count = 1;
      for (std::int64_t k = offsets[i]; free && k < offsets[i + 1]; ++k)
      {
        if (isFree(neighbors[k]))
        {
          cols.push_back(at.Global(neighbors[k]));
          values.push_back(-factor * weights[k]);
          ++count;
        }
      }
      counts.push_back(count);
    }
    HYPRE_IJMatrixSetValues(m, static_cast<HYPRE_Int>(rows.size()), counts.data(), rows.data(), cols.data(),
      values.data());
  }
  HYPRE_IJMatrixAssemble(m);
  return m;
}

HYPRE_IJVector MakeVector(const Layout& at, Index n)
{
  HYPRE_IJVector v = nullptr;
  HYPRE_IJVectorCreate(at.Comm, at.First, at.First + n - 1, &v);
  HYPRE_IJVectorSetObjectType(v, HYPRE_PARCSR);
  HYPRE_IJVectorInitialize(v);
  HYPRE_IJVectorAssemble(v);
  return v;
}

} // namespace

AlgebraicMultigrid::AlgebraicMultigrid(Index rows, const std::int64_t* offsets, const Index* neighbors,
  const double* weights, const double* diagonal, const double* shift, double factor,
  const std::uint8_t* fixed, const Partition* split)
  : H(std::make_unique<Hierarchy>())
{
  if ((rows <= 0 && !split) || (rows > 0 && (!offsets || !neighbors || !weights || !diagonal)))
  {
    throw std::invalid_argument("AlgebraicMultigrid: inconsistent problem");
  }
  EnsureRuntime();
  std::lock_guard<std::mutex> lock(HypreMutex());
  H->Rows = rows;
  Layout at;
  at.Split = split;
  if (split)
  {
    at.Comm = *static_cast<const MPI_Comm*>(split->Communicator());
    at.First = split->FirstRow();
  }
  for (Index i = 0; i < rows; ++i)
  {
    if (!split || split->IsOwned(i))
    {
      H->Owned.push_back(i);
    }
  }
  const Index owned = static_cast<Index>(H->Owned.size());
  H->Matrix = AssembleMatrix(at, H->Owned, offsets, neighbors, weights, diagonal, shift, factor, fixed);
  H->B = MakeVector(at, owned);
  H->X = MakeVector(at, owned);
  HYPRE_BoomerAMGCreate(&H->Solver);
  HYPRE_BoomerAMGSetPrintLevel(H->Solver, 0);
  HYPRE_BoomerAMGSetMaxIter(H->Solver, 1); // one cycle per application
  HYPRE_BoomerAMGSetTol(H->Solver, 0.0);
  // HMIS coarsening with extended+i interpolation truncated to 4 entries
  // (hypre's defaults for unstructured problems, set here so that they do
  // not move with the library's version).  Smoothing by a Chebyshev
  // polynomial of order 2 (the same before and after the coarse
  // correction: the cycle is a symmetric operator, as CG needs): on noisy
  // scans, whose cotangent weights spread over orders of magnitude with a
  // tenth of them negative, it needed 69 iterations where hypre's default
  // l1-Gauss-Seidel needed 331 (Loop-subdivided bunny, 150k rows, default
  // fairing step).  Gaussian elimination on the coarsest level.
  HYPRE_BoomerAMGSetCoarsenType(H->Solver, 10);
  HYPRE_BoomerAMGSetInterpType(H->Solver, 6);
  HYPRE_BoomerAMGSetPMaxElmts(H->Solver, 4);
  HYPRE_BoomerAMGSetStrongThreshold(H->Solver, 0.25);
  HYPRE_BoomerAMGSetCycleRelaxType(H->Solver, 16, 1);
  HYPRE_BoomerAMGSetCycleRelaxType(H->Solver, 16, 2);
  HYPRE_BoomerAMGSetCycleRelaxType(H->Solver, 9, 3);
  HYPRE_BoomerAMGSetChebyOrder(H->Solver, 2);
  HYPRE_BoomerAMGSetup(H->Solver, H->ParMatrix(), VectorObject(H->B), VectorObject(H->X));
}

AlgebraicMultigrid::~AlgebraicMultigrid()
{
  std::lock_guard<std::mutex> lock(HypreMutex());
  H.reset();
}

void AlgebraicMultigrid::Apply(const double* r, double* z, int columns) const
{
  std::lock_guard<std::mutex> lock(HypreMutex());
  const std::vector<Index>& owned = H->Owned;
  const Index n = static_cast<Index>(owned.size());
  double* b = VectorData(H->B);
  double* x = VectorData(H->X);
  if (n < H->Rows)
  {
    std::fill(z, z + static_cast<std::int64_t>(H->Rows) * columns, 0.0); // the ghost rows
  }
  for (int c = 0; c < columns; ++c)
  {
    for (Index k = 0; k < n; ++k)
    {
      b[k] = r[static_cast<std::int64_t>(owned[k]) * columns + c];
      x[k] = 0.0;
    }
    HYPRE_BoomerAMGSolve(H->Solver, H->ParMatrix(), VectorObject(H->B), VectorObject(H->X));
    for (Index k = 0; k < n; ++k)
    {
      z[static_cast<std::int64_t>(owned[k]) * columns + c] = x[k];
    }
  }
}

int AlgebraicMultigrid::Levels() const
{
  return hypre_ParAMGDataNumLevels(reinterpret_cast<hypre_ParAMGData*>(H->Solver));
}

double AlgebraicMultigrid::OperatorComplexity() const
{
  hypre_ParAMGData* data = reinterpret_cast<hypre_ParAMGData*>(H->Solver);
  const auto nonZeros = [](hypre_ParCSRMatrix* a) {
    return static_cast<double>(hypre_CSRMatrixNumNonzeros(hypre_ParCSRMatrixDiag(a))) +
      static_cast<double>(hypre_CSRMatrixNumNonzeros(hypre_ParCSRMatrixOffd(a)));
  };
  double total = 0.0;
  for (int l = 0; l < Levels(); ++l)
  {
    total += nonZeros(hypre_ParAMGDataAArray(data)[l]);
  }
  return total / nonZeros(hypre_ParAMGDataAArray(data)[0]);
}

} // namespace beltrami
