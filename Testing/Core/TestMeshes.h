// Analytic test surfaces for the core tests and benchmarks (VTK-free).
#pragma once

#include "Mesh/Laplacian.h"
#include "Mesh/MeshTopology.h"

#include "IO/OFFFormat.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace beltrami
{
namespace test
{

struct Mesh
{
  std::vector<double> Points; // xyz per vertex
  std::vector<Index> Triangles;

  Index NumberOfVertices() const { return static_cast<Index>(Points.size() / 3); }
  Eigen::Vector3d Point(Index i) const
  {
    return { Points[3 * i], Points[3 * i + 1], Points[3 * i + 2] };
  }
  void SetPoint(Index i, const Eigen::Vector3d& p)
  {
    for (int d = 0; d < 3; ++d)
    {
      Points[3 * i + d] = p[d];
    }
  }
  Index AddPoint(const Eigen::Vector3d& p)
  {
    Points.insert(Points.end(), { p[0], p[1], p[2] });
    return NumberOfVertices() - 1;
  }
  void AddTriangle(Index a, Index b, Index c) { Triangles.insert(Triangles.end(), { a, b, c }); }
  MeshTopology Topology(int threads = 0) const
  {
    return MeshTopology(NumberOfVertices(), IndexArray(Triangles.begin(), Triangles.end()), threads);
  }
  double TotalArea() const
  {
    double area = 0;
    for (std::size_t t = 0; t < Triangles.size(); t += 3)
    {
      const Eigen::Vector3d a = Point(Triangles[t]), b = Point(Triangles[t + 1]),
                            c = Point(Triangles[t + 2]);
      area += 0.5 * (b - a).cross(c - a).norm();
    }
    return area;
  }
};

/// A triangle mesh of Testing/Data (an OFF file); `error` says why when
/// it cannot be read or has a face that is not a triangle (then empty).
inline Mesh ReadMesh(const std::string& name, std::string& error)
{
  OFFMesh off;
  Mesh m;
  if (!ReadOFFFile(std::string(BELTRAMI_TEST_DATA_DIR) + "/" + name, off, error))
  {
    return m;
  }
  m.Points = off.Points;
  for (std::int64_t f = 0; f < off.NumberOfFaces(); ++f)
  {
    if (off.FaceOffsets[f + 1] - off.FaceOffsets[f] != 3)
    {
      error = name + ": face " + std::to_string(f) + " is not a triangle";
      return Mesh();
    }
    for (std::int64_t k = off.FaceOffsets[f]; k < off.FaceOffsets[f + 1]; ++k)
    {
      m.Triangles.push_back(static_cast<Index>(off.FaceIndices[k]));
    }
  }
  return m;
}

/// `a` and a copy of `b` moved by `shift`: two components.
inline Mesh Merged(Mesh a, const Mesh& b, const Eigen::Vector3d& shift)
{
  const Index offset = a.NumberOfVertices();
  for (Index v = 0; v < b.NumberOfVertices(); ++v)
  {
    a.AddPoint(b.Point(v) + shift);
  }
  for (const Index v : b.Triangles)
  {
    a.Triangles.push_back(v + offset);
  }
  return a;
}

/// An assembled Laplacian's graph copied into `offsets` and `neighbors`
/// (its own arrays point into the topology's edge table, which a test's
/// temporary topology takes with it).
inline void KeepGraph(GraphLaplacian& L, std::vector<std::int64_t>& offsets, std::vector<Index>& neighbors)
{
  const Index n = L.NumberOfVertices;
  offsets.assign(L.Offsets, L.Offsets + n + 1);
  neighbors.assign(L.Neighbors, L.Neighbors + offsets[n]);
  L.Offsets = offsets.data();
  L.Neighbors = neighbors.data();
}

/// Unit sphere from an octahedron, quadrisected and re-projected `levels`
/// times (thesis section 2.7.1): 6, 18, 66, 258, 1026, 4098, 16386 vertices.
inline Mesh OctahedronSphere(int levels, double radius = 1.0)
{
  Mesh m;
  const Eigen::Vector3d v[6] = { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 },
    { 0, 0, 1 }, { 0, 0, -1 } };
  for (const auto& p : v)
  {
    m.AddPoint(p);
  }
  const int f[8][3] = { { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 }, { 2, 0, 5 },
    { 1, 2, 5 }, { 3, 1, 5 }, { 0, 3, 5 } };
  for (const auto& t : f)
  {
    m.AddTriangle(t[0], t[1], t[2]);
  }
  for (int level = 0; level < levels; ++level)
  {
    std::map<std::pair<Index, Index>, Index> mid;
    auto midpoint = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end())
      {
        return it->second;
      }
      const Index id = m.AddPoint((m.Point(a) + m.Point(b)).normalized());
      mid.emplace(key, id);
      return id;
    };
    std::vector<Index> old;
    old.swap(m.Triangles);
    for (std::size_t t = 0; t < old.size(); t += 3)
    {
      const Index a = old[t], b = old[t + 1], c = old[t + 2];
      const Index ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      m.AddTriangle(a, ab, ca);
      m.AddTriangle(ab, b, bc);
      m.AddTriangle(ca, bc, c);
      m.AddTriangle(ab, bc, ca);
    }
  }
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    m.SetPoint(i, radius * m.Point(i).normalized());
  }
  return m;
}

/// Torus (R, r) on a nu x nv grid; `jitter` moves each vertex in parameter
/// space by up to jitter * cell size (the points stay on the torus).
/// Parameters per vertex are returned in uv (u around the axis, v around the tube).
inline Mesh Torus(double R, double r, int nu, int nv, double jitter, unsigned seed,
  std::vector<std::array<double, 2>>* uv = nullptr)
{
  Mesh m;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-jitter, jitter);
  const double du = 2 * M_PI / nu, dv = 2 * M_PI / nv;
  for (int i = 0; i < nu; ++i)
  {
    for (int j = 0; j < nv; ++j)
    {
      const double u = (i + d(rng)) * du, v = (j + d(rng)) * dv;
      m.AddPoint({ (R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
        r * std::sin(v) });
      if (uv)
      {
        uv->push_back({ u, v });
      }
    }
  }
  auto id = [&](int i, int j) { return static_cast<Index>(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i)
  {
    for (int j = 0; j < nv; ++j)
    {
      // Outward orientation.
      m.AddTriangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.AddTriangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return m;
}

/// Height field z = f(x, y) on [-h, h]^2 with n x n vertices, triangles
/// oriented with the +z normal.  jitter moves interior vertices in x, y by
/// up to jitter * spacing; randomDiagonals picks each quad's diagonal at random.
template <typename F>
Mesh HeightField(F&& f, double h, int n, double jitter, bool randomDiagonals, unsigned seed)
{
  Mesh m;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-jitter, jitter);
  const double step = 2 * h / (n - 1);
  for (int i = 0; i < n; ++i)
  {
    for (int j = 0; j < n; ++j)
    {
      double x = -h + i * step, y = -h + j * step;
      if (i > 0 && j > 0 && i < n - 1 && j < n - 1)
      {
        x += d(rng) * step;
        y += d(rng) * step;
      }
      m.AddPoint({ x, y, f(x, y) });
    }
  }
  std::bernoulli_distribution coin(0.5);
  for (int i = 0; i + 1 < n; ++i)
  {
    for (int j = 0; j + 1 < n; ++j)
    {
      const Index a = i * n + j, b = (i + 1) * n + j, c = (i + 1) * n + j + 1, e = i * n + j + 1;
      if (randomDiagonals && coin(rng))
      {
        m.AddTriangle(a, b, e);
        m.AddTriangle(b, c, e);
      }
      else
      {
        m.AddTriangle(a, b, c);
        m.AddTriangle(a, c, e);
      }
    }
  }
  return m;
}

/// Open cylinder of radius r along z, nu around x nz along, height length.
inline Mesh Cylinder(double r, double length, int nu, int nz)
{
  Mesh m;
  for (int k = 0; k < nz; ++k)
  {
    for (int i = 0; i < nu; ++i)
    {
      const double u = 2 * M_PI * i / nu;
      m.AddPoint({ r * std::cos(u), r * std::sin(u), length * k / (nz - 1) });
    }
  }
  for (int k = 0; k + 1 < nz; ++k)
  {
    for (int i = 0; i < nu; ++i)
    {
      const Index a = k * nu + i, b = k * nu + (i + 1) % nu, c = (k + 1) * nu + (i + 1) % nu,
                  e = (k + 1) * nu + i;
      m.AddTriangle(a, b, c); // outward
      m.AddTriangle(a, c, e);
    }
  }
  return m;
}

/// A flat, irregular triangulation of the unit square: jittered grid with
/// random diagonals, then some triangles split at a random interior point
/// (valence-3 vertices, many obtuse triangles).
inline Mesh FlatIrregular(int n, unsigned seed)
{
  Mesh m = HeightField([](double, double) { return 0.0; }, 0.5, n, 0.2, true, seed);
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  std::vector<Index> tris;
  tris.swap(m.Triangles);
  for (std::size_t t = 0; t < tris.size(); t += 3)
  {
    const Index a = tris[t], b = tris[t + 1], c = tris[t + 2];
    if ((t / 3) % 3 == 0)
    {
      double wa = u(rng), wb = u(rng) * (1 - wa);
      const Index p = m.AddPoint(wa * m.Point(a) + wb * m.Point(b) + (1 - wa - wb) * m.Point(c));
      m.AddTriangle(a, b, p);
      m.AddTriangle(b, c, p);
      m.AddTriangle(c, a, p);
    }
    else
    {
      m.AddTriangle(a, b, c);
    }
  }
  return m;
}


/// A flat disk whose ragged rim (n points, every other one 1% further out)
/// is fanned from one centre point through a ring of radius 0.5: long
/// slivers round a vertex of valence n, as a hole filled by a fan (a stiff
/// chain along the ring for the cotangent Laplacian: weights of about 300).
inline Mesh FannedDisk(int n)
{
  Mesh m;
  m.AddPoint({ 0.0, 0.0, 0.0 });
  for (double radius : { 0.5, 1.0 })
  {
    for (int i = 0; i < n; ++i)
    {
      const double a = 2.0 * M_PI * i / n, r = radius * (radius < 1.0 ? 1.0 : 1.0 + 0.01 * (i % 2));
      m.AddPoint({ r * std::cos(a), r * std::sin(a), 0.0 });
    }
  }
  for (int i = 0; i < n; ++i)
  {
    const int j = (i + 1) % n;
    m.AddTriangle(0, 1 + i, 1 + j);
    m.AddTriangle(1 + i, 1 + n + i, 1 + n + j);
    m.AddTriangle(1 + i, 1 + n + j, 1 + j);
  }
  return m;
}

/// Sphere of radius R made of latitude rings: `upper` rings of `upperCount`
/// points above the equator, `lower` rings of `lowerCount` below (figure
/// 3.10's two sampling rates), zipped together; outward orientation.
inline Mesh TwoRateSphere(double R, int upper, int upperCount, int lower, int lowerCount)
{
  Mesh m;
  const Index north = m.AddPoint({ 0, 0, R });
  std::vector<std::vector<Index>> rings;
  const auto ring = [&](double theta, int count, double offset) {
    std::vector<Index> r;
    for (int i = 0; i < count; ++i)
    {
      const double phi = 2 * M_PI * (i + offset) / count;
      r.push_back(m.AddPoint(
        { R * std::sin(theta) * std::cos(phi), R * std::sin(theta) * std::sin(phi), R * std::cos(theta) }));
    }
    rings.push_back(r);
  };
  for (int k = 1; k <= upper; ++k)
  {
    ring(0.5 * M_PI * k / upper, upperCount, 0.5 * (k % 2));
  }
  for (int k = 1; k < lower; ++k)
  {
    ring(0.5 * M_PI + 0.5 * M_PI * k / lower, lowerCount, 0.5 * (k % 2));
  }
  const Index south = m.AddPoint({ 0, 0, -R });
  const auto angle = [&](Index v) {
    const double a = std::atan2(m.Points[3 * v + 1], m.Points[3 * v]);
    return a < 0 ? a + 2 * M_PI : a;
  };
  const auto sorted = [&](std::vector<Index> r) {
    std::sort(r.begin(), r.end(), [&](Index a, Index b) { return angle(a) < angle(b); });
    return r;
  };
  // Zip two rings (a above b) by advancing on the one whose next point comes first.
  const auto zip = [&](const std::vector<Index>& a0, const std::vector<Index>& b0) {
    const std::vector<Index> a = sorted(a0), b = sorted(b0);
    const std::size_t na = a.size(), nb = b.size();
    std::size_t i = 0, j = 0;
    while (i < na || j < nb)
    {
      const double ta = i < na ? angle(a[(i + 1) % na]) + (i + 1 == na ? 2 * M_PI : 0) : 1e9;
      const double tb = j < nb ? angle(b[(j + 1) % nb]) + (j + 1 == nb ? 2 * M_PI : 0) : 1e9;
      if (ta <= tb)
      {
        m.AddTriangle(a[i % na], b[j % nb], a[(i + 1) % na]);
        ++i;
      }
      else
      {
        m.AddTriangle(a[i % na], b[j % nb], b[(j + 1) % nb]);
        ++j;
      }
    }
  };
  const std::vector<Index> first = sorted(rings.front()), last = sorted(rings.back());
  for (std::size_t i = 0; i < first.size(); ++i)
  {
    m.AddTriangle(north, first[i], first[(i + 1) % first.size()]);
  }
  for (std::size_t k = 0; k + 1 < rings.size(); ++k)
  {
    zip(rings[k], rings[k + 1]);
  }
  for (std::size_t i = 0; i < last.size(); ++i)
  {
    m.AddTriangle(south, last[(i + 1) % last.size()], last[i]);
  }
  return m;
}

/// Surface of the cube [-1, 1]^3 with n x n quads (split in two) per face,
/// outward orientation; vertices on edges and corners are shared.
inline Mesh CubeSurface(int n)
{
  Mesh m;
  std::map<std::array<long, 3>, Index> ids;
  const auto vertex = [&](const Eigen::Vector3d& p) {
    const std::array<long, 3> key = { std::lround(p[0] * n * 2), std::lround(p[1] * n * 2),
      std::lround(p[2] * n * 2) };
    auto it = ids.find(key);
    if (it != ids.end())
    {
      return it->second;
    }
    const Index id = m.AddPoint(p);
    ids.emplace(key, id);
    return id;
  };
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int side : { -1, 1 })
    {
      Eigen::Vector3d normal = Eigen::Vector3d::Zero(), u = Eigen::Vector3d::Zero(),
                      v = Eigen::Vector3d::Zero();
      normal[axis] = side;
      u[(axis + 1) % 3] = 1;
      v[(axis + 2) % 3] = 1;
      if (side < 0)
      {
        std::swap(u, v); // keep u x v = outward normal
      }
      std::vector<Index> grid;
      for (int i = 0; i <= n; ++i)
      {
        for (int j = 0; j <= n; ++j)
        {
          grid.push_back(vertex(normal + (2.0 * i / n - 1) * u + (2.0 * j / n - 1) * v));
        }
      }
      for (int i = 0; i < n; ++i)
      {
        for (int j = 0; j < n; ++j)
        {
          const Index a = grid[i * (n + 1) + j], b = grid[(i + 1) * (n + 1) + j],
                      c = grid[(i + 1) * (n + 1) + j + 1], d = grid[i * (n + 1) + j + 1];
          m.AddTriangle(a, b, c);
          m.AddTriangle(a, c, d);
        }
      }
    }
  }
  return m;
}

} // namespace test
} // namespace beltrami
