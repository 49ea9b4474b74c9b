#include "Remeshing/RemeshOptimization.h"

#include "Remeshing/RemeshOptimizer.h"
#include "Support/Parallel.h"
#include "Support/Vectorization.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_set>

namespace beltrami
{

namespace detail
{

namespace
{

/// Stitching rounds after RoundRimCorners moved corners, with the boundary
/// fixed: the triangles beside them follow.
constexpr int RimRounds = 3;

/// The part of the plane triangle (p, a, b) nearer to p than to a and b
/// (p's Voronoi region in it; in an obtuse triangle the circumcentre is
/// replaced by the middle of the longest edge, the mixed area of thesis
/// section 2.3): its area and centroid.
double VoronoiPart(const double* p, const double* a, const double* b, double* centroid)
{
  const double ux = a[0] - p[0], uy = a[1] - p[1], vx = b[0] - p[0], vy = b[1] - p[1];
  const double cross = ux * vy - uy * vx;
  const double uu = ux * ux + uy * uy, vv = vx * vx + vy * vy, uv = ux * vx + uy * vy;
  double c[2]; // relative to p
  if (uv < 0.0 || uu < uv || vv < uv || cross == 0.0) // obtuse (or flat): middle of the longest edge
  {
    const double ab = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
    const double* far = ab >= uu && ab >= vv ? a : (uu >= vv ? a : b);
    const double* other = ab >= uu && ab >= vv ? b : p;
    c[0] = 0.5 * (far[0] + other[0]) - p[0];
    c[1] = 0.5 * (far[1] + other[1]) - p[1];
  }
  else
  {
    c[0] = (vy * uu - uy * vv) / (2.0 * cross);
    c[1] = (ux * vv - vx * uu) / (2.0 * cross);
  }
  // Two triangles: (p, a/2, c) and (p, c, b/2).
  const double area1 = 0.5 * std::abs(0.5 * ux * c[1] - 0.5 * uy * c[0]);
  const double area2 = 0.5 * std::abs(c[0] * 0.5 * vy - c[1] * 0.5 * vx);
  const double area = area1 + area2;
  for (int k = 0; k < 2; ++k)
  {
    const double half[2] = { 0.5 * (k ? uy : ux), 0.5 * (k ? vy : vx) };
    centroid[k] = p[k] + (area > 0.0 ? (area1 * (half[0] + c[k]) + area2 * (c[k] + half[1])) / (3.0 * area) : 0.0);
  }
  return area;
}

/// The Voronoi part of VoronoiPart for a triangle in 3D, computed in the
/// triangle's own plane: its area and its centroid (3D).
double VoronoiPart3D(const Vec3& p, const Vec3& a, const Vec3& b, Vec3& centroid)
{
  const Vec3 n = (a - p).cross(b - p);
  if (!(n.norm() > 0.0))
  {
    return 0.0;
  }
  const Vec3 e1 = (a - p).normalized(), e2 = n.normalized().cross(e1);
  const double origin[2] = { 0.0, 0.0 }, a2[2] = { (a - p).norm(), 0.0 },
               b2[2] = { (b - p).dot(e1), (b - p).dot(e2) };
  double c[2];
  const double area = VoronoiPart(origin, a2, b2, c);
  centroid = p + c[0] * e1 + c[1] * e2;
  return area;
}
/// One thread's buffers for the moves (no allocation per move).
struct MoveBuffers
{
  std::vector<std::pair<Index, std::array<double, 2>>> Corners; ///< Place's new corner positions
  std::vector<Index> Queue;            ///< NearestOnSurface's triangles
  std::vector<std::uint32_t> Visited;  ///< per input triangle: NearestOnSurface's stamp
  std::uint32_t Stamp = 0;             ///< above every stamp in Visited
};

MoveBuffers& ThreadBuffers()
{
  static thread_local MoveBuffers buffers;
  return buffers;
}

} // namespace

/// The mean importance of face f's vertices (1 without one).
double Optimizer::Importance(Index f) const
{
  if (VertexImportance.empty())
  {
    return 1.0;
  }
  return (VertexImportance[M.Tail(3 * f)] + VertexImportance[M.Tail(3 * f + 1)] + VertexImportance[M.Tail(3 * f + 2)]) /
    3.0;
}

/// The importance at vertex v's place on the input (interpolated).
double Optimizer::ImportanceAt(Index v) const
{
  double importance = 0.0;
  for (int j = 0; j < 3; ++j)
  {
    importance +=
      R.Barycentric[3 * v + j] * std::max(0.0, ImportanceValues[Topology.CornerVertex(3 * R.Triangle[v] + j)]);
  }
  return importance;
}

/// The relaxation weight of face f: its 3D area times its mean importance.
double Optimizer::Weight(Index f) const
{
  const Vec3 a = M.Position(M.Tail(3 * f)), b = M.Position(M.Tail(3 * f + 1)), c = M.Position(M.Tail(3 * f + 2));
  return 0.5 * (b - a).cross(c - a).norm() * Importance(f);
}

/// Every face around v stays positively oriented in its chart with v at
/// (triangle, w) of the input; their corners' positions go to the thread's
/// buffer.
bool Optimizer::KeepsPlane(Index v, Index triangle, const double* w)
{
  std::vector<std::pair<Index, std::array<double, 2>>>& corners = ThreadBuffers().Corners;
  corners.clear();
  bool valid = true, located = false;
  int chart = -1; // of the last position found (an interior vertex's faces are all in one chart)
  std::array<double, 2> uv;
  M.ForEachOutgoing(v, [&](Index h) {
    if (R.FaceChart[h / 3] != chart)
    {
      chart = R.FaceChart[h / 3];
      located = ChartPosition(Topology, Atlas.Charts[chart], triangle, w, uv.data());
    }
    valid = valid && located &&
      Cross2(uv.data(), UVAt(HalfEdgeMesh::Next(h)), UVAt(HalfEdgeMesh::Prev(h))) >
        1e-3 * std::abs(Cross2(UVAt(h), UVAt(HalfEdgeMesh::Next(h)), UVAt(HalfEdgeMesh::Prev(h))));
    corners.push_back({ h, uv });
  });
  return valid;
}

/// The unit normal of v's faces (area-weighted; not finite where they have
/// no area).
Vec3 Optimizer::FanNormal(Index v) const
{
  Vec3 normal = Vec3::Zero();
  const Vec3 x = M.Position(v);
  M.ForEachOutgoing(v, [&](Index h) {
    normal += (M.Position(M.Head(h)) - x).cross(M.Position(M.Tail(HalfEdgeMesh::Prev(h))) - x);
  });
  return normal.normalized();
}

/// The unit normal of input triangle t.
Vec3 Optimizer::InputNormalOf(Index t) const
{
  const Vec3 a = Point(Points, Topology.CornerVertex(3 * t)), b = Point(Points, Topology.CornerVertex(3 * t + 1)),
             c = Point(Points, Topology.CornerVertex(3 * t + 2));
  return (b - a).cross(c - a).normalized();
}

/// The folded faces around v (Folded) with v at x, on the input where its
/// normal is inputNormal.
int Optimizer::FoldsAround(Index v, const Vec3& x, const Vec3& inputNormal) const
{
  int folds = 0;
  M.ForEachOutgoing(v, [&](Index h) {
    const Index b = M.Head(h), c = M.Tail(HalfEdgeMesh::Prev(h));
    folds += Folded(x, M.Position(b), M.Position(c), inputNormal, InputNormals[b], InputNormals[c]);
  });
  return folds;
}

/// With v at x (where the input's normal is inputNormal): every face around
/// v stays within acos(cosine) of `normal` (FanNormal(v) before the move) and
/// none folds (no fold); where faces around v are folded already (a lifted
/// chart map that is far from linear at the spacing folds some), fewer are.
bool Optimizer::KeepsSurface(
  Index v, const Vec3& x, const Vec3& normal, const Vec3& inputNormal, double cosine, int foldsBefore) const
{
  const int before = foldsBefore >= 0 ? foldsBefore : FoldsAround(v, M.Position(v), InputNormals[v]);
  const int after = FoldsAround(v, x, inputNormal);
  if (before > 0)
  {
    return after < before;
  }
  bool valid = normal.allFinite() && after == 0;
  M.ForEachOutgoing(v, [&](Index h) {
    const Vec3 n = (M.Position(M.Head(h)) - x).cross(M.Position(M.Tail(HalfEdgeMesh::Prev(h))) - x);
    valid = valid && n.dot(normal) > cosine * n.norm() && n.norm() > 0.0;
  });
  return valid;
}

/// Moves vertex v to (triangle, w) of the input if no face around it flips
/// (in its chart, or on the surface while stitching: KeepsSurface with
/// `normal`, v's FanNormal where the caller has it, and `cosine`); `moved`
/// gets the 3D distance.
bool Optimizer::Place(
  Index v, Index triangle, const double* w, double& moved, const Vec3* normal, double cosine, int foldsBefore)
{
  const Vec3 x = SurfacePoint(Topology, Points, triangle, w), inputNormal = InputNormalOf(triangle);
  std::vector<std::pair<Index, std::array<double, 2>>>& corners = ThreadBuffers().Corners;
  corners.clear();
  if (Stitching ? !KeepsSurface(v, x, normal ? *normal : FanNormal(v), inputNormal, cosine, foldsBefore)
                : !KeepsPlane(v, triangle, w))
  {
    return false;
  }
  for (const auto& [h, uv] : corners) // empty while stitching (the charts are left behind)
  {
    R.CornerUV[2 * h] = uv[0];
    R.CornerUV[2 * h + 1] = uv[1];
  }
  moved = (x - M.Position(v)).norm();
  M.SetPosition(v, x);
  R.Triangle[v] = triangle;
  InputNormals[v] = inputNormal;
  std::copy(w, w + 3, &R.Barycentric[3 * v]);
  if (!VertexImportance.empty())
  {
    VertexImportance[v] = ImportanceAt(v);
  }
  if (!VertexMetric.empty())
  {
    VertexMetric[v] = MetricAt(v);
  }
  return true;
}

/// An interior vertex towards the weighted centroid of its faces in its
/// chart (halving the step while a face would flip); with a metric, the
/// centroid of its Voronoi cell in the metric at v, carried into the plane
/// (PlaneMetricFactor).
bool Optimizer::MoveInterior(Index v, double& moved)
{
  double sum = 0.0, target[2] = { 0.0, 0.0 };
  int chart = -1;
  const double* p = nullptr;
  const bool metric = !VertexMetric.empty();
  const Eigen::Matrix2d u = metric ? PlaneMetricFactor(v) : Eigen::Matrix2d::Identity();
  M.ForEachOutgoing(v, [&](Index h) {
    const double* q[3] = { UVAt(h), UVAt(HalfEdgeMesh::Next(h)), UVAt(HalfEdgeMesh::Prev(h)) };
    double c[2], w = 0.0;
    if (metric)
    {
      // The face's share of v's Voronoi cell in the metric (the plane's
      // coordinates relative to v mapped by u), times its importance.
      const Eigen::Vector2d a = u * Eigen::Vector2d(q[1][0] - q[0][0], q[1][1] - q[0][1]),
                            b = u * Eigen::Vector2d(q[2][0] - q[0][0], q[2][1] - q[0][1]);
      const double origin[2] = { 0.0, 0.0 };
      w = VoronoiPart(origin, a.data(), b.data(), c) * Importance(h / 3);
    }
    else
    {
      // The face's share of v's Voronoi cell in the plane, weighted by the
      // face's 3D area (times importance) per unit of its area in the plane.
      const double planeArea = 0.5 * std::abs(Cross2(q[0], q[1], q[2]));
      const double part = VoronoiPart(q[0], q[1], q[2], c);
      w = planeArea > 0.0 ? Weight(h / 3) / planeArea * part : 0.0;
    }
    target[0] += w * c[0];
    target[1] += w * c[1];
    sum += w;
    chart = R.FaceChart[h / 3];
    p = UVAt(h);
  });
  if (!(sum > 0.0) || chart < 0)
  {
    return false;
  }
  const double start[2] = { p[0], p[1] };
  if (metric) // (the metric's centroid is relative to v)
  {
    const Eigen::Vector2d back = u.triangularView<Eigen::Upper>().solve(Eigen::Vector2d(target[0], target[1]) / sum);
    target[0] = (start[0] + back[0]) * sum;
    target[1] = (start[1] + back[1]) * sum;
  }
  for (double step = OverRelaxation; step > 0.1; step *= 0.5)
  {
    const double uv[2] = { start[0] + step * (target[0] / sum - start[0]), start[1] + step * (target[1] / sum - start[1]) };
    double w[3];
    const Index t = Locators[chart].LocateNearest(uv, w);
    if (t >= 0 && Place(v, Atlas.Charts[chart].Triangles[t], w, moved))
    {
      return true;
    }
  }
  return false;
}

/// A vertex of a chart boundary path along it by the tangential part of the
/// move to the weighted centroid of all its faces (on both sides of a seam),
/// or on the surface's boundary towards the middle of its neighbours there,
/// kept between its neighbours on the path.
bool Optimizer::MoveOnPath(Index v, double& moved)
{
  const SamplePath& path = Samples.Paths[R.Path[v]];
  const Index i = PathIndex[v];
  double sum = 0.0;
  Vec3 target = Vec3::Zero();
  M.ForEachOutgoing(v, [&](Index h) {
    const double w = Weight(h / 3);
    target += w * (M.Position(M.Tail(h)) + M.Position(M.Head(h)) + M.Position(M.Tail(HalfEdgeMesh::Prev(h)))) / 3.0;
    sum += w;
  });
  if (!(sum > 0.0))
  {
    return false;
  }
  const double arc = R.Arc[v];
  const double lo = i > 1 ? R.Arc[path.Samples[i - 1]] : 0.0;
  const double hi = i + 2 < static_cast<Index>(path.Samples.size()) ? R.Arc[path.Samples[i + 1]] : path.Arc.back();
  // The path's direction at v: between the points a little before and after it.
  double w0[3], w1[3];
  const double delta = 1e-3 * (hi - lo);
  const Index t0 = LocateOnPath(Topology, path, arc - delta, w0), t1 = LocateOnPath(Topology, path, arc + delta, w1);
  const Vec3 tangent = SurfacePoint(Topology, Points, t1, w1) - SurfacePoint(Topology, Points, t0, w0);
  if (!(tangent.norm() > 0.0))
  {
    return false;
  }
  // Where a kept line takes more samples than the density (at its bends),
  // the move goes as much nearer to the denser side as a 1D relaxation in
  // its refinement would (nothing where the refinement is 1).
  const std::optional<double> refined = RefinedMiddle(path, lo, hi);
  // On the surface's boundary, the middle of its neighbours there: the
  // relaxation's pull, from one side only, left samples of jagged rims
  // unevenly spaced, with slivers on their short gaps (elephant-with-holes
  // at 10k: 7.1 degrees and 1.5% of the triangles below 30, now 17.9 and
  // 0.8%).
  const bool rim = path.Charts[0] < 0 || path.Charts[1] < 0;
  const double shift = refined ? *refined - arc
    : rim                      ? 0.5 * (lo + hi) - arc
                               : (target / sum - M.Position(v)).dot(tangent.normalized());
  // Between its neighbours, a fifth of the way from each at least (a tenth
  // where the line is refined, its gaps uneven by design): a bound of its
  // own gaps would let a sample pulled towards a corner creep, move after
  // move, to beside it (a sliver).
  const double margin = (refined ? 0.1 : 0.2) * (hi - lo);
  const double first = lo + margin, last = hi - margin;
  for (double step = 1.0; step > 0.1; step *= 0.5)
  {
    const double next = std::clamp(arc + step * shift, first, last);
    double w[3];
    const Index t = LocateOnPath(Topology, path, next, w);
    if (Place(v, t, w, moved))
    {
      R.Arc[v] = next;
      return true;
    }
  }
  return false;
}

/// The input triangle nearest to p among those reached from `start` through
/// triangles less than `radius` from p (the ball a move of that length
/// stays in), each crossed where p's nearest point in it lies (its edge or
/// vertex), with the nearest point's weights in w.
Index Optimizer::NearestOnSurface(const Vec3& p, Index start, double radius, double* w)
{
  // Most moves stay inside their triangle: nothing nearer is reached
  // through it (as below), so no search.
  const double d0 = ClosestPointOnTriangle(p, Point(Points, Topology.CornerVertex(3 * start)),
    Point(Points, Topology.CornerVertex(3 * start + 1)), Point(Points, Topology.CornerVertex(3 * start + 2)), w);
  if (w[0] > 0.0 && w[1] > 0.0 && w[2] > 0.0 && d0 < HUGE_VAL)
  {
    return start;
  }
  MoveBuffers& buffers = ThreadBuffers();
  std::vector<Index>& queue = buffers.Queue;
  std::vector<std::uint32_t>& visited = buffers.Visited;
  if (visited.size() != static_cast<std::size_t>(Topology.NumberOfTriangles()) || ++buffers.Stamp == 0)
  {
    visited.assign(Topology.NumberOfTriangles(), 0);
    buffers.Stamp = 1;
  }
  const std::uint32_t stamp = buffers.Stamp;
  queue.assign(1, start);
  visited[start] = stamp;
  Index best = -1;
  double bestDistance = HUGE_VAL;
  const double reach = radius * radius * (1.0 + 1e-9);
  constexpr std::ptrdiff_t FanValence = 64; // triangles around a fan's apex: more
  const auto isApex = [&](Index v) { return Topology.CornersEnd(v) - Topology.CornersBegin(v) > FanValence; };
  for (std::size_t i = 0; i < queue.size(); ++i)
  {
    const Index t = queue[i];
    double weights[3];
    const double d = ClosestPointOnTriangle(p, Point(Points, Topology.CornerVertex(3 * t)),
      Point(Points, Topology.CornerVertex(3 * t + 1)), Point(Points, Topology.CornerVertex(3 * t + 2)), weights);
    if (d < bestDistance)
    {
      bestDistance = d;
      best = t;
      std::copy(weights, weights + 3, w);
    }
    if (d > reach && t != start)
    {
      continue;
    }
    // Only across the edge or vertex where p's nearest point in t lies:
    // inside t (no weight 0) nothing nearer is reached through t.  Across
    // an edge, through the triangles around its ends; where one end is the
    // apex of a fan (a cone's tip, a disk's centre), through the other
    // end's only, which hold the triangles across the edge (each move near
    // a fan of 20,000 triangles tested all of them: 117 s to remesh a
    // double cone).
    Index ends[3];
    int count = 0;
    for (int k = 0; k < 3; ++k)
    {
      if (weights[k] > 0.0)
      {
        ends[count++] = Topology.CornerVertex(3 * t + k);
      }
    }
    for (int e = 0; e < count && count < 3; ++e)
    {
      if (count == 2 && isApex(ends[e]) && !isApex(ends[1 - e]))
      {
        continue;
      }
      for (const Index* c = Topology.CornersBegin(ends[e]); c != Topology.CornersEnd(ends[e]); ++c)
      {
        if (visited[*c / 3] != stamp)
        {
          visited[*c / 3] = stamp;
          queue.push_back(*c / 3);
        }
      }
    }
  }
  return best;
}

/// A free vertex while stitching: towards the centroid of its Voronoi cell
/// on the surface (each face's part in its own plane, weighted by the face's
/// importance; with a metric, in the metric at v), tangentially, then onto
/// the input at the nearest point (halving the step while a face would
/// fold).
bool Optimizer::MoveOnSurface(Index v, double& moved)
{
  double sum = 0.0;
  Vec3 target = Vec3::Zero(), normal = Vec3::Zero();
  const Vec3 x = M.Position(v);
  const bool metric = !VertexMetric.empty();
  const Mat3 u = metric ? MetricFactor({ v }) : Mat3::Identity();
  M.ForEachOutgoing(v, [&](Index h) {
    const Vec3 a = M.Position(M.Head(h)), b = M.Position(M.Tail(HalfEdgeMesh::Prev(h)));
    Vec3 c = Vec3::Zero();
    const double part = metric ? VoronoiPart3D(Vec3::Zero(), u * (a - x), u * (b - x), c) : VoronoiPart3D(x, a, b, c);
    const double w = part * Importance(h / 3);
    target += w * c;
    sum += w;
    normal += (a - x).cross(b - x);
  });
  if (!(sum > 0.0) || !(normal.norm() > 0.0))
  {
    return false;
  }
  normal.normalize();
  Vec3 shift = metric ? Vec3(u.triangularView<Eigen::Upper>().solve(target / sum)) : Vec3(target / sum - x);
  if (metric && LatticeWeight > 0.0)
  {
    double weight = 0.0;
    const Vec3 lattice = LatticeShift(v, u, weight);
    weight *= LatticeWeight;
    shift = (1.0 - weight) * shift + weight * Vec3(u.triangularView<Eigen::Upper>().solve(lattice));
  }
  shift -= shift.dot(normal) * normal;
  const int folds = FoldsAround(v, x, InputNormals[v]);
  if (folds > 0)
  {
    shift = ShiftToNeighbours(v); // (folded faces: their Voronoi parts and normal mean nothing)
  }
  for (double step = OverRelaxation; step > 0.1; step *= 0.5)
  {
    double w[3];
    const Index t = NearestOnSurface(x + step * shift, R.Triangle[v], step * shift.norm(), w);
    if (t >= 0 && Place(v, t, w, moved, &normal, 0.5, folds)) // (normal: FanNormal(v), the same sums)
    {
      return true;
    }
  }
  return false;
}

/// Starts the stitching rounds: the mobility of every vertex (free, except
/// samples on the surface's boundary or on feature edges, which slide along
/// their paths, and corners touching them, which stay); the number of
/// chart-boundary samples freed.
Index Optimizer::BeginStitching(const std::uint8_t* featureEdges)
{
  const MeshTopology::EdgeTable& edges = Topology.Edges();
  std::vector<std::uint8_t> kept(Topology.NumberOfVertices(), 0); // surface vertices on a kept edge
  const auto isKept = [&](std::int64_t e) { return IsKeptEdge(edges, e, featureEdges); };
  for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
  {
    if (isKept(e))
    {
      kept[edges.Vertices[2 * e]] = kept[edges.Vertices[2 * e + 1]] = 1;
    }
  }
  Moves.assign(M.NumberOfVertices(), Free);
  Index freed = 0;
  for (Index v = 0; v < M.NumberOfVertices(); ++v)
  {
    if (R.Kind[v] == SampleKind::Tip)
    {
      Moves[v] = Fixed;
    }
    else if (R.Kind[v] == SampleKind::Corner)
    {
      const double* w = &R.Barycentric[3 * v];
      const int k = static_cast<int>(std::max_element(w, w + 3) - w);
      Moves[v] = kept[Topology.CornerVertex(3 * R.Triangle[v] + k)] ? Fixed : Free;
    }
    else if (R.Kind[v] == SampleKind::Boundary)
    {
      const SamplePath& path = Samples.Paths[R.Path[v]];
      const std::size_t i = std::min<std::size_t>(path.Vertices.size() - 2,
        std::upper_bound(path.Arc.begin(), path.Arc.end(), R.Arc[v]) - path.Arc.begin() - 1);
      const std::int64_t e = edges.Find(path.Vertices[i], path.Vertices[i + 1]);
      Moves[v] = e < 0 || isKept(e) ? OnPath : Free;
    }
    freed += R.Kind[v] != SampleKind::Interior && R.Kind[v] != SampleKind::Tip && Moves[v] == Free;
  }
  for (const SamplePath& path : Samples.Paths)
  {
    for (std::size_t i = 0; i + 1 < path.Samples.size(); ++i)
    {
      if (Moves[path.Samples[i]] != Free && Moves[path.Samples[i + 1]] != Free)
      {
        KeptEdges.insert(EdgeKey(path.Samples[i], path.Samples[i + 1]));
      }
    }
  }
  for (Index v = 0; v < M.NumberOfVertices(); ++v) // (pinned vertices joined along a crease: JoinAlongInputEdges)
  {
    if (R.Kind[v] == SampleKind::Tip)
    {
      KeepEdgesAlongCreases(v);
    }
  }
  Stitching = true;
  return freed;
}

void Optimizer::OptimizationRound(RemeshOptimizationStatistics& stats)
{
  if (Stitching)
  {
    stats.FoldSwaps += SwapFolds();
  }
  stats.ShapeSwaps += SwapForShape();
  stats.ValenceSwaps += SwapForValence();
  stats.MeanDisplacement = Relax();
}

/// Moves vertex v as its kind and the pass allow; `moved`: the 3D distance.
void Optimizer::Move(Index v, double& moved)
{
  if (Stitching)
  {
    if (Moves[v] == Free)
    {
      MoveOnSurface(v, moved);
    }
    else if (Moves[v] == OnPath)
    {
      MoveOnPath(v, moved);
    }
  }
  else if (R.Kind[v] == SampleKind::Interior)
  {
    MoveInterior(v, moved);
  }
  else if (R.Kind[v] == SampleKind::Boundary)
  {
    MoveOnPath(v, moved);
  }
}

/// Asks for what moving v reads: its neighbours' positions and importance,
/// its input triangle's corners.
void Optimizer::Prefetch(Index v) const
{
  M.ForEachOutgoing(v, [&](Index h) {
    const Index w = M.Head(h);
    PrefetchKept(M.Points().data() + 3 * static_cast<std::int64_t>(w));
    if (!VertexImportance.empty())
    {
      PrefetchKept(&VertexImportance[w]);
    }
  });
  const Index t = R.Triangle[v];
  for (int k = 0; k < 3; ++k)
  {
    PrefetchKept(Points + 3 * static_cast<std::int64_t>(Topology.CornerVertex(3 * t + k)));
  }
}

/// One relaxation sweep over the vertices (section 4.4.3), colour by
/// colour; the mean 3D move.
double Optimizer::Relax()
{
  ColourVertices();
  std::vector<double> moved(M.NumberOfVertices(), 0.0);
  for (std::size_t c = 0; c + 1 < ColourOffsets.size(); ++c)
  {
    ParallelFor(ColourOffsets[c + 1] - ColourOffsets[c], NumberOfThreads,
      [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t i = begin; i < end; ++i)
        {
          if (i + 4 < end)
          {
            Prefetch(ColourVerticesList[ColourOffsets[c] + i + 4]);
          }
          const Index v = ColourVerticesList[ColourOffsets[c] + i];
          if (Active.empty() || Active[v])
          {
            Move(v, moved[v]);
          }
        }
      },
      {}, 0, 256);
  }
  double total = 0.0;
  for (double m : moved)
  {
    total += m;
  }
  return total / std::max<Index>(1, M.NumberOfVertices());
}

} // namespace detail

RemeshOptimizationStatistics OptimizeRemesh(Remesh& remesh, const MeshTopology& topology, const double* points,
  const AtlasResult& atlas, const SurfaceSamples& samples, const RemeshOptimizationOptions& options)
{
  RemeshOptimizationStatistics stats;
  if (!remesh.Error.empty())
  {
    return stats;
  }
  detail::Optimizer optimizer(
    remesh, topology, points, atlas, samples, options.Importance, options.Metric, options.Cache);
  optimizer.NumberOfThreads = options.NumberOfThreads;
  optimizer.OverRelaxation = std::max(1.0, options.OverRelaxation);
  const int rounds = std::max(0, options.Iterations) + std::max(0, options.StitchingIterations);
  for (int i = 0; i < rounds; ++i)
  {
    if (i == std::max(0, options.Iterations))
    {
      stats.FreedVertices = optimizer.BeginStitching(options.FeatureEdges);
    }
    // With a metric, the first half of the stitching rounds pull the
    // vertices towards a lattice aligned with it (LatticeShift), the rest
    // are Lloyd's, which keeps the lattice's orientation and evens it.
    const int stitched = i - std::max(0, options.Iterations);
    optimizer.LatticeWeight = options.Metric && stitched >= 0 && 2 * stitched < options.StitchingIterations ? 1.0 : 0.0;
    optimizer.OptimizationRound(stats);
  }
  if (rounds > std::max(0, options.Iterations) &&
    optimizer.RoundRimCorners(options.FeatureEdges, options.PinnedVertices, options.MaximumLineSag) > 0)
  {
    for (int i = 0; i < detail::RimRounds; ++i) // (the triangles beside the corners moved)
    {
      stats.ShapeSwaps += optimizer.SwapForShape();
      stats.ValenceSwaps += optimizer.SwapForValence();
      stats.MeanDisplacement = optimizer.Relax();
    }
  }
  if (rounds > 0)
  {
    stats.ShapeSwaps += optimizer.SwapSlivers();
  }
  if (rounds > std::max(0, options.Iterations))
  {
    stats.ShapeSwaps += optimizer.MendSlivers(20.0);
  }
  return stats;
}

} // namespace beltrami
