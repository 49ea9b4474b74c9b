#include "Solvers/Partition.h"

#include <mpi.h>

#include <algorithm>
#include <cstring>
#include <array>
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
  Owners.assign(ownerRank, ownerRank + rows);
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
    throw InconsistentOwnership("Partition: a row's owner does not own it (inconsistent ownership of the pieces' points)");
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

namespace
{

/// The values of rows `from` (grouped by process, `fromCounts`) sent to the
/// processes, which set (or, with `add`, add to) their rows `to` (grouped
/// by the sending process, `toCounts`).
void Send(MPI_Comm comm, double* values, int columns, const std::vector<Index>& from,
  const std::vector<int>& fromCounts, const std::vector<Index>& to, const std::vector<int>& toCounts, bool add)
{
  std::vector<double> send(from.size() * columns), receive;
  for (std::size_t k = 0; k < from.size(); ++k)
  {
    std::copy_n(values + static_cast<std::size_t>(from[k]) * columns, columns, send.data() + k * columns);
  }
  AllToAll(comm, send, fromCounts, receive, toCounts, columns);
  for (std::size_t k = 0; k < to.size(); ++k)
  {
    double* row = values + static_cast<std::size_t>(to[k]) * columns;
    for (int c = 0; c < columns; ++c)
    {
      row[c] = add ? row[c] + receive[k * columns + c] : receive[k * columns + c];
    }
  }
}

} // namespace

void Partition::UpdateGhosts(double* values, int columns) const
{
  const Exchange& x = *Plan;
  Send(x.Comm, values, columns, x.SendRows, x.SendCounts, x.ReceiveRows, x.ReceiveCounts, false);
}

void Partition::SumToOwners(double* values, int columns) const
{
  const Exchange& x = *Plan;
  Send(x.Comm, values, columns, x.ReceiveRows, x.ReceiveCounts, x.SendRows, x.SendCounts, true);
}

std::unique_ptr<Partition> Partition::OfItems(const Partition& rows, Index count, int arity, const Index* ends)
{
  // An item's key: its rows' global numbers, ascending.  The owner of the
  // lowest is asked, per item that another process holds, for its local
  // number there.
  if (arity < 1 || arity > 3)
  {
    throw std::invalid_argument("Partition::OfItems: items of 1 to 3 rows");
  }
  const int P = rows.Processes;
  const MPI_Comm comm = rows.Plan->Comm;
  std::vector<int> ownerRank(count);
  std::vector<Index> ownerRow(count, -1);
  std::vector<std::int64_t> keys(static_cast<std::size_t>(count) * arity);
  using Key = std::array<std::int64_t, 4>; // (arity at most 3, padded with -1), the local item last
  std::vector<Key> mine;
  const auto keyOf = [arity](const std::int64_t* key, std::int64_t item) {
    Key k{ -1, -1, -1, item };
    std::copy_n(key, arity, k.begin());
    return k;
  };
  std::vector<int> askCounts(P, 0);
  for (Index k = 0; k < count; ++k)
  {
    std::int64_t* key = &keys[static_cast<std::size_t>(k) * arity];
    for (int m = 0; m < arity; ++m)
    {
      key[m] = rows.Global[ends[static_cast<std::size_t>(k) * arity + m]];
    }
    std::sort(key, key + arity);
    const Index low = *std::min_element(ends + static_cast<std::size_t>(k) * arity,
      ends + static_cast<std::size_t>(k + 1) * arity, [&rows](Index a, Index b) { return rows.Global[a] < rows.Global[b]; });
    ownerRank[k] = rows.Owners[low];
    if (ownerRank[k] == rows.RankId)
    {
      ownerRow[k] = k;
      mine.push_back(keyOf(key, k));
    }
    else
    {
      ++askCounts[ownerRank[k]];
    }
  }
  std::vector<int> offsets = OffsetsOf(askCounts), fill(offsets), answerCounts(P, 0);
  std::vector<std::int64_t> asked(static_cast<std::size_t>(offsets.back() + askCounts.back()) * arity), received;
  std::vector<Index> askers(asked.size() / arity);
  for (Index k = 0; k < count; ++k)
  {
    if (ownerRank[k] != rows.RankId)
    {
      const int at = fill[ownerRank[k]]++;
      std::copy_n(&keys[static_cast<std::size_t>(k) * arity], arity, &asked[static_cast<std::size_t>(at) * arity]);
      askers[at] = k;
    }
  }
  std::sort(mine.begin(), mine.end());
  MPI_Alltoall(askCounts.data(), 1, MPI_INT, answerCounts.data(), 1, MPI_INT, comm);
  AllToAll(comm, asked, askCounts, received, answerCounts, arity);
  std::vector<Index> answers(received.size() / arity), rowsBack;
  for (std::size_t a = 0; a < answers.size(); ++a)
  {
    const Key key = keyOf(&received[a * arity], -1);
    const auto found = std::lower_bound(mine.begin(), mine.end(), key);
    const bool held = found != mine.end() && std::equal(key.begin(), key.begin() + 3, found->begin());
    answers[a] = held ? static_cast<Index>((*found)[3]) : -1;
  }
  AllToAll(comm, answers, answerCounts, rowsBack, askCounts, 1);
  for (std::size_t a = 0; a < rowsBack.size(); ++a)
  {
    ownerRow[askers[a]] = rowsBack[a];
  }
  // (A row of -1 makes the constructor throw on every process.)
  return std::make_unique<Partition>(&comm, count, ownerRank.data(), ownerRow.data());
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
