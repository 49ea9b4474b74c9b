#include "Flows/FairingInvariants.h"

#include "Mesh/MeshMeasures.h"

#include <cmath>
#include <functional>
#include <utility>

namespace beltrami::detail
{

namespace
{

void Rescale(double* x, Index n, const Vec3& center, double s)
{
  for (Index i = 0; i < n; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      x[3 * i + c] = center[c] + s * (x[3 * i + c] - center[c]);
    }
  }
}

/// Volume or area with its centroid over the processes of a distributed
/// run: each process' share of the counted triangles, the volumes from one
/// origin (the vertex centroid of the owned points of all processes).
double MeasureDistributed(const InvariantState& s, const MeshTopology& topo, const double* x, int threads,
  Vec3* center)
{
  const Vec3 origin = MeanPoint(topo, x, s.Split, [&](Index i) { return topo.Valence(i) > 0; }).first;
  Vec3 share;
  const double amount = s.Kind == FairingInvariant::Volume
    ? VolumeAndCentroid(*s.Counted, x, threads, &share, &origin)
    : AreaAndCentroid(*s.Counted, x, threads, &share);
  double total[4] = { amount, amount * share[0], amount * share[1], amount * share[2] };
  s.Split->Sum(total, 4);
  if (center)
  {
    *center = total[0] != 0.0 ? Vec3(Vec3(total[1], total[2], total[3]) / total[0]) : origin;
  }
  return total[0];
}

} // namespace

std::pair<Vec3, double> MeanPoint(
  const MeshTopology& topo, const double* x, const Partition* split, const std::function<bool(Index)>& use)
{
  double sums[4] = { 0.0, 0.0, 0.0, 0.0 };
  for (Index i = 0; i < topo.NumberOfVertices(); ++i)
  {
    if ((!split || split->IsOwned(i)) && use(i) && Point(x, i).allFinite())
    {
      sums[0] += 1.0;
      for (int c = 0; c < 3; ++c)
      {
        sums[1 + c] += x[3 * i + c];
      }
    }
  }
  if (split)
  {
    split->Sum(sums, 4);
  }
  return { sums[0] > 0.0 ? Vec3(Vec3(sums[1], sums[2], sums[3]) / sums[0]) : Vec3::Zero(), sums[0] };
}

double MeasureInvariant(const InvariantState& s, const MeshTopology& topo, const double* x, int threads,
  Vec3* center)
{
  if (s.Split && (s.Kind == FairingInvariant::Volume || s.Kind == FairingInvariant::Area))
  {
    return MeasureDistributed(s, topo, x, threads, center);
  }
  if (s.Split && s.Kind == FairingInvariant::HeightFieldVolume)
  {
    return s.Split->Sum(HeightVolume(*s.Counted, x, s.PlaneOrigin, s.PlaneNormal, threads));
  }
  if (s.Split && s.Kind == FairingInvariant::RevolutionVolume)
  {
    return s.Split->Sum(RevolutionVolume(*s.Counted, x, s.PlaneOrigin, s.PlaneNormal, threads));
  }
  switch (s.Kind)
  {
    case FairingInvariant::Volume:
      return VolumeAndCentroid(topo, x, threads, center);
    case FairingInvariant::Area:
      return AreaAndCentroid(topo, x, threads, center);
    case FairingInvariant::HeightFieldVolume:
      return HeightVolume(topo, x, s.PlaneOrigin, s.PlaneNormal, threads);
    case FairingInvariant::RevolutionVolume:
      return RevolutionVolume(topo, x, s.PlaneOrigin, s.PlaneNormal, threads);
    default:
      return 0.0;
  }
}

double RestoreInvariant(const InvariantState& s, const MeshTopology& topo, double* x, int threads, bool measure)
{
  Vec3 center;
  const double now = MeasureInvariant(s, topo, x, threads, &center);
  const Index n = topo.NumberOfVertices();
  if (!(now != 0.0) || !std::isfinite(now) || now * s.Initial <= 0.0)
  {
    return now;
  }
  switch (s.Kind)
  {
    case FairingInvariant::Volume:
      Rescale(x, n, center, std::cbrt(s.Initial / now));
      break;
    case FairingInvariant::Area:
      Rescale(x, n, center, std::sqrt(s.Initial / now));
      break;
    case FairingInvariant::HeightFieldVolume:
    {
      const double factor = s.Initial / now; // the volume is linear in the heights
      for (Index i = 0; i < n; ++i)
      {
        const double h = (Point(x, i) - s.PlaneOrigin).dot(s.PlaneNormal);
        for (int c = 0; c < 3; ++c)
        {
          x[3 * i + c] += (factor - 1.0) * h * s.PlaneNormal[c];
        }
      }
      break;
    }
    case FairingInvariant::RevolutionVolume:
    {
      const double factor = std::sqrt(s.Initial / now); // the volume is quadratic in the radii
      for (Index i = 0; i < n; ++i)
      {
        const Vec3 p = Point(x, i) - s.PlaneOrigin;
        const Vec3 radial = p - p.dot(s.PlaneNormal) * s.PlaneNormal;
        for (int c = 0; c < 3; ++c)
        {
          x[3 * i + c] += (factor - 1.0) * radial[c];
        }
      }
      break;
    }
    default:
      break;
  }
  return measure ? MeasureInvariant(s, topo, x, threads, &center) : s.Initial;
}

} // namespace beltrami::detail
