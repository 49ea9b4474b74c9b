#include "Drawing/LineDrawing.h"

#include "Drawing/ApparentRidges.h"
#include "Drawing/FaceZeroSets.h"
#include "Drawing/FieldSmoothing.h"
#include "Mesh/CurvatureDerivatives.h"
#include "Mesh/Curvatures.h"
#include "Mesh/MeshMeasures.h"
#include "Mesh/RingGeometry.h"
#include "Solvers/Partition.h"
#include "Support/Vectorization.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <utility>

namespace beltrami
{

namespace
{

constexpr double NaN = std::numeric_limits<double>::quiet_NaN();
constexpr double Degree = M_PI / 180.0;
/// The points in double precision into `copy`, and in the same pass the
/// bounding box of the used ones (finite, in a triangle) into box: -lo, hi.
template <typename T>
void CopyPoints(const MeshTopology& topology, const T* points, int numThreads, double* copy, double* box)
{
  std::fill(box, box + 6, -std::numeric_limits<double>::infinity());
  std::mutex merge;
  ParallelFor(topology.NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    double part[6];
    std::fill(part, part + 6, -std::numeric_limits<double>::infinity());
    for (std::int64_t i = begin; i < end; ++i)
    {
      std::copy(points + 3 * i, points + 3 * i + 3, copy + 3 * i);
      const Vec3 p = Point(copy, static_cast<Index>(i));
      if (p.allFinite() && topology.Valence(static_cast<Index>(i)) > 0)
      {
        for (int k = 0; k < 3; ++k)
        {
          part[k] = std::max(part[k], -p[k]);
          part[k + 3] = std::max(part[k + 3], p[k]);
        }
      }
    }
    const std::lock_guard<std::mutex> lock(merge);
    for (int k = 0; k < 6; ++k)
    {
      box[k] = std::max(box[k], part[k]);
    }
  });
}

} // namespace

template <typename T>
void LineDrawingGeometry::Build(const MeshTopology& topology, const T* points, int numThreads,
  std::shared_ptr<const Partition> split, const FieldSmoothingOptions& smoothing)
{
  const Index n = topology.NumberOfVertices();
  Thresholded[0].Valid = Thresholded[1].Valid = CreaseEdges.Valid = false;
  Triangles.assign(topology.TriangleList().begin(), topology.TriangleList().end());
  Split = std::move(split);
  GlobalIds.clear();
  DrawnFaces.clear();
  if (Split)
  {
    GlobalIds.resize(n);
    for (Index i = 0; i < n; ++i)
    {
      GlobalIds[i] = Split->GlobalRow(i);
    }
    KeyIds = Split->TotalRows();
    DrawnFaces.resize(Triangles.size() / 3);
    for (std::size_t f = 0; f < DrawnFaces.size(); ++f)
    {
      DrawnFaces[f] = Split->CountsTriangle(Triangles[3 * f], Triangles[3 * f + 1], Triangles[3 * f + 2]);
    }
  }
  // (ComputeCurvatures writes every vertex of its outputs.)
  for (auto* field : { &Points, &Normals, &E1, &E2 })
  {
    field->resize(3 * static_cast<std::size_t>(n));
  }
  K1.resize(n);
  K2.resize(n);
  SharpestCosine.resize(n);
  double box[6]; // -lo, hi of the used points (for the feature size)
  CopyPoints(topology, points, numThreads, Points.data(), box);
  if (Split)
  {
    Split->Max(box, 6);
  }
  const Vec3 extent(box[3] + box[0], box[4] + box[1], box[5] + box[2]);
  DefaultFeatureSize = extent.allFinite() ? 0.01 * extent.norm() : 0.0;
  SmoothingWarning.clear();
  FairedPoints.clear();
  NearSharpestCosine.clear();
  Smoothed = false;
  if (smoothing.Amount > 0.0)
  {
    FindFeatureEdges(topology, numThreads, true); // (the surface's creases, not the copy's)
    Fair(topology, numThreads, smoothing);
  }
  CurvatureOptions options;
  options.NumberOfThreads = numThreads;
  CurvatureOutputs out;
  out.Normals = Normals.data();
  out.MaximumCurvature = K1.data();
  out.MinimumCurvature = K2.data();
  out.PrincipalDirection1 = E1.data();
  out.PrincipalDirection2 = E2.data();
  if (!Smoothed)
  {
    out.SharpestEdgeCosine = SharpestCosine.data(); // (the regular vertices': FindFeatureEdges does the others)
    ComputeCurvatures(topology, points, options, out);
  }
  else
  {
    ComputeCurvatures(topology, FairedPoints.data(), options, out);
  }
  ShareCurvatures(topology);
  Derivatives.resize(4 * static_cast<std::size_t>(n)); // (every vertex written)
  const CurvatureTensors tensors{ Normals.data(), K1.data(), K2.data(), E1.data(), E2.data() };
  ComputeCurvatureDerivatives(topology, FieldPoints(), tensors, Derivatives.data(), numThreads);
  if (Split)
  {
    Split->UpdateGhosts(Derivatives.data(), 4);
  }
  Threads = numThreads;
  RidgesFound = false; // (found when first drawn: RidgeCandidates)
  Occlusion.reset();    // (built when first asked for: Occluders)
  Ridges[0] = SegmentList();
  Ridges[1] = SegmentList();
  if (!Smoothed)
  {
    FindFeatureEdges(topology, numThreads, false); // (collective: Smoothed is the same everywhere)
  }
}

void LineDrawingGeometry::Fair(const MeshTopology& topology, int numThreads, const FieldSmoothingOptions& smoothing)
{
  const double size = smoothing.FeatureSize > 0.0 ? smoothing.FeatureSize : DefaultFeatureSize;
  const std::vector<double> faired =
    FairedCopy(topology, Points.data(), smoothing.Amount * size, numThreads, Split.get(), SmoothingWarning);
  FairedPoints.assign(faired.begin(), faired.end());
  Smoothed = SmoothingWarning.empty(); // (the same on every process; a process may hold no points)
  if (!Smoothed)
  {
    return;
  }
  // The faired copy rounds a crease over about the smoothing's length, and
  // its curvatures there are the rounding's: the zone that AtCrease keeps
  // the curvature lines out of grows by as many rings.
  const double rings = std::ceil(smoothing.Amount * size / MeanEdgeLength(topology, Points.data(), Split.get()));
  SpreadCreases(topology, rings, numThreads);
}

void LineDrawingGeometry::SpreadCreases(const MeshTopology& topology, double rings, int numThreads)
{
  const MeshTopology::VertexGraph& graph = topology.Graph();
  const double vertices = Split ? static_cast<double>(Split->TotalRows()) : NumberOfVertices();
  std::vector<double> near(SharpestCosine.begin(), SharpestCosine.end()), next(near.size());
  for (double ring = 0.0; ring < std::min(rings, vertices); ++ring) // (no graph is wider than its vertices)
  {
    ParallelFor(NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t a = begin; a < end; ++a)
      {
        next[a] = near[a];
        for (std::int64_t k = graph.NeighborOffsets[a]; k < graph.NeighborOffsets[a + 1]; ++k)
        {
          next[a] = std::min(next[a], near[graph.Neighbors[k]]);
        }
      }
    });
    if (Split)
    {
      Split->UpdateGhosts(next.data(), 1);
    }
    near.swap(next);
  }
  NearSharpestCosine.assign(near.begin(), near.end());
}

template void LineDrawingGeometry::Build<float>(
  const MeshTopology&, const float*, int, std::shared_ptr<const Partition>, const FieldSmoothingOptions&);
template void LineDrawingGeometry::Build<double>(
  const MeshTopology&, const double*, int, std::shared_ptr<const Partition>, const FieldSmoothingOptions&);

void LineDrawingGeometry::ShareCurvatures(const MeshTopology& topology)
{
  const Index n = NumberOfVertices();
  if (Split)
  {
    // A ghost point's star is cut at the edge of the ring: its owner's values.
    Split->UpdateGhosts(Normals.data(), 3);
    Split->UpdateGhosts(E1.data(), 3);
    Split->UpdateGhosts(E2.data(), 3);
    Split->UpdateGhosts(K1.data(), 1);
    Split->UpdateGhosts(K2.data(), 1);
  }
  double undefined = 0.0;
  for (Index i = 0; i < n; ++i)
  {
    undefined += (!Split || Split->IsOwned(i)) && topology.Valence(i) > 0 && !std::isfinite(K1[i]);
  }
  UndefinedVertices = static_cast<Index>(Split ? Split->Sum(undefined) : undefined);
}

const SegmentList& LineDrawingGeometry::RidgeCandidates(bool valleys) const
{
  if (!RidgesFound)
  {
    FindRidges();
    RidgesFound = true;
  }
  return Ridges[valleys ? 1 : 0];
}

void LineDrawingGeometry::FindRidges() const
{
  const int numThreads = Threads;
  // A valley is a ridge of -kappa_2 along e2: D_e2(-kappa_2) = -C(e2,e2,e2).
  // What the faces read of a vertex, side by side in single precision (from
  // three arrays read at random, the cache misses were most of the faces'
  // time; 32 bytes, two vertices a cache line): e1, D_e1 kappa_1, e2,
  // D_e2 kappa_2.  (Single precision moves a crossing by about 1e-7 of its
  // edge.)
  constexpr int Stride = 8;
  constexpr Index Ahead = 8; // (faces whose frames are asked for ahead: random reads)
  UninitializedVector<float> frames(Stride * static_cast<std::size_t>(NumberOfVertices())); // (written whole)
  ParallelFor(NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i)
    {
      float* frame = frames.data() + Stride * i;
      std::copy(E1.data() + 3 * i, E1.data() + 3 * i + 3, frame);
      frame[3] = static_cast<float>(Derivatives[4 * i]);
      std::copy(E2.data() + 3 * i, E2.data() + 3 * i + 3, frame + 4);
      frame[7] = static_cast<float>(Derivatives[4 * i + 3]);
    }
  });
  auto lists = CollectSegments(NumberOfFaces(), numThreads, 2, [&](Index f, std::vector<LineSegment>* out) {
    const Index* v = Triangles.data() + 3 * static_cast<std::int64_t>(f);
    if (f + Ahead < NumberOfFaces())
    {
      for (int k = 0; k < 3; ++k)
      {
        __builtin_prefetch(frames.data() + Stride * static_cast<std::int64_t>(v[3 * Ahead + k]));
        __builtin_prefetch(FieldPoints() + 3 * static_cast<std::int64_t>(v[3 * Ahead + k]));
      }
    }
    for (int valleys = 0; valleys < 2; ++valleys)
    {
      Vec3 e[3];
      double g[3];
      for (int k = 0; k < 3; ++k)
      {
        const float* frame = frames.data() + Stride * static_cast<std::int64_t>(v[k]) + 4 * valleys;
        e[k] = Vec3(frame[0], frame[1], frame[2]);
        // The principal directions are lines, not vectors: turned like the first corner's.
        const double flip = k > 0 && e[k].dot(e[0]) < 0.0 ? -1.0 : 1.0;
        e[k] *= flip;
        g[k] = (valleys ? -flip : flip) * frame[3];
      }
      LineSegment s;
      if (!Draws(f) || !ZeroCrossing(*this, f, v, g, s))
      {
        continue;
      }
      const double* at = FieldPoints();
      const Vec3 p[3] = { Point(at, v[0]), Point(at, v[1]), Point(at, v[2]) };
      // A maximum along e: the derivative decreases along e.
      if (FaceGradient(p, g).dot(e[0] + e[1] + e[2]) < 0.0)
      {
        out[valleys].push_back(s);
      }
    }
  },
    { FacesPerBlock / 4, FacesPerBlock / 4, 0 }); // (about a sixth of the faces on a scan)
  Ridges[0] = std::move(lists[0]);
  Ridges[1] = std::move(lists[1]);
}

float LineDrawingGeometry::CreaseCosine(double angle)
{
  return static_cast<float>(std::cos(angle * Degree));
}

LineSegment LineDrawingGeometry::EdgeSegment(Index a, Index b, Index face) const
{
  LineSegment s;
  s.Face = face;
  for (int end = 0; end < 2; ++end)
  {
    const Index vertex = end == 0 ? a : b;
    s.End[end].Key = VertexKey(*this, vertex);
    for (int k = 0; k < 3; ++k)
    {
      s.End[end].W[k] = Triangles[3 * static_cast<std::int64_t>(face) + k] == vertex ? 1.0 : 0.0;
    }
  }
  return s;
}

Vec3 LineDrawingGeometry::FaceCross(Index f, Index a) const
{
  const Index* v = Triangles.data() + 3 * static_cast<std::int64_t>(f);
  const int k = v[0] == a ? 0 : (v[1] == a ? 1 : 2);
  const Vec3 p = Point(Points.data(), a);
  return (Point(Points.data(), v[(k + 1) % 3]) - p).cross(Point(Points.data(), v[(k + 2) % 3]) - p);
}

void LineDrawingGeometry::FindFeatureEdges(const MeshTopology& topology, int numThreads, bool everyVertex)
{
  // SharpestCosine has the values of the vertices with a regular fan
  // (ComputeCurvatures); here the others' from their edges
  // (MeshTopology::VertexEdges), and the boundary edges to larger ids drawn
  // here, in (vertex, neighbour) order.
  struct Edge
  {
    Index A, B, Face;
  };
  const auto boundary = CollectSegments<Edge>(NumberOfVertices(), numThreads, 1, [&](Index a, std::vector<Edge>* out) {
    if (topology.VertexFlags(a) == VertexRegular && !everyVertex)
    {
      return;
    }
    thread_local std::vector<MeshTopology::VertexEdge> edges;
    topology.VertexEdges(a, edges);
    double lowest = 1.0;
    for (const MeshTopology::VertexEdge& e : edges)
    {
      if (e.Faces == 1)
      {
        // Split: each edge drawn once, where the whole star of an end is
        // (so that a cut through the ring is no boundary).
        if (e.Neighbor > a && (!Split || Split->CountsEdge(a, e.Neighbor)))
        {
          out[0].push_back({ a, e.Neighbor, e.Opposite[0] / 3 });
        }
      }
      else if (e.Faces == 2)
      {
        const double cosine = NormalCosine(FaceCross(e.Opposite[0] / 3, a), FaceCross(e.Opposite[1] / 3, a));
        lowest = cosine < lowest ? cosine : lowest; // (NaN: left out)
      }
    }
    SharpestCosine[a] = static_cast<float>(lowest);
  })[0];
  if (Split)
  {
    std::vector<double> sharpest(SharpestCosine.begin(), SharpestCosine.end());
    Split->UpdateGhosts(sharpest.data(), 1); // (a ghost's star is cut)
    std::copy(sharpest.begin(), sharpest.end(), SharpestCosine.begin());
  }
  BoundaryEdges.clear();
  for (const Edge& e : boundary)
  {
    BoundaryEdges.push_back(EdgeSegment(e.A, e.B, e.Face));
  }
}

const LineDrawingGeometry::CreaseList& LineDrawingGeometry::Creases(double angle) const
{
  const float creaseCosine = CreaseCosine(angle);
  if (CreaseEdges.Valid && CreaseEdges.Cosine == creaseCosine)
  {
    return CreaseEdges;
  }
  // The edges (a < b) of the faces whose lower end a has an edge sharper
  // than the angle (few: a scan of the faces, no edge table; none on most
  // smooth surfaces, found by a scan of the vertices), then those of two
  // faces, sorted, tested.
  CreaseEdges.Edges.clear();
  CreaseEdges.Angles.clear();
  CreaseEdges.Cosine = creaseCosine;
  CreaseEdges.Valid = true;
  if (std::none_of(SharpestCosine.begin(), SharpestCosine.end(), [&](float c) { return c < creaseCosine; }))
  {
    return CreaseEdges;
  }
  struct Edge
  {
    Index A, B, Face;
    bool operator<(const Edge& o) const { return A != o.A ? A < o.A : (B != o.B ? B < o.B : Face < o.Face); }
  };
  auto candidates = CollectSegments<Edge>(NumberOfFaces(), Threads, 1, [&](Index f, std::vector<Edge>* out) {
    const Index* v = Triangles.data() + 3 * static_cast<std::int64_t>(f);
    for (int k = 0; k < 3; ++k)
    {
      const Index a = std::min(v[k], v[(k + 1) % 3]), b = std::max(v[k], v[(k + 1) % 3]);
      if (SharpestCosine[a] < creaseCosine)
      {
        out[0].push_back({ a, b, f });
      }
    }
  })[0];
  std::sort(candidates.begin(), candidates.end());
  for (std::size_t g = 0; g < candidates.size();)
  {
    const Edge& e = candidates[g];
    std::size_t h = g + 1;
    while (h < candidates.size() && candidates[h].A == e.A && candidates[h].B == e.B)
    {
      ++h;
    }
    if (h - g == 2 && (!Split || Split->CountsEdge(e.A, e.B)))
    {
      const double cosine = NormalCosine(FaceCross(e.Face, e.A), FaceCross(candidates[g + 1].Face, e.A));
      if (static_cast<float>(cosine) < creaseCosine)
      {
        CreaseEdges.Edges.push_back(EdgeSegment(e.A, e.B, e.Face));
        CreaseEdges.Angles.push_back(std::acos(std::clamp(cosine, -1.0, 1.0)) / Degree);
      }
    }
    g = h;
  }
  return CreaseEdges;
}

namespace
{

/// Bits of a vertex's view fields (n.v and kappa_r): finite, >= 0.
enum SignBits : std::uint8_t
{
  NdotVFinite = 1,
  NdotVPositive = 2,
  RadialFinite = 4,
  RadialPositive = 8
};

/// The bits of a field's value (finite, and >= 0 as ZeroCrossing tests it).
inline std::uint8_t SignOf(double value, std::uint8_t finite, std::uint8_t positive)
{
  return std::isfinite(value) ? static_cast<std::uint8_t>(finite | (value >= 0.0 ? positive : 0)) : 0;
}

/// Whether a field with these bits (finite, positive) can cross zero in a
/// face whose corners' bits are and-ed in `all` and or-ed in `any`: all
/// three finite, signs mixed (ZeroCrossing's early outs, from one byte per
/// corner instead of the field's doubles).
inline bool MayCross(std::uint8_t all, std::uint8_t any, std::uint8_t finite, std::uint8_t positive)
{
  return (all & finite) && (any & positive) && !(all & positive);
}

/// The per-vertex quantities of vertices [begin, end) of a view (see the
/// header's conventions; Perspective: from the eye, else along `toward`,
/// the unit vector to the viewer), and their SignBits.  Branch-free, so
/// that it vectorizes: where the radial direction is undefined (the surface
/// faces the viewer) kappa_r and its derivative are NaN.
template <bool Perspective>
CLONES void ViewFieldRange(std::int64_t begin, std::int64_t end, const double* __restrict points,
  const double* __restrict normals, const double* __restrict e1, const double* __restrict e2,
  const double* __restrict k1, const double* __restrict k2, const double* __restrict derivatives, const double* eye,
  const double* toward, double* __restrict ndotv, double* __restrict kr, double* __restrict drkr,
  std::uint8_t* __restrict signs)
{
  const double ex = eye[0], ey = eye[1], ez = eye[2], tx = toward[0], ty = toward[1], tz = toward[2];
  for (std::int64_t i = 0; i < end - begin; ++i)
  {
    const std::int64_t j = 3 * (begin + i), k = begin + i; // (indices, not pointers: they vectorize)
    const double dx = ex - points[j], dy = ey - points[j + 1], dz = ez - points[j + 2];
    const double dd = dx * dx + dy * dy + dz * dz;
    const double length = dd > 0.0 ? std::sqrt(dd) : 1.0;
    const double vx = Perspective ? dx / length : tx, vy = Perspective ? dy / length : ty,
                 vz = Perspective ? dz / length : tz;
    const double nx = normals[j], ny = normals[j + 1], nz = normals[j + 2];
    const double nv = nx * vx + ny * vy + nz * vz;
    const double wx = vx - nv * nx, wy = vy - nv * ny, wz = vz - nv * nz;
    const double sine = std::sqrt(wx * wx + wy * wy + wz * wz);
    const double r1 = wx * e1[j] + wy * e1[j + 1] + wz * e1[j + 2], r2 = wx * e2[j] + wy * e2[j + 1] + wz * e2[j + 2];
    const double rr = std::sqrt(r1 * r1 + r2 * r2); // (unit-sized: no hypot)
    const double r[2] = { r1 / rr, r2 / rr };
    const double radial = k1[k] * r[0] * r[0] + k2[k] * r[1] * r[1];
    const double tau = (k2[k] - k1[k]) * r[0] * r[1];
    const double c[4] = { derivatives[4 * k], derivatives[4 * k + 1], derivatives[4 * k + 2], derivatives[4 * k + 3] };
    const double derivative = EvaluateCubicForm(c, r, r, r) - 2.0 * (nv / sine) * tau * tau;
    // NaN where the radial direction is undefined (added, not selected:
    // GCC 12 does not vectorize the select).
    const double undefined = sine > 1e-9 ? 0.0 : NaN;
    ndotv[k] = nv;
    kr[k] = radial + undefined;
    drkr[k] = derivative + undefined;
    signs[k] =
      static_cast<std::uint8_t>(SignOf(nv, NdotVFinite, NdotVPositive) | SignOf(kr[k], RadialFinite, RadialPositive));
  }
}

/// The per-vertex quantities of a view, and their SignBits.
void ComputeViewFields(const LineDrawingGeometry& geo, const LineView& view, int numThreads, double* ndotv,
  double* kr, double* drkr, std::uint8_t* signs)
{
  const Vec3 toward = -view.Direction.normalized();
  ParallelFor(geo.NumberOfVertices(), numThreads, [&](std::int64_t begin, std::int64_t end) {
    (view.Perspective ? ViewFieldRange<true> : ViewFieldRange<false>)(begin, end, geo.FieldPoints(),
      geo.Normals.data(), geo.E1.data(), geo.E2.data(), geo.K1.data(), geo.K2.data(), geo.Derivatives.data(),
      view.Position.data(), toward.data(), ndotv, kr, drkr, signs);
  });
}


/// Appends `segments` of `type` to `out` with their ends resolved (see
/// ViewSegments; strength(segment, corners, values) gives a segment's
/// corner strengths).
template <typename Strength>
void Resolve(const LineDrawingGeometry& geo, const SegmentList& segments, LineType type,
  Strength&& strength, ViewSegments& out, int threads)
{
  std::vector<std::int64_t>& keys = out.Keys[static_cast<int>(type)];
  std::vector<double>& ends = out.Ends[static_cast<int>(type)];
  std::vector<Index>& faces = out.Faces[static_cast<int>(type)];
  const std::size_t first = keys.size(); // (in place, in parallel: each segment its own slots)
  keys.resize(first + 2 * segments.size());
  ends.resize(ViewSegments::ValuesPerEnd * keys.size());
  faces.resize(keys.size() / 2);
  ParallelFor(static_cast<std::int64_t>(segments.size()), threads, [&](std::int64_t begin, std::int64_t last) {
    for (std::int64_t i = begin; i < last; ++i)
    {
      const LineSegment& s = segments[i];
      const Index* v = geo.Triangles.data() + 3 * static_cast<std::int64_t>(s.Face);
      double corners[3];
      strength(static_cast<Index>(i), v, corners);
      faces[first / 2 + i] = s.Face;
      for (int e = 0; e < 2; ++e)
      {
        const LineEnd& end = s.End[e];
        Vec3 p = Vec3::Zero(), n = Vec3::Zero(), q = Vec3::Zero();
        for (int k = 0; k < 3; ++k)
        {
          p += end.W[k] * Point(geo.Points.data(), v[k]);
          n += end.W[k] * Point(geo.Normals.data(), v[k]);
          q += end.W[k] * Point(geo.FieldPoints(), v[k]);
        }
        n.normalize();
        const std::size_t at = first + 2 * static_cast<std::size_t>(i) + e;
        keys[at] = end.Key;
        const double values[ViewSegments::ValuesPerEnd] = { p[0], p[1], p[2], n[0], n[1], n[2],
          Interpolate(end, corners), q[0], q[1], q[2] };
        std::copy(values, values + ViewSegments::ValuesPerEnd, ends.begin() + ViewSegments::ValuesPerEnd * at);
      }
    }
  });
}

/// The feature size of a drawing: the option's, else the automatic one.
double FeatureSizeOf(const LineDrawingGeometry& geo, const LineDrawingOptions& options)
{
  return options.FeatureSize > 0.0 ? options.FeatureSize : geo.AutomaticFeatureSize();
}

} // namespace

const SegmentList& LineDrawingGeometry::ThresholdedRidges(bool valleys, double size,
  const LineDrawingOptions& options) const
{
  RidgeCache& cache = Thresholded[valleys ? 1 : 0];
  const double threshold = options.RidgeThreshold * HysteresisFactor(options); // (the lower one)
  if (cache.Valid && cache.Size == size && cache.Threshold == threshold &&
    cache.AvoidCreases == options.AvoidCreases && (!options.AvoidCreases || cache.CreaseAngle == options.CreaseAngle))
  {
    return cache.Kept;
  }
  cache.Kept.clear();
  const float creaseCosine = CreaseCosine(options.CreaseAngle);
  for (LineSegment s : RidgeCandidates(valleys))
  {
    if (options.AvoidCreases && AtCrease(s.Face, creaseCosine))
    {
      continue;
    }
    double test[3], k[3];
    Corners(Triangles, s.Face, valleys ? K2.data() : K1.data(), k);
    for (int c = 0; c < 3; ++c)
    {
      test[c] = (valleys ? -k[c] : k[c]) * size - threshold;
    }
    if (Clip(s, test))
    {
      cache.Kept.push_back(s);
    }
  }
  cache.Valid = true;
  cache.Size = size;
  cache.Threshold = threshold;
  cache.AvoidCreases = options.AvoidCreases;
  cache.CreaseAngle = options.CreaseAngle;
  return cache.Kept;
}

namespace
{

/// The segments of the faces this process draws (LineDrawingGeometry::Draws)
/// for a view's fields and their SignBits: contours, suggestive contours,
/// suggestive highlights (three lists, in face order).
std::vector<SegmentList> FaceSegments(const LineDrawingGeometry& geo, const LineDrawingOptions& options,
  double size, const double* ndotv, const double* kr, const double* drkr, const std::vector<std::uint8_t>& signs)
{
  const bool* draw = options.Draw;
  const bool radial =
    draw[int(LineType::SuggestiveContour)] || draw[int(LineType::SuggestiveHighlight)];
  const double cosAngle = std::cos(options.SuggestiveAngle * Degree);
  const float creaseCosine = LineDrawingGeometry::CreaseCosine(options.CreaseAngle);
  const double hysteresis = HysteresisFactor(options);
  const double scale = size * size;
  return CollectSegments(geo.NumberOfFaces(), options.NumberOfThreads, 3,
    [&](Index f, std::vector<LineSegment>* out) {
      const Index* v = geo.Triangles.data() + 3 * static_cast<std::int64_t>(f);
      if (!geo.Draws(f))
      {
        return;
      }
      // Most faces cross neither zero set: one byte per corner tells.
      const std::uint8_t all = signs[v[0]] & signs[v[1]] & signs[v[2]], any = signs[v[0]] | signs[v[1]] | signs[v[2]];
      const bool contour = draw[int(LineType::Contour)] && MayCross(all, any, NdotVFinite, NdotVPositive);
      if (!contour && !(radial && MayCross(all, any, RadialFinite, RadialPositive)))
      {
        return;
      }
      double nv[3], k[3];
      Corners(geo.Triangles, f, ndotv, nv);
      LineSegment s;
      if (contour && ZeroCrossing(geo, f, v, nv, s))
      {
        out[0].push_back(s);
      }
      Corners(geo.Triangles, f, kr, k);
      if (!radial || !ZeroCrossing(geo, f, v, k, s) || (options.AvoidCreases && geo.AtCrease(f, creaseCosine)))
      {
        return;
      }
      double d[3], facing[3], front[3];
      Corners(geo.Triangles, f, drkr, d);
      for (int c = 0; c < 3; ++c)
      {
        facing[c] = cosAngle - nv[c];
        front[c] = options.DropBackFacing ? nv[c] : 1.0;
      }
      for (int list = 1; list <= 2; ++list)
      {
        if (!draw[list])
        {
          continue;
        }
        double test[3];
        for (int c = 0; c < 3; ++c)
        {
          test[c] = (list == 1 ? d[c] : -d[c]) * scale - options.SuggestiveThreshold * hysteresis;
        }
        LineSegment piece = s;
        if (Clip(piece, test) && Clip(piece, facing) && Clip(piece, front))
        {
          out[list].push_back(piece);
        }
      }
    });

}

/// Ridges (valleys: valleys): the candidates past the threshold (kept by
/// the geometry) clipped by the view.
SegmentList ClipRidges(
  const LineDrawingGeometry& geo, const LineDrawingOptions& options, double size, const double* ndotv, bool valleys)
{
  const SegmentList& candidates = geo.ThresholdedRidges(valleys, size, options);
  if (!options.DropBackFacing)
  {
    return candidates;
  }
  // (The blocks of CollectSegments over the candidates: in parallel, in their order.)
  return std::move(CollectSegments(static_cast<Index>(candidates.size()), options.NumberOfThreads, 1,
    [&](Index i, std::vector<LineSegment>* out) {
      LineSegment s = candidates[i];
      double nv[3];
      Corners(geo.Triangles, s.Face, ndotv, nv);
      if (Clip(s, nv))
      {
        out[0].push_back(s);
      }
    })[0]);
}

/// Appends the edges sharper than the crease angle that this process draws.
void ResolveCreases(const LineDrawingGeometry& geo, const LineDrawingOptions& options, ViewSegments& segments)
{
  const LineDrawingGeometry::CreaseList& creases = geo.Creases(options.CreaseAngle);
  Resolve(geo, creases.Edges, LineType::Crease,
    [&](Index s, const Index*, double* c) { c[0] = c[1] = c[2] = creases.Angles[s]; }, segments,
    options.NumberOfThreads);
}

} // namespace

ViewSegments CollectViewSegments(const LineDrawingGeometry& geo, const LineView& view,
  const LineDrawingOptions& options, const ViewFields& fields)
{
  const Index n = geo.NumberOfVertices();
  const double size = FeatureSizeOf(geo, options);
  std::vector<double> own[3];
  double* field[3] = { fields.NdotV, fields.RadialCurvature, fields.RadialCurvatureDerivative };
  for (int k = 0; k < 3; ++k)
  {
    if (!field[k])
    {
      own[k].resize(n);
      field[k] = own[k].data();
    }
  }
  const double *ndotv = field[0], *kr = field[1], *drkr = field[2];
  std::vector<std::uint8_t> signs(n);
  ComputeViewFields(geo, view, options.NumberOfThreads, field[0], field[1], field[2], signs.data());

  const bool* draw = options.Draw;
  const double scale = size * size;
  const auto lists = FaceSegments(geo, options, size, ndotv, kr, drkr, signs);
  ViewSegments segments;
  const auto one = [](Index, const Index*, double* c) { c[0] = c[1] = c[2] = 1.0; };
  const auto vertexStrength = [](const double* values, double factor) {
    return [=](Index, const Index* v, double* c) {
      for (int k = 0; k < 3; ++k)
      {
        c[k] = factor * values[v[k]];
      }
    };
  };
  const int threads = options.NumberOfThreads;
  Resolve(geo, lists[0], LineType::Contour, one, segments, threads);
  Resolve(geo, lists[1], LineType::SuggestiveContour, vertexStrength(drkr, scale), segments, threads);
  Resolve(geo, lists[2], LineType::SuggestiveHighlight, vertexStrength(drkr, -scale), segments, threads);
  if (draw[int(LineType::Ridge)])
  {
    Resolve(geo, ClipRidges(geo, options, size, ndotv, false), LineType::Ridge, vertexStrength(geo.K1.data(), size),
      segments, threads);
  }
  if (draw[int(LineType::Valley)])
  {
    Resolve(geo, ClipRidges(geo, options, size, ndotv, true), LineType::Valley,
      vertexStrength(geo.K2.data(), -size), segments, threads);
  }
  if (draw[int(LineType::Boundary)])
  {
    Resolve(geo, geo.BoundaryEdges, LineType::Boundary, one, segments, threads);
  }
  if (draw[int(LineType::Crease)])
  {
    ResolveCreases(geo, options, segments);
  }
  if (draw[int(LineType::ApparentRidge)])
  {
    const ApparentCurvature apparent = ComputeApparentCurvature(geo, view, threads);
    Resolve(geo, ApparentRidgeSegments(geo, apparent, options, size), LineType::ApparentRidge,
      vertexStrength(apparent.Q1.data(), size), segments, threads);
  }
  return segments;
}

LineSet DrawLines(const LineDrawingGeometry& geo, const LineView& view, const LineDrawingOptions& options,
  const ViewFields& fields)
{
  ViewSegments segments = CollectViewSegments(geo, view, options, fields);
  if (geo.Split)
  {
    segments = GatherViewSegments(segments, geo); // (collective)
    if (geo.Split->Rank() != 0)
    {
      return LineSet();
    }
  }
  return ChainViewSegments(segments, options, FeatureSizeOf(geo, options));
}

} // namespace beltrami
