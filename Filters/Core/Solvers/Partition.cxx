#include "Solvers/Partition.h"

#include <mpi.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <type_traits>

namespace beltrami
{

/// Who sends what to whom in UpdateGhosts: per process, the owned rows it
/// wants (sent) and the ghost rows it fills (received), grouped by process.
struct Partition::Exchange
{
  MPI_Comm Comm = MPI_COMM_NULL;
  std::vector<int> SendCounts, SendOffsets, ReceiveCounts, ReceiveOffsets;
  std::vector<Index> SendRows, ReceiveRows;
};

namespace
{

std::vector<int> OffsetsOf(const std::vector<int>& counts)
{
  std::vector<int> offsets(counts.size(), 0);
  std::partial_sum(counts.begin(), counts.end() - 1, offsets.begin() + 1);
  return offsets;
}

/// MPI_Alltoallv of `columns` values per row with the row counts given.
template <typename T>
void AllToAll(MPI_Comm comm, const std::vector<T>& send, const std::vector<int>& sendCounts, std::vector<T>& receive,
  const std::vector<int>& receiveCounts, int columns)
{
  std::vector<int> sc(sendCounts), rc(receiveCounts);
  for (int& c : sc)
  {
    c *= columns;
  }
  for (int& c : rc)
  {
    c *= columns;
  }
  const std::vector<int> so = OffsetsOf(sc), ro = OffsetsOf(rc);
  receive.resize(static_cast<std::size_t>(ro.back() + rc.back()));
  const MPI_Datatype type = sizeof(T) == 8 ? (std::is_integral_v<T> ? MPI_INT64_T : MPI_DOUBLE) : MPI_INT32_T;
  MPI_Alltoallv(send.data(), sc.data(), so.data(), type, receive.data(), rc.data(), ro.data(), type, comm);
}

} // namespace

Partition::Partition(const void* communicator, Index rows, const int* ownerRank, const Index* ownerRow)
  : Plan(std::make_unique<Exchange>())
{
  Exchange& x = *Plan;
  x.Comm = *static_cast<const MPI_Comm*>(communicator);
  MPI_Comm_rank(x.Comm, &RankId);
  MPI_Comm_size(x.Comm, &Processes);
  const int P = Processes;
  Owned.assign(rows, 0);
  Global.assign(rows, -1);
  int bad = 0;
  std::vector<Index> ordinal(rows, 0);
  for (Index i = 0; i < rows; ++i)
  {
    Owned[i] = ownerRank[i] == RankId && ownerRow[i] == i;
    bad |= ownerRank[i] == RankId && ownerRow[i] != i;
    bad |= ownerRank[i] < 0 || ownerRank[i] >= P;
    ordinal[i] = OwnedCount;
    OwnedCount += Owned[i];
  }
  const std::int64_t owned = OwnedCount;
  MPI_Exscan(&owned, &First, 1, MPI_INT64_T, MPI_SUM, x.Comm);
  First = RankId == 0 ? 0 : First;
  MPI_Allreduce(&owned, &Total, 1, MPI_INT64_T, MPI_SUM, x.Comm);
  for (Index i = 0; i < rows; ++i)
  {
    Global[i] = Owned[i] ? First + ordinal[i] : -1;
  }
  // The ghosts, grouped by owner: each owner learns which of its rows it
  // sends to whom, and answers with their global numbers.
  x.ReceiveCounts.assign(P, 0);
  for (Index i = 0; i < rows && !bad; ++i) // (a bad owner rank is no index)
  {
    x.ReceiveCounts[ownerRank[i]] += !Owned[i];
  }
  x.ReceiveOffsets = OffsetsOf(x.ReceiveCounts);
  x.ReceiveRows.resize(static_cast<std::size_t>(x.ReceiveOffsets.back() + x.ReceiveCounts.back()));
  std::vector<Index> wanted(x.ReceiveRows.size());
  std::vector<int> fill(x.ReceiveOffsets);
  for (Index i = 0; i < rows && !bad; ++i)
  {
    if (!Owned[i])
    {
      const int at = fill[ownerRank[i]]++;
      x.ReceiveRows[at] = i;
      wanted[at] = ownerRow[i];
    }
  }
  x.SendCounts.assign(P, 0);
  MPI_Alltoall(x.ReceiveCounts.data(), 1, MPI_INT, x.SendCounts.data(), 1, MPI_INT, x.Comm);
  x.SendOffsets = OffsetsOf(x.SendCounts);
  AllToAll(x.Comm, wanted, x.ReceiveCounts, x.SendRows, x.SendCounts, 1);
  std::vector<std::int64_t> answer(x.SendRows.size()), globals;
  for (std::size_t k = 0; k < answer.size(); ++k)
  {
    const Index r = x.SendRows[k];
    const bool mine = r >= 0 && r < rows && Owned[r];
    bad |= !mine;
    answer[k] = mine ? Global[r] : -1;
  }
  AllToAll(x.Comm, answer, x.SendCounts, globals, x.ReceiveCounts, 1);
  for (std::size_t k = 0; k < globals.size(); ++k)
  {
    Global[x.ReceiveRows[k]] = globals[k];
    bad |= globals[k] < 0;
  }
  int anyBad = 0;
  MPI_Allreduce(&bad, &anyBad, 1, MPI_INT, MPI_MAX, x.Comm);
  if (anyBad)
  {
    throw std::runtime_error("Partition: a row's owner does not own it (inconsistent ownership of the pieces' points)");
  }
}

Partition::~Partition() = default;

const void* Partition::Communicator() const
{
  return &Plan->Comm;
}

std::int64_t Partition::SentPerUpdate() const
{
  return static_cast<std::int64_t>(Plan->SendRows.size());
}

void Partition::UpdateGhosts(double* values, int columns) const
{
  const Exchange& x = *Plan;
  std::vector<double> send(x.SendRows.size() * columns), receive;
  for (std::size_t k = 0; k < x.SendRows.size(); ++k)
  {
    std::copy_n(values + static_cast<std::size_t>(x.SendRows[k]) * columns, columns, send.data() + k * columns);
  }
  AllToAll(x.Comm, send, x.SendCounts, receive, x.ReceiveCounts, columns);
  for (std::size_t k = 0; k < x.ReceiveRows.size(); ++k)
  {
    std::copy_n(receive.data() + k * columns, columns, values + static_cast<std::size_t>(x.ReceiveRows[k]) * columns);
  }
}

void Partition::Sum(double* values, int count) const
{
  MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_SUM, Plan->Comm);
}

void Partition::Max(double* values, int count) const
{
  MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_MAX, Plan->Comm);
}

std::vector<double> Partition::AllGather(const std::vector<double>& values) const
{
  std::vector<int> counts(static_cast<std::size_t>(Processes));
  const int mine = static_cast<int>(values.size());
  MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, Plan->Comm);
  const std::vector<int> offsets = OffsetsOf(counts);
  std::vector<double> all(static_cast<std::size_t>(offsets.back() + counts.back()));
  MPI_Allgatherv(values.data(), mine, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, Plan->Comm);
  return all;
}

std::vector<double> Partition::GatherOnFirst(const std::vector<double>& values) const
{
  std::vector<int> counts(static_cast<std::size_t>(Processes));
  const int mine = static_cast<int>(values.size());
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, Plan->Comm);
  const std::vector<int> offsets = OffsetsOf(counts);
  std::vector<double> all(RankId == 0 ? static_cast<std::size_t>(offsets.back() + counts.back()) : 0);
  MPI_Gatherv(values.data(), mine, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, 0, Plan->Comm);
  return all;
}

double Partition::NthSmallest(const std::vector<double>& values, std::int64_t k) const
{
  // Non-negative doubles order as their bit patterns: the pattern of the
  // answer is chosen 8 bits at a time, from one sum of 256 counts over the
  // processes each (8 sums, whatever the count).
  std::vector<std::uint64_t> keys(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    const double v = values[i] + 0.0; // -0 as +0
    std::memcpy(&keys[i], &v, sizeof v);
  }
  std::uint64_t prefix = 0;
  std::vector<double> counts(256);
  for (int shift = 56; shift >= 0; shift -= 8)
  {
    const std::uint64_t known = shift == 56 ? 0 : ~std::uint64_t(0) << (shift + 8);
    std::fill(counts.begin(), counts.end(), 0.0);
    for (const std::uint64_t key : keys)
    {
      if ((key & known) == prefix)
      {
        counts[(key >> shift) & 255] += 1.0;
      }
    }
    Sum(counts.data(), 256);
    std::uint64_t digit = 0;
    while (digit < 255 && static_cast<double>(k) >= counts[digit])
    {
      k -= static_cast<std::int64_t>(counts[digit]);
      ++digit;
    }
    prefix |= digit << shift;
  }
  double answer;
  std::memcpy(&answer, &prefix, sizeof answer);
  return answer;
}

} // namespace beltrami
