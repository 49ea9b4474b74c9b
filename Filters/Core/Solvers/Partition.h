// Beltrami core: the rows of a system split over MPI processes (the points
// of a surface split over the ranks of pvbatch or pvserver).  Each process
// owns some of its local rows and holds copies (ghosts) of rows that other
// processes own: the 1-ring neighbours of its owned rows, so that its owned
// rows of a Laplacian can be assembled and applied locally.  Owned rows get
// consecutive global numbers per process (process p's first row after those
// of processes 0..p-1).  The solvers sum their inner products over the owned
// rows of all processes (Sum) and refresh the ghosts from their owners
// before each product (UpdateGhosts), so a distributed solve is the serial
// one up to the order of the sums.  No process ever holds the whole system.
//
// Every method but the accessors is collective: all processes of the
// communicator call it, in the same order.  The only file besides
// AlgebraicMultigrid.cxx that sees MPI.
#pragma once

#include "Support/Parallel.h"

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace beltrami
{

/// What a Partition throws, on every process, when some process names a
/// row (or item) that its owner does not hold: the pieces do not hold the
/// stars they should (e.g. points of one input counted as one point where
/// pieces meet but as several within a piece).
class InconsistentOwnership : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

class Partition
{
public:
  /// `communicator` points to an MPI_Comm (MPI initialised by the caller);
  /// local row i is owned by process ownerRank[i], where it is local row
  /// ownerRow[i] (for an owned row: ownerRank[i] = this process, ownerRow[i]
  /// = i).  Throws InconsistentOwnership, on every process, when some
  /// process names a row that its owner does not own.
  Partition(const void* communicator, Index rows, const int* ownerRank, const Index* ownerRow);
  /// The partition of `count` items over the same processes, each item
  /// named by `arity` rows of `rows` (ends[arity * k + m]: local rows; e.g.
  /// the edges or triangles of a surface whose vertices `rows` splits) and
  /// owned by the owner of its row with the lowest global number, which
  /// must hold it too (it holds the whole star of that row: CountsEdge,
  /// CountsTriangle).  Every process must list each item it holds once.
  /// Throws InconsistentOwnership, on every process, when an owner does not
  /// hold an item that another process names.
  static std::unique_ptr<Partition> OfItems(const Partition& rows, Index count, int arity, const Index* ends);
  ~Partition();
  Partition(const Partition&) = delete;
  Partition& operator=(const Partition&) = delete;

  Index Rows() const { return static_cast<Index>(Owned.size()); }
  bool IsOwned(Index i) const { return Owned[i] != 0; }
  /// The global row of local row i (owned or ghost).
  std::int64_t GlobalRow(Index i) const { return Global[i]; }
  std::int64_t FirstRow() const { return First; }
  Index OwnedRows() const { return OwnedCount; }
  std::int64_t TotalRows() const { return Total; }
  int Rank() const { return RankId; }
  int Size() const { return Processes; }
  /// Whether this process counts the edge (a, b) of local rows in a sum
  /// over the edges of a mesh: each edge once, at the owner of its end with
  /// the lower global row (which holds the whole star of that end, so the
  /// edge too).
  bool CountsEdge(Index a, Index b) const { return IsOwned(Global[a] < Global[b] ? a : b); }
  /// The same for a triangle (a, b, c): counted once, at the owner of its
  /// corner with the lowest global row.
  bool CountsTriangle(Index a, Index b, Index c) const
  {
    const Index low = Global[a] < Global[b] ? a : b;
    return IsOwned(Global[low] < Global[c] ? low : c);
  }
  /// The MPI_Comm (a pointer to it) the rows are split over.
  const void* Communicator() const;
  /// Values this process sends per column in one UpdateGhosts (its owned
  /// rows that are ghosts elsewhere, counted once per process holding them).
  std::int64_t SentPerUpdate() const;

  /// The ghost rows of `values` (`columns` interleaved per row) set to their
  /// owners' values.
  void UpdateGhosts(double* values, int columns) const;
  template <typename T, class Allocator>
  void UpdateGhosts(std::vector<T, Allocator>& values) const
  {
    std::vector<double> v(values.begin(), values.end());
    UpdateGhosts(v.data(), 1);
    std::copy(v.begin(), v.end(), values.begin());
  }
  /// The reverse of UpdateGhosts: each owned row of `values` gets the values
  /// of its ghosts on the other processes added (an assembly whose terms
  /// are computed where they are held: a term known on one process, 0 on
  /// the others, reaches the owner); the ghost rows are left as they are.
  void SumToOwners(double* values, int columns) const;
  /// values[k] replaced by its sum (or largest value) over the processes.
  void Sum(double* values, int count) const;
  void Max(double* values, int count) const;
  double Sum(double value) const
  {
    Sum(&value, 1);
    return value;
  }
  double Max(double value) const
  {
    Max(&value, 1);
    return value;
  }
  /// The values of every process, concatenated in the order of the ranks
  /// (the same on every process): for data much smaller than the rows,
  /// e.g. the boundary of a surface.
  std::vector<double> AllGather(const std::vector<double>& values) const;
  /// The same on process 0 only (the others get nothing): for results that
  /// one process finishes, e.g. the segments of a line drawing it chains.
  std::vector<double> GatherOnFirst(const std::vector<double>& values) const;
  /// The k-th smallest (0-based) of the values of all processes together,
  /// exactly (what std::nth_element gives on all of them); the values must
  /// not be negative, k below their total count.
  double NthSmallest(const std::vector<double>& values, std::int64_t k) const;

private:
  struct Exchange;
  std::unique_ptr<Exchange> Plan;
  std::vector<std::uint8_t> Owned;
  std::vector<std::int64_t> Global;
  std::int64_t First = 0, Total = 0;
  Index OwnedCount = 0;
  std::vector<int> Owners; ///< per local row, its owner's rank
  int RankId = 0, Processes = 1;
};

} // namespace beltrami
