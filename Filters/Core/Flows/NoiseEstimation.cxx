#include "Flows/NoiseEstimation.h"

#include "Mesh/Geometry.h"
#include "Mesh/RingGeometry.h"
#include "Support/Parallel.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>
#include <cstring>
#include <vector>

namespace beltrami
{

namespace
{

/// At most about this many samples are used, all components together (rows,
/// planes or vertices taken at a regular stride beyond): medians of the kept
/// halves of 2^18 samples have a relative standard error of about
/// 1.17 / sqrt(2^17) = 0.3%, far below the estimator's bias on real data,
/// and an image of a megapixel in colour spent 45 ms (half its flow's
/// set-up) selecting from all.
constexpr std::int64_t SampleBudget = std::int64_t(1) << 18;

/// The stride that keeps `count` samples of `components` each within the
/// budget.
std::int64_t StrideFor(double count, int components)
{
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(count * components / SampleBudget)));
}

/// Responses and gradients of the samples of one component.
struct Samples
{
  std::vector<double> Response; ///< |high-pass response| / its noise gain
  std::vector<double> Gradient; ///< any measure that grows with the gradient
  /// 1 at or next to flat data (RobustDeviation): where the sample equals
  /// more than half of its face (graph) neighbours, or another voxel of its
  /// window equals all its face neighbours in the window but the centre
  /// (images: the 4 face neighbours of the sample, equal to the 2 beside
  /// them).  Inside the window: the same flags on a piece of a grid split
  /// over processes (one ring around it) as on the whole grid.
  std::vector<std::uint8_t> Flat;
};

/// The samples of `rows` sampled rows of `width` each, in parallel and in
/// the order of a serial loop: sample(row, x, response, gradient, flat).
template <typename Sample>
void SampleRows(std::int64_t rows, std::int64_t width, int numThreads, Samples& s, Sample&& sample)
{
  s.Response.resize(static_cast<std::size_t>(rows * width));
  s.Gradient.resize(s.Response.size());
  s.Flat.resize(s.Response.size());
  ParallelFor(rows, numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t r = begin; r < end; ++r)
    {
      for (std::int64_t x = 0; x < width; ++x)
      {
        const std::int64_t k = r * width + x;
        sample(r, x, s.Response[k], s.Gradient[k], s.Flat[k]);
      }
    }
  }, {}, 0, 1);
}

/// The k-th smallest of `values` (0-based; of all processes' with `split`).
double NthSmallest(std::vector<double>& values, std::int64_t k, const Partition* split)
{
  if (split)
  {
    return split->NthSmallest(values, k);
  }
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

/// A count over all processes (`split`) or of this one.
std::int64_t Total(std::size_t count, const Partition* split)
{
  return static_cast<std::int64_t>(split ? split->Sum(static_cast<double>(count)) : count);
}

/// The median response over the half of the samples with the smallest
/// gradient, as a standard deviation (0 without samples).
double LowGradientDeviation(const Samples& s, const Partition* split)
{
  const std::int64_t count = Total(s.Response.size(), split);
  if (count == 0)
  {
    return 0.0;
  }
  std::vector<double> sorted = s.Gradient;
  const double half = NthSmallest(sorted, count / 2, split);
  std::vector<double> low;
  low.reserve(s.Response.size() / 2 + 1);
  for (std::size_t k = 0; k < s.Response.size(); ++k)
  {
    if (s.Gradient[k] <= half) // ties: all of them
    {
      low.push_back(s.Response[k]);
    }
  }
  return NthSmallest(low, Total(low.size(), split) / 2, split) / 0.6744897501960817;
}

/// The samples of `s` that are not next to flat data.
Samples AwayFromFlat(const Samples& s)
{
  Samples kept;
  for (std::size_t k = 0; k < s.Response.size(); ++k)
  {
    if (!s.Flat[k])
    {
      kept.Response.push_back(s.Response[k]);
      kept.Gradient.push_back(s.Gradient[k]);
    }
  }
  return kept;
}

/// The noise of the samples (LowGradientDeviation).  split: the samples of
/// all processes together (collective).
/// Flat data (a masked or padded background, clipped values, clean
/// piecewise-constant data) carry no noise to measure, but from a quarter
/// of the samples on they made the estimate 0 (the defaults then left, say,
/// a skull-stripped MRI volume or a photograph with a black border as it
/// was), and the windows next to them see less noise, or an edge.  Where
/// samples are next to flat data (Samples::Flat), the estimate is that of
/// the others, if they are at least 1% of all (and 64): clean
/// piecewise-constant data have next to none (nearly every window there
/// holds a voxel equal to its neighbours), and keep the estimate of all
/// samples, as before (0 where the flat ones are a quarter or more).
/// Noise in floating point leaves no equal values, so such data get the
/// same estimate as before to the bit; quantized to 8 bits (noise of 5
/// levels), about 2% of an image's samples and 0.5% of a volume's are left
/// out by chance.
double RobustDeviation(const Samples& s, const Partition* split)
{
  const double all = LowGradientDeviation(s, split);
  const std::int64_t count = Total(s.Response.size(), split);
  const Samples away = AwayFromFlat(s);
  const std::int64_t kept = Total(away.Response.size(), split);
  if (kept == count || kept < std::max<std::int64_t>(64, count / 100))
  {
    return all;
  }
  return LowGradientDeviation(away, split);
}

/// The mean over the components of one component's estimate.
template <typename Component>
double MeanOverComponents(int components, Component&& component, const Partition* split = nullptr)
{
  double sum = 0.0;
  for (int c = 0; c < components; ++c)
  {
    Samples s;
    component(c, s);
    sum += RobustDeviation(s, split);
  }
  return sum / components;
}

} // namespace

namespace
{

/// The samples of a piece of a split grid (GridPiece): the samples it owns
/// inside the whole grid (a margin of 1), on the rows (y, z) the whole grid
/// samples at `stride` (its interior rows numbered y fastest), in any order
/// (the estimate takes order statistics); sample(x, y, z, response,
/// gradient, flat) at local coordinates.
template <typename Sample>
void SamplePiece(const GridPiece& piece, std::int64_t w, std::int64_t h, std::int64_t d, std::int64_t stride,
  Samples& s, Sample&& sample)
{
  const std::int64_t* whole = piece.Whole;
  const std::int64_t* origin = piece.Origin;
  const bool volume = whole[2] > 1;
  const auto inside = [&](std::int64_t local, int a) {
    const std::int64_t g = local + origin[a];
    return g >= 1 && g <= whole[a] - 2;
  };
  for (std::int64_t z = 0; z < d; ++z)
  {
    for (std::int64_t y = 0; y < h; ++y)
    {
      const std::int64_t row = (y + origin[1] - 1) + (volume ? (z + origin[2] - 1) * (whole[1] - 2) : 0);
      if (!inside(y, 1) || (volume && !inside(z, 2)) || row % stride != 0)
      {
        continue;
      }
      for (std::int64_t x = 0; x < w; ++x)
      {
        if (inside(x, 0) && piece.Split->IsOwned(static_cast<Index>((z * h + y) * w + x)))
        {
          double response = 0.0, gradient = 0.0;
          std::uint8_t flat = 0;
          sample(x, y, z, response, gradient, flat);
          s.Response.push_back(response);
          s.Gradient.push_back(gradient);
          s.Flat.push_back(flat);
        }
      }
    }
  }
}

} // namespace

double EstimateImageNoise(
  const PixelGrid& grid, int components, const double* values, int numThreads, const GridPiece* piece)
{
  const bool split = piece && piece->Split; // (every process joins, an empty piece too)
  const std::int64_t W = split ? piece->Whole[0] : grid.Width, H = split ? piece->Whole[1] : grid.Height;
  if (W < 3 || H < 3 || components < 1 || (!values && !split))
  {
    return 0.0;
  }
  const Index w = grid.Width, h = grid.Height;
  const std::int64_t stride = StrideFor(static_cast<double>(W - 2) * (H - 2), components); // rows
  return MeanOverComponents(components, [&](int comp, Samples& s) {
    const auto at = [&](Index x, Index y) {
      return values[(static_cast<std::size_t>(y) * w + x) * components + comp];
    };
    const auto sample = [&](Index x, Index y, double& response, double& gradient, std::uint8_t& flat) {
      const double a = at(x - 1, y - 1), b = at(x, y - 1), c = at(x + 1, y - 1);
      const double d = at(x - 1, y), e = at(x, y), f = at(x + 1, y);
      const double g = at(x - 1, y + 1), i = at(x, y + 1), j = at(x + 1, y + 1);
      response = std::abs(a - 2 * b + c - 2 * d + 4 * e - 2 * f + g - 2 * i + j) / 6.0;
      const double gx = (c + 2 * f + j) - (a + 2 * d + g), gy = (g + 2 * i + j) - (a + 2 * b + c);
      gradient = gx * gx + gy * gy;
      flat = (b == e) + (d == e) + (f == e) + (i == e) > 2 || (a == b && b == c) || (g == i && i == j) ||
        (a == d && d == g) || (c == f && f == j);
    };
    if (split)
    {
      SamplePiece(*piece, w, h, 1, stride, s,
        [&](std::int64_t x, std::int64_t y, std::int64_t, double& response, double& gradient, std::uint8_t& flat) {
          sample(static_cast<Index>(x), static_cast<Index>(y), response, gradient, flat);
        });
      return;
    }
    SampleRows((h - 2 + stride - 1) / stride, w - 2, numThreads, s,
      [&](std::int64_t row, std::int64_t column, double& response, double& gradient, std::uint8_t& flat) {
        sample(static_cast<Index>(1 + column), static_cast<Index>(1 + row * stride), response, gradient, flat);
      });
  }, split ? piece->Split : nullptr);
}

double EstimateVolumeNoise(
  const VoxelGrid& grid, int components, const double* values, int numThreads, const GridPiece* piece)
{
  const bool split = piece && piece->Split; // (every process joins, an empty piece too)
  const std::int64_t W = split ? piece->Whole[0] : grid.Width, H = split ? piece->Whole[1] : grid.Height,
                     D = split ? piece->Whole[2] : grid.Depth;
  if (W < 3 || H < 3 || D < 3 || components < 1 || (!values && !split))
  {
    return 0.0;
  }
  const std::int64_t w = grid.Width, h = grid.Height, d = grid.Depth;
  const double gain = std::sqrt(216.0);
  const double line[3] = { 1.0, -2.0, 1.0 };
  const std::int64_t rows = (H - 2) * (D - 2);
  const std::int64_t stride = StrideFor(static_cast<double>(W - 2) * rows, components); // rows (y, z)
  return MeanOverComponents(components, [&](int comp, Samples& s) {
    const auto at = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
      return values[((z * h + y) * w + x) * components + comp];
    };
    // The window's voxel at (x, y, z) + (dx, dy, dz) equal to all its face
    // neighbours in the window but the centre (4 for a face's or an edge's
    // voxel, 3 for a corner).
    const auto flatInWindow = [&](std::int64_t x, std::int64_t y, std::int64_t z, int dx, int dy, int dz) {
      const int p[3] = { dx, dy, dz };
      const double v = at(x + dx, y + dy, z + dz);
      for (int axis = 0; axis < 3; ++axis)
      {
        for (const int side : { -1, 1 })
        {
          int q[3] = { p[0], p[1], p[2] };
          q[axis] += side;
          if (q[axis] < -1 || q[axis] > 1 || (q[0] == 0 && q[1] == 0 && q[2] == 0))
          {
            continue;
          }
          if (at(x + q[0], y + q[1], z + q[2]) != v)
          {
            return false;
          }
        }
      }
      return true;
    };
    const auto sample = [&](std::int64_t x, std::int64_t y, std::int64_t z, double& response, double& gradient,
                          std::uint8_t& flat) {
      double r = 0.0;
      for (int k = 0; k < 3; ++k)
      {
        for (int j = 0; j < 3; ++j)
        {
          const double c = line[k] * line[j];
          for (int i = 0; i < 3; ++i)
          {
            r += c * line[i] * at(x + i - 1, y + j - 1, z + k - 1);
          }
        }
      }
      const double gx = at(x + 1, y, z) - at(x - 1, y, z), gy = at(x, y + 1, z) - at(x, y - 1, z),
                   gz = at(x, y, z + 1) - at(x, y, z - 1);
      response = std::abs(r) / gain;
      gradient = gx * gx + gy * gy + gz * gz;
      const double e = at(x, y, z);
      flat = (at(x - 1, y, z) == e) + (at(x + 1, y, z) == e) + (at(x, y - 1, z) == e) + (at(x, y + 1, z) == e) +
          (at(x, y, z - 1) == e) + (at(x, y, z + 1) == e) > 3;
      for (int k = 0; k < 27 && !flat; ++k)
      {
        flat = k != 13 && flatInWindow(x, y, z, k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1);
      }
    };
    if (split)
    {
      SamplePiece(*piece, w, h, d, stride, s, sample);
      return;
    }
    SampleRows((rows + stride - 1) / stride, w - 2, numThreads, s,
      [&](std::int64_t sampled, std::int64_t column, double& response, double& gradient, std::uint8_t& flat) {
        const std::int64_t row = sampled * stride;
        sample(1 + column, 1 + row % (h - 2), 1 + row / (h - 2), response, gradient, flat);
      });
  }, split ? piece->Split : nullptr);
}

double EstimateGraphNoise(Index size, const std::int64_t* offsets, const Index* neighbors, const double* points,
  int components, const double* values, const std::uint8_t* skip, const Partition* split)
{
  if (!split && (size <= 0 || !values || !offsets || !neighbors || !points))
  {
    return 0.0; // (a process of a split run joins the sums with no samples)
  }
  if (components < 1)
  {
    return 0.0;
  }
  std::int64_t counted = 0;
  // Rows at a regular stride of the (global) numbering beyond the budget.
  const std::int64_t stride = StrideFor(split ? static_cast<double>(split->TotalRows()) : size, components);
  const auto sampled = [&](Index i) {
    return split ? split->IsOwned(i) && split->GlobalRow(i) % stride == 0 : i % stride == 0;
  };
  const double estimate = MeanOverComponents(components, [&](int comp, Samples& s) {
    for (Index i = 0; i < size; i += split ? 1 : stride)
    {
      const std::int64_t b = offsets[i], e = offsets[i + 1];
      const double n = static_cast<double>(e - b);
      if (!sampled(i) || n < 3 || (skip && skip[i]))
      {
        continue;
      }
      const double value = values[static_cast<std::size_t>(i) * components + comp];
      double mean = 0.0, centre[3] = { 0.0, 0.0, 0.0 };
      int equal = 0; // neighbours with the same value (Samples::Flat)
      for (std::int64_t k = b; k < e; ++k)
      {
        const double neighbour = values[static_cast<std::size_t>(neighbors[k]) * components + comp];
        mean += neighbour;
        equal += neighbour == value;
        for (int a = 0; a < 3; ++a)
        {
          centre[a] += points[3 * static_cast<std::size_t>(neighbors[k]) + a];
        }
      }
      mean /= n;
      double moment[3] = { 0.0, 0.0, 0.0 }, spread = 0.0;
      for (std::int64_t k = b; k < e; ++k)
      {
        const double df = values[static_cast<std::size_t>(neighbors[k]) * components + comp] - mean;
        for (int a = 0; a < 3; ++a)
        {
          const double dx = points[3 * static_cast<std::size_t>(neighbors[k]) + a] - centre[a] / n;
          moment[a] += dx * df;
          spread += dx * dx;
        }
      }
      const double r = value - mean;
      s.Response.push_back(std::abs(r) / std::sqrt(1.0 + 1.0 / n));
      s.Gradient.push_back(
        spread > 0.0 ? (moment[0] * moment[0] + moment[1] * moment[1] + moment[2] * moment[2]) / (spread * spread)
                     : 0.0);
      s.Flat.push_back(2 * equal > e - b);
    }
    counted = static_cast<std::int64_t>(s.Response.size());
  }, split);
  return (split ? split->Sum(static_cast<double>(counted)) : counted) >= 8 ? estimate : 0.0;
}

namespace
{

/// Per edge, the angle (degrees) between the normals of its two triangles
/// (NaN where it has not two, or a triangle has no area).
std::vector<double> DihedralAngles(const MeshTopology& topo, const double* x, int numThreads)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  const auto normal = [&](Index corner) {
    const Index t = corner / 3;
    const Vec3 a = Point(x, topo.CornerVertex(3 * t)), b = Point(x, topo.CornerVertex(3 * t + 1)),
               c = Point(x, topo.CornerVertex(3 * t + 2));
    return Vec3((b - a).cross(c - a));
  };
  std::vector<double> angles(static_cast<std::size_t>(edges.NumberOfEdges()), std::nan(""));
  ParallelFor(edges.NumberOfEdges(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t e = begin; e < end; ++e)
    {
      const Index c0 = edges.OppositeCorners[2 * e], c1 = edges.OppositeCorners[2 * e + 1];
      if (c0 >= 0 && c1 >= 0 && edges.FaceCount[e] == 2)
      {
        const double cosine = NormalCosine(normal(c0), normal(c1)); // (NaN without a normal)
        if (std::isfinite(cosine))
        {
          angles[e] = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / 3.141592653589793;
        }
      }
    }
  });
  return angles;
}

/// The median of the edges' angles (each edge counted on one process).
double MedianDihedral(const MeshTopology& topo, const std::vector<double>& angles, const Partition* split)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  std::vector<double> counted;
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    if (std::isfinite(angles[e]) && (!split || split->CountsEdge(edges.Vertices[2 * e], edges.Vertices[2 * e + 1])))
    {
      counted.push_back(angles[e]);
    }
  }
  const std::int64_t count = Total(counted.size(), split);
  return count > 0 ? NthSmallest(counted, count / 2, split) : 0.0;
}

/// The median angle of the edges at vertex v (0 without any).
double VertexDihedral(const MeshTopology& topo, const std::vector<double>& angles, Index v, std::vector<double>& scratch)
{
  const MeshTopology::EdgeTable& edges = topo.Edges();
  scratch.clear();
  for (std::int64_t k = edges.NeighborOffsets[v]; k < edges.NeighborOffsets[v + 1]; ++k)
  {
    const double angle = angles[edges.NeighborEdges[k]];
    if (std::isfinite(angle))
    {
      scratch.push_back(angle);
    }
  }
  if (scratch.empty())
  {
    return 0.0;
  }
  std::nth_element(scratch.begin(), scratch.begin() + scratch.size() / 2, scratch.end());
  return scratch[scratch.size() / 2];
}

/// The rings of the quadric fits for a median dihedral angle (degrees; see
/// EstimateSurfaceNoise).
int RingsFor(double dihedral)
{
  return dihedral < 35.0 ? 2 : dihedral < 45.0 ? 3 : dihedral < 52.0 ? 4 : 6;
}

/// From this median dihedral angle (degrees) on, the noise crumples the
/// surface (it is an edge length or more): the fits' frames (the principal
/// axes of their rings' points) tilt with it, and the tilt lets the fits
/// take up part of the noise (bunny00 Loop-subdivided three and four times
/// with noise of 2.4 edge lengths along the normals, median angle 51.5
/// degrees: 0.30 and 0.27 of it on the 4-rings RingsFor gives).  There it
/// is measured again, at CrumpledSamples points, by fits on
/// CrumpledFitRings-rings in the frame of the vector area of the point's
/// MostRings-ring (the sum of its triangles' area vectors, which depends
/// only on the ring's boundary: the noise hardly tilts it), and that
/// estimate is taken where it is more than CrumpledGrowth times the first.
/// bunny00 Loop-subdivided 2, 3 and 4 times with noise of 2.4 edge lengths:
/// 0.98, 0.96 and 0.92 of it (fits on the 12-rings themselves in their
/// principal axes: 1.02, 0.95 and 0.65); 3 times with 1.2 edge lengths
/// 0.99.  On the corpus with noise of 0.1-1% of the diagonal along the
/// normals four meshes at 1% are crumpled enough: bunny00 1.02, the
/// locally refined cylinder (its refined part crumpled) 0.94, and, where
/// fits on 12-rings took in the shape's detail (cow 4.76, fandisk_large
/// 1.36), cow 1.25 and fandisk_large 1.08.
constexpr double CrumpledDihedral = 45.0;
constexpr double CrumpledGrowth = 1.1;
constexpr int MostRings = 12;
constexpr int CrumpledFitRings = 2;
/// The crumpled surface's second estimate takes 2^30 / n of its n points,
/// from CrumpledSamples (a median's relative error of about 1.8%) to the
/// first estimate's 2^15: its wide rings cost about 0.5 s at 4096 points on
/// 2 threads, and a small surface split over processes needs more (bunny00
/// on 4 processes: 9% from the serial estimate at 4096).
constexpr double CrumpledSamples = 4096.0;
constexpr double CrumpledWork = 1073741824.0;

/// Points of more neighbours than this are taken into a ring but not
/// expanded (unless they are its centre): the apex of a fan of 20,000
/// triangles put its whole fan into the ring of every point near it, and
/// the estimate took 54 s instead of 0.2.
constexpr std::int64_t MostExpandedNeighbours = 64;

/// The k-ring of `centre` (without it) into `ring`; false when a point to
/// expand is not whole here (a ghost of a split surface).
bool CollectRing(const MeshTopology::VertexGraph& graph, Index centre, int rings, const Partition* split,
  std::vector<int>& stamp, int mark, std::vector<Index>& ring)
{
  ring.assign(1, centre);
  stamp[centre] = mark;
  std::size_t begin = 0;
  for (int r = 0; r < rings; ++r)
  {
    const std::size_t end = ring.size();
    for (std::size_t k = begin; k < end; ++k)
    {
      const Index v = ring[k];
      if (split && !split->IsOwned(v))
      {
        return false;
      }
      if (v != centre && graph.NeighborOffsets[v + 1] - graph.NeighborOffsets[v] > MostExpandedNeighbours)
      {
        continue;
      }
      for (std::int64_t j = graph.NeighborOffsets[v]; j < graph.NeighborOffsets[v + 1]; ++j)
      {
        const Index w = graph.Neighbors[j];
        if (stamp[w] != mark)
        {
          stamp[w] = mark;
          ring.push_back(w);
        }
      }
    }
    begin = end;
  }
  ring.erase(ring.begin());
  return true;
}

/// The height of x_centre above the least-squares quadric through the ring's
/// points, over its noise gain (a noise sample), in the frame of `normal`
/// (unit) where given, else of the ring's principal axes; NaN where the fit
/// is not determined.
double QuadricResidual(const double* x, Index centre, const std::vector<Index>& ring, const Vec3* normal = nullptr)
{
  const Vec3 o = Point(x, centre);
  Vec3 mean = Vec3::Zero();
  for (Index v : ring)
  {
    mean += Point(x, v) - o;
  }
  mean /= static_cast<double>(ring.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (Index v : ring)
  {
    const Vec3 d = Point(x, v) - o - mean;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> pca(cov);
  Vec3 axisU = pca.eigenvectors().col(2), axisV = pca.eigenvectors().col(1), axisN = pca.eigenvectors().col(0);
  if (normal)
  {
    axisN = *normal;
    TangentFrame(axisN, axisU, axisV);
  }
  double radius = 0.0;
  for (Index v : ring)
  {
    const Vec3 d = Point(x, v) - o;
    radius += d.dot(axisU) * d.dot(axisU) + d.dot(axisV) * d.dot(axisV);
  }
  radius = std::sqrt(radius / static_cast<double>(ring.size()));
  if (!(radius > 0.0) || !std::isfinite(radius))
  {
    return std::nan("");
  }
  using Row = Eigen::Matrix<double, 6, 1>;
  const auto basis = [&](Index v) {
    const Vec3 d = Point(x, v) - o;
    const double u = d.dot(axisU) / radius, w = d.dot(axisV) / radius;
    return Row(1.0, u, w, u * u, u * w, w * w);
  };
  Eigen::Matrix<double, 6, 6> gram = Eigen::Matrix<double, 6, 6>::Zero();
  for (Index v : ring)
  {
    const Row b = basis(v);
    gram += b * b.transpose();
  }
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(gram);
  const Eigen::VectorXd d = ldlt.vectorD();
  if (ldlt.info() != Eigen::Success || !(d.minCoeff() > 1e-9 * d.maxCoeff()))
  {
    return std::nan("");
  }
  const Row g = ldlt.solve(Row::Unit(0)); // the fit's value at the centre: sum_j (b_j . g) z_j
  double height = 0.0, gain = 1.0;
  for (Index v : ring)
  {
    const double w = basis(v).dot(g);
    height += w * (Point(x, v) - o).dot(axisN);
    gain += w * w;
  }
  return std::abs(height) / std::sqrt(gain);
}

} // namespace

std::uint64_t PointHash(const double* point)
{
  const auto mix = [](std::uint64_t z) { // SplitMix64's finaliser
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  };
  std::uint64_t h = 0x9e3779b97f4a7c15ull;
  for (int a = 0; a < 3; ++a)
  {
    std::uint64_t bits = 0;
    std::memcpy(&bits, point + a, sizeof bits);
    h = mix(h ^ bits);
  }
  return h;
}

namespace
{

/// The median of the finite values over the processes, as the deviation of
/// a normal law (MAD / 0.6745); 0 below 8 values.
double RobustDeviation(const std::vector<double>& values, const Partition* split)
{
  std::vector<double> samples;
  for (double r : values)
  {
    if (std::isfinite(r))
    {
      samples.push_back(r);
    }
  }
  const std::int64_t count = Total(samples.size(), split);
  return count >= 8 ? NthSmallest(samples, count / 2, split) / 0.6744897501960817 : 0.0;
}

/// The quadric residuals of EstimateSurfaceNoise at the points a hash
/// samples (one in `Stride`), owned and not skipped.
struct RingResiduals
{
  const MeshTopology& Topo;
  const double* X;
  const std::vector<double>& Angles;
  double MedianDihedral;
  const std::uint8_t* Skip;
  const Partition* Split;
  int NumberOfThreads;
  std::int64_t Stride = 1;
  /// Where positive: every fit on a CrumpledFitRings-ring in the frame of
  /// the vector area of this ring (Frame), not on the rings of Measure's
  /// `least` in their principal axes.
  int FrameRings = 0;

  /// The sum of the area vectors of v's triangles.
  Vec3 AreaVector(Index v) const
  {
    Vec3 sum = Vec3::Zero();
    for (const Index* c = Topo.CornersBegin(v); c < Topo.CornersEnd(v); ++c)
    {
      const Index t = *c / 3;
      const Vec3 a = Point(X, Topo.CornerVertex(3 * t));
      sum += (Point(X, Topo.CornerVertex(3 * t + 1)) - a).cross(Point(X, Topo.CornerVertex(3 * t + 2)) - a);
    }
    return sum;
  }

  /// In `normal`, the unit normal of the vector area of v's `ring` (three
  /// times its triangles' area vectors, those at its edge partly), or none
  /// where that is less than a tenth of their total area (a ring around a
  /// thin tube or a small closed component, whose vector area is nearly 0:
  /// the fit's principal axes instead).
  void Frame(Index v, const std::vector<Index>& ring, std::optional<Vec3>& normal) const
  {
    Vec3 sum = AreaVector(v);
    double total = sum.norm();
    for (const Index w : ring)
    {
      const Vec3 a = AreaVector(w);
      sum += a;
      total += a.norm();
    }
    normal.reset();
    if (sum.norm() > 0.1 * total && sum.allFinite())
    {
      normal = sum.normalized();
    }
  }

  /// (Deviation, WiderDeviation) with every ring at least `least` wide
  /// (the wider one only with `wide`, else the same), or in FrameRings'
  /// frames.
  std::pair<double, double> Measure(int least, bool wide) const
  {
    const Index n = Topo.NumberOfVertices();
    const MeshTopology::VertexGraph& graph = Topo.Graph();
    std::vector<double> residual(static_cast<std::size_t>(n), std::nan("")), wider(residual);
    ParallelFor(n, NumberOfThreads, [&](std::int64_t begin, std::int64_t end) {
      std::vector<int> stamp(static_cast<std::size_t>(n), -1);
      std::vector<Index> ring;
      std::vector<double> scratch;
      int mark = 0;
      for (std::int64_t i = begin; i < end; ++i)
      {
        const Index v = static_cast<Index>(i);
        if ((Split && !Split->IsOwned(v)) || PointHash(X + 3 * static_cast<std::size_t>(v)) % Stride != 0 ||
          (Skip && Skip[v]))
        {
          continue;
        }
        std::optional<Vec3> normal;
        if (FrameRings > 0)
        {
          if (!CollectRing(graph, v, FrameRings, Split, stamp, mark++, ring))
          {
            continue;
          }
          Frame(v, ring, normal);
        }
        const int rings = FrameRings > 0
          ? CrumpledFitRings
          : std::max(least, RingsFor(std::max(MedianDihedral, VertexDihedral(Topo, Angles, v, scratch))));
        if (CollectRing(graph, v, rings, Split, stamp, mark++, ring) && ring.size() >= 9)
        {
          residual[i] = QuadricResidual(X, v, ring, normal ? &*normal : nullptr);
          if (wide && CollectRing(graph, v, rings + 1, Split, stamp, mark++, ring))
          {
            wider[i] = QuadricResidual(X, v, ring);
          }
        }
      }
    }, {}, ResolveThreadCount(NumberOfThreads), 1);
    const double deviation = RobustDeviation(residual, Split);
    return { deviation, wide ? RobustDeviation(wider, Split) : deviation };
  }
};

std::int64_t StrideFor(double rows, double samples)
{
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(rows / samples)));
}

} // namespace

SurfaceNoise EstimateSurfaceNoise(
  const MeshTopology& topo, const double* x, const std::uint8_t* skip, const Partition* split, int numThreads)
{
  SurfaceNoise result;
  const std::vector<double> angles = DihedralAngles(topo, x, numThreads);
  result.MedianDihedral = MedianDihedral(topo, angles, split);
  const double rows =
    split ? static_cast<double>(split->TotalRows()) : static_cast<double>(topo.NumberOfVertices());
  RingResiduals residuals{ topo, x, angles, result.MedianDihedral, skip, split, numThreads, StrideFor(rows, 32768.0) };
  std::tie(result.Deviation, result.WiderDeviation) = residuals.Measure(0, true);
  result.LocalDeviation = result.Deviation;
  result.Rings = RingsFor(result.MedianDihedral);
  if (result.MedianDihedral >= CrumpledDihedral && result.Deviation > 0.0)
  {
    // Measured again in the frames of MostRings-rings (CrumpledDihedral), at
    // fewer points (CrumpledSamples), and taken where it grew (the wider
    // estimate is then the same: the growth is the frames', not the shape's).
    residuals.Stride = StrideFor(rows, std::clamp(CrumpledWork / std::max(rows, 1.0), CrumpledSamples, 32768.0));
    residuals.FrameRings = MostRings;
    const double crumpled = residuals.Measure(0, false).first;
    if (crumpled > CrumpledGrowth * result.Deviation)
    {
      result.Deviation = result.WiderDeviation = crumpled;
      result.Rings = MostRings;
    }
  }
  result.Rings = result.Deviation > 0.0 ? result.Rings : 0;
  return result;
}

double EstimateTangentialNoise(const MeshTopology& topo, const double* x, const double* normals,
  const std::uint8_t* skip, const Partition* split)
{
  const Index n = topo.NumberOfVertices();
  const MeshTopology::VertexGraph& graph = topo.Graph();
  const double rows = split ? static_cast<double>(split->TotalRows()) : static_cast<double>(n);
  const std::int64_t stride = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(rows / 32768.0)));
  std::vector<double> samples;
  for (Index v = 0; v < n; ++v)
  {
    const std::int64_t begin = graph.NeighborOffsets[v], end = graph.NeighborOffsets[v + 1];
    const Vec3 normal = Point(normals, v);
    if ((split && !split->IsOwned(v)) || (skip && skip[v]) || (topo.VertexFlags(v) & VertexBoundary) ||
      end - begin < 3 || !normal.allFinite() || PointHash(x + 3 * static_cast<std::size_t>(v)) % stride != 0)
    {
      continue;
    }
    Vec3 move = Vec3::Zero();
    for (std::int64_t k = begin; k < end; ++k)
    {
      move += Point(x, graph.Neighbors[k]);
    }
    const double count = static_cast<double>(end - begin);
    move = move / count - Point(x, v);
    const Vec3 tangential = move - move.dot(normal) * normal;
    if (tangential.allFinite())
    {
      samples.push_back(tangential.squaredNorm() / (1.0 + 1.0 / count));
    }
  }
  const std::int64_t total = Total(samples.size(), split);
  return total >= 8 ? std::sqrt(NthSmallest(samples, total / 2, split) / (2.0 * std::log(2.0))) : 0.0;
}

} // namespace beltrami
