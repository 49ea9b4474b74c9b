#include "Mesh/TriangleTree.h"

#include "Support/Parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <utility>

namespace beltrami
{

namespace
{

constexpr int LeafSize = 4;

/// Whether origin + t direction meets triangle abc at some tmin < t < 1
/// (Moller & Trumbore 1997; barycentric coordinates down to -1e-9).
bool SegmentMeetsTriangle(const Vec3& o, const Vec3& d, double tmin, const Vec3& a, const Vec3& b, const Vec3& c)
{
  constexpr double slack = 1e-9;
  const Vec3 e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (!(std::abs(det) > 1e-300))
  {
    return false; // parallel to the triangle's plane, or a degenerate triangle
  }
  const Vec3 s = o - a;
  const double u = s.dot(p) / det;
  if (u < -slack || u > 1.0 + slack)
  {
    return false;
  }
  const Vec3 q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < -slack || u + v > 1.0 + slack)
  {
    return false;
  }
  const double t = e2.dot(q) / det;
  return t > tmin && t < 1.0;
}

float Below(double x)
{
  const float f = static_cast<float>(x);
  return static_cast<double>(f) <= x ? f : std::nextafter(f, -HUGE_VALF);
}

float Above(double x)
{
  const float f = static_cast<float>(x);
  return static_cast<double>(f) >= x ? f : std::nextafter(f, HUGE_VALF);
}

} // namespace

TriangleTree::TriangleTree(
  const double* points, const Index* triangles, std::size_t numberOfTriangles, int numThreads)
  : Points(points)
  , Triangles(triangles)
{
  // Each finite triangle's box and centre.
  std::vector<double> boxes;
  boxes.reserve(6 * numberOfTriangles);
  for (std::size_t t = 0; t < numberOfTriangles; ++t)
  {
    Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
    for (int k = 0; k < 3; ++k)
    {
      const Vec3 p = Point(points, triangles[3 * t + k]);
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    if (lo.allFinite() && hi.allFinite())
    {
      Order.push_back(static_cast<Index>(t));
      boxes.insert(boxes.end(), { lo[0], lo[1], lo[2], hi[0], hi[1], hi[2] });
    }
  }
  if (Order.empty())
  {
    return;
  }
  std::vector<Index> slot(numberOfTriangles, 0); // triangle -> its box in `boxes`
  for (std::size_t k = 0; k < Order.size(); ++k)
  {
    slot[Order[k]] = static_cast<Index>(k);
  }
  const Builder build{ boxes, slot, Order };
  // The top levels here, then the subtrees below them in parallel, each in
  // its own nodes, appended in order (the same splits whatever the threads).
  const int threads = ResolveThreadCount(numThreads);
  const std::int32_t size = static_cast<std::int32_t>(Order.size());
  const std::int32_t chunk = threads > 1 ? std::max(LeafSize, size / (4 * threads)) : 0;
  Nodes.reserve(2 * Order.size() / LeafSize + 1);
  std::vector<Subtree> deferred;
  build.Grow(Nodes, 0, size, chunk, deferred);
  std::vector<std::vector<Node>> parts(deferred.size());
  ParallelFor(static_cast<std::int64_t>(deferred.size()), threads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i)
    {
      std::vector<Subtree> none;
      build.Grow(parts[i], deferred[i].Begin, deferred[i].End, 0, none);
    }
  }, {}, 0, 1);
  for (std::size_t i = 0; i < parts.size(); ++i)
  {
    // Part node k > 0 goes to base + k - 1, its root to the node it grows from.
    const std::int32_t base = static_cast<std::int32_t>(Nodes.size());
    for (Node& node : parts[i])
    {
      node.First = node.Count == 0 ? base + node.First - 1 : node.First;
    }
    Nodes[deferred[i].Node] = parts[i][0];
    Nodes.insert(Nodes.end(), parts[i].begin() + 1, parts[i].end());
  }
}

void TriangleTree::Builder::Grow(std::vector<Node>& nodes, std::int32_t first, std::int32_t last, std::int32_t chunk,
  std::vector<Subtree>& deferred) const
{
  const auto centre = [&](Index t, int axis) {
    const double* b = &Boxes[6 * static_cast<std::size_t>(Slot[t])];
    return b[axis] + b[3 + axis];
  };
  // Top down: a node's triangles split at the median of their centres along
  // the longest side of the centres' box; ranges of `chunk` triangles or
  // fewer (and more than a leaf's; chunk 0: none) are left to `deferred`.
  nodes.emplace_back();
  std::vector<std::pair<std::int32_t, std::int32_t>> pending{ { first, last } };
  std::vector<std::int32_t> nodeOf{ static_cast<std::int32_t>(nodes.size()) - 1 };
  while (!pending.empty())
  {
    const auto [begin, end] = pending.back();
    const std::int32_t id = nodeOf.back();
    pending.pop_back();
    nodeOf.pop_back();
    if (end - begin > LeafSize && end - begin <= chunk)
    {
      deferred.push_back({ id, begin, end });
      continue;
    }
    Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
    Vec3 clo = lo, chi = hi;
    for (std::int32_t k = begin; k < end; ++k)
    {
      const double* b = &Boxes[6 * static_cast<std::size_t>(Slot[Order[k]])];
      for (int a = 0; a < 3; ++a)
      {
        lo[a] = std::min(lo[a], b[a]);
        hi[a] = std::max(hi[a], b[3 + a]);
        clo[a] = std::min(clo[a], b[a] + b[3 + a]);
        chi[a] = std::max(chi[a], b[a] + b[3 + a]);
      }
    }
    for (int a = 0; a < 3; ++a)
    {
      nodes[id].Lo[a] = Below(lo[a]);
      nodes[id].Hi[a] = Above(hi[a]);
    }
    if (end - begin <= LeafSize)
    {
      nodes[id].First = begin;
      nodes[id].Count = end - begin;
      continue;
    }
    int axis = 0;
    (chi - clo).maxCoeff(&axis);
    const std::int32_t middle = begin + (end - begin) / 2;
    std::nth_element(Order.begin() + begin, Order.begin() + middle, Order.begin() + end,
      [&](Index x, Index y) { return centre(x, axis) < centre(y, axis); });
    const std::int32_t children = static_cast<std::int32_t>(nodes.size());
    nodes[id].First = children;
    nodes[id].Count = 0;
    nodes.emplace_back();
    nodes.emplace_back();
    pending.emplace_back(begin, middle);
    nodeOf.push_back(children);
    pending.emplace_back(middle, end);
    nodeOf.push_back(children + 1);
  }
}

bool TriangleTree::Blocks(
  const Vec3& o, const Vec3& d, double tmin, const std::function<bool(Index triangle)>& ignore) const
{
  if (Nodes.empty() || !o.allFinite() || !d.allFinite())
  {
    return false;
  }
  const Vec3 inverse(1.0 / d[0], 1.0 / d[1], 1.0 / d[2]); // (infinite along an axis d does not move on)
  const auto enters = [&](const Node& n) {
    double t0 = 0.0, t1 = 1.0;
    for (int a = 0; a < 3; ++a)
    {
      double ta = (n.Lo[a] - o[a]) * inverse[a], tb = (n.Hi[a] - o[a]) * inverse[a];
      if (std::isnan(ta) || std::isnan(tb))
      {
        ta = -HUGE_VAL; // (0 * infinity: o on the box's side, moving along it)
        tb = HUGE_VAL;
      }
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    }
    return t0 <= t1;
  };
  std::int32_t stack[128];
  int top = 0;
  if (enters(Nodes[0]))
  {
    stack[top++] = 0;
  }
  while (top > 0)
  {
    const Node& n = Nodes[stack[--top]];
    if (n.Count == 0)
    {
      for (int c = 0; c < 2; ++c)
      {
        if (enters(Nodes[n.First + c]))
        {
          stack[top++] = n.First + c;
        }
      }
      continue;
    }
    for (std::int32_t k = n.First; k < n.First + n.Count; ++k)
    {
      const Index* v = Triangles + 3 * static_cast<std::int64_t>(Order[k]);
      if (SegmentMeetsTriangle(o, d, tmin, Point(Points, v[0]), Point(Points, v[1]), Point(Points, v[2])) &&
        !ignore(Order[k]))
      {
        return true;
      }
    }
  }
  return false;
}

} // namespace beltrami
