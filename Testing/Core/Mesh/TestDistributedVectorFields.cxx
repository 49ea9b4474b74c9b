// The vector field decomposition split over MPI processes
// (Mesh/VectorFields.h's DecomposeVectorField with a Partition) against the
// serial decomposition of the whole surface: run by ctest under mpirun on
// 1, 2 and 3 processes with the other distributed solves
// (TestPartition.cxx).
#include "Mesh/VectorFields.h"
#include "Solvers/Partition.h"
#include "Solvers/TestMPI.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

using namespace beltrami;

namespace
{

/// A surface split over the processes as the filters split it: process p
/// holds the triangles given to it (its piece) and the rings around them
/// (every triangle touching a point of its piece), so that the owner of a
/// point (the lowest process whose piece has it) holds its whole star.  A
/// process's rows are its triangles' points, in ascending order of their
/// ids in the whole surface.
struct SurfacePiece
{
  std::vector<Index> Global;    ///< local row -> point of the whole surface
  std::vector<Index> Triangles; ///< local rows, 3 per triangle: the piece's, then the ring's
  std::vector<Index> WholeTriangle;
  std::vector<int> OwnerRank;
  std::vector<Index> OwnerRow;
  std::vector<double> Points;

  /// `rankOf`: per triangle of the whole surface (`triangles`, `points`),
  /// the process whose piece it is.
  SurfacePiece(const std::vector<Index>& triangles, const std::vector<double>& points,
    const std::vector<int>& rankOf, int rank, int size)
  {
    const std::size_t nt = rankOf.size();
    const Index nv = static_cast<Index>(points.size() / 3);
    std::vector<int> owner(nv, size); // the lowest process whose piece has the point
    for (std::size_t t = 0; t < nt; ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        owner[triangles[3 * t + k]] = std::min(owner[triangles[3 * t + k]], rankOf[t]);
      }
    }
    const auto rowsOf = [&](int p, std::vector<Index>* held) {
      std::vector<std::uint8_t> inPiece(nv, 0);
      for (std::size_t t = 0; t < nt; ++t)
      {
        for (int k = 0; k < 3 && rankOf[t] == p; ++k)
        {
          inPiece[triangles[3 * t + k]] = 1;
        }
      }
      std::set<Index> rows;
      for (int pass = 0; pass < 2; ++pass) // the piece's triangles first
      {
        for (std::size_t t = 0; t < nt; ++t)
        {
          const Index* v = &triangles[3 * t];
          const bool touches = inPiece[v[0]] || inPiece[v[1]] || inPiece[v[2]];
          if ((pass == 0) == (rankOf[t] == p) && touches)
          {
            rows.insert(v, v + 3);
            if (held)
            {
              held->push_back(static_cast<Index>(t));
            }
          }
        }
      }
      return std::vector<Index>(rows.begin(), rows.end());
    };
    Global = rowsOf(rank, &WholeTriangle);
    std::map<Index, Index> local;
    for (std::size_t l = 0; l < Global.size(); ++l)
    {
      local[Global[l]] = static_cast<Index>(l);
      Points.insert(Points.end(), &points[3 * Global[l]], &points[3 * Global[l] + 3]);
    }
    for (const Index t : WholeTriangle)
    {
      for (int k = 0; k < 3; ++k)
      {
        Triangles.push_back(local.at(triangles[3 * static_cast<std::size_t>(t) + k]));
      }
    }
    std::map<int, std::vector<Index>> rowsThere;
    for (const Index g : Global)
    {
      const int p = owner[g];
      if (!rowsThere.count(p))
      {
        rowsThere[p] = rowsOf(p, nullptr);
      }
      OwnerRank.push_back(p);
      OwnerRow.push_back(static_cast<Index>(
        std::lower_bound(rowsThere[p].begin(), rowsThere[p].end(), g) - rowsThere[p].begin()));
    }
  }
  Index Rows() const { return static_cast<Index>(Global.size()); }
};

/// The test surfaces, about the z axis: a torus of revolution (radii 1 and
/// 0.35, n x n/2 points), the outer half of its tube (an annulus: two
/// boundary loops), a sphere of n/2 - 1 rings and two poles, and its upper
/// cap (a disk); and each triangle's process: by the angle about z, in
/// slabs over the processes (the last of 3 holding nothing).
enum class Shape
{
  Torus,
  Annulus,
  Sphere,
  Cap
};

struct SplitSurface
{
  std::vector<Index> Triangles;
  std::vector<double> Points;
  std::vector<int> RankOf;

  SplitSurface(Shape shape, int n, int size)
  {
    const int owners = size >= 3 ? size - 1 : size;
    const auto slab = [&](int i) { return i * owners / n; };
    const int m = n / 2;
    if (shape == Shape::Torus || shape == Shape::Annulus)
    {
      const int rings = shape == Shape::Annulus ? m / 2 : m;
      for (int j = 0; j < m; ++j)
      {
        for (int i = 0; i < n; ++i)
        {
          const double u = 2.0 * M_PI * i / n, v = 2.0 * M_PI * (j - m / 4) / m; // (v from -90 degrees)
          const double rho = 1.0 + 0.35 * std::cos(v);
          Points.insert(Points.end(), { rho * std::cos(u), rho * std::sin(u), 0.35 * std::sin(v) });
        }
      }
      for (int j = 0; j < rings; ++j)
      {
        for (int i = 0; i < n; ++i)
        {
          const Index a = j * n + i, b = j * n + (i + 1) % n, c = ((j + 1) % m) * n + (i + 1) % n,
                      d = ((j + 1) % m) * n + i;
          Triangles.insert(Triangles.end(), { a, b, c, a, c, d });
          RankOf.insert(RankOf.end(), 2, slab(i));
        }
      }
      return;
    }
    // Rings j = 1 .. m - 1 of n points (point 1 + (j - 1) n + i), the poles 0 and the last.
    const Index south = 1 + (m - 1) * n;
    Points.insert(Points.end(), { 0.0, 0.0, 1.0 });
    for (int j = 1; j < m; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        const double u = 2.0 * M_PI * i / n, w = M_PI * j / m;
        Points.insert(Points.end(), { std::sin(w) * std::cos(u), 0.8 * std::sin(w) * std::sin(u), std::cos(w) });
      }
    }
    Points.insert(Points.end(), { 0.0, 0.0, -1.0 });
    const int rings = shape == Shape::Cap ? m / 2 : m - 1;
    const auto at = [n](int j, int i) { return static_cast<Index>(1 + (j - 1) * n + (i % n)); };
    for (int i = 0; i < n; ++i)
    {
      Triangles.insert(Triangles.end(), { 0, at(1, i), at(1, i + 1) });
      RankOf.push_back(slab(i));
      for (int j = 1; j < rings; ++j)
      {
        Triangles.insert(Triangles.end(), { at(j, i), at(j + 1, i), at(j + 1, i + 1), at(j, i), at(j + 1, i + 1), at(j, i + 1) });
        RankOf.insert(RankOf.end(), 2, slab(i));
      }
      if (shape == Shape::Sphere)
      {
        Triangles.insert(Triangles.end(), { south, at(m - 1, i + 1), at(m - 1, i) });
        RankOf.push_back(slab(i));
      }
    }
  }
  /// A field with all three parts: smooth, not tangent, per triangle.
  std::vector<double> Field() const
  {
    std::vector<double> x;
    for (std::size_t t = 0; t < RankOf.size(); ++t)
    {
      double c[3] = { 0, 0, 0 };
      for (int k = 0; k < 3; ++k)
      {
        for (int d = 0; d < 3; ++d)
        {
          c[d] += Points[3 * Triangles[3 * t + k] + d] / 3.0;
        }
      }
      x.insert(x.end(), { std::sin(2.0 * c[1]) + c[2] - c[1], std::cos(3.0 * c[0]) + c[0], c[0] * c[1] + 0.5 });
    }
    return x;
  }
};

} // namespace

TEST(Partition, DistributedVectorFieldDecompositionIsTheSerialOne)
{
  // A torus (its harmonic part of two dimensions), an annulus cut from it
  // (one), where the stream function is solved, and a sphere and a cap of
  // it (a disk: no harmonic part), where it is integrated, split over the
  // processes by the angle about their axis (the last of 3 holding
  // nothing; the poles shared by all), under both boundary conditions:
  // every process's potential, stream function and parts on all its points,
  // edges and triangles (ring included) as the serial decomposition of the
  // whole surface, and the energies of the whole surface on every process.
  const auto [rank, size] = RankAndSize();
  const MPI_Comm world = MPI_COMM_WORLD;
  for (const Shape shape : { Shape::Torus, Shape::Annulus, Shape::Sphere, Shape::Cap })
  {
    const SplitSurface surface(shape, 64, size);
    const SurfacePiece mine(surface.Triangles, surface.Points, surface.RankOf, rank, size);
    const Partition split(&world, mine.Rows(), mine.OwnerRank.data(), mine.OwnerRow.data());
    const MeshTopology whole(static_cast<Index>(surface.Points.size() / 3),
      IndexArray(surface.Triangles.begin(), surface.Triangles.end()), 1);
    const MeshTopology piece(mine.Rows(), IndexArray(mine.Triangles.begin(), mine.Triangles.end()), 1);
    const std::vector<double> field = surface.Field();
    std::vector<double> vectors;
    for (const Index t : mine.WholeTriangle)
    {
      vectors.insert(vectors.end(), &field[3 * static_cast<std::size_t>(t)], &field[3 * static_cast<std::size_t>(t) + 3]);
    }
    for (const VectorFieldBoundary boundary :
      { VectorFieldBoundary::TangentDivergenceFree, VectorFieldBoundary::NormalCurlFree })
    {
      VectorFieldOptions o;
      o.Boundary = boundary;
      o.NumberOfThreads = 1;
      VectorFieldDecomposition a, b;
      DecomposeVectorField(whole, surface.Points.data(), field.data(), o, a);
      DecomposeVectorField(piece, mine.Points.data(), vectors.data(), o, split, b);
      const auto largest = [](const std::vector<double>& v) {
        double m = 0.0;
        for (const double x : v)
        {
          m = std::max(m, std::abs(x));
        }
        return m;
      };
      double potential = 0.0, stream = 0.0, parts = 0.0;
      for (std::size_t l = 0; l < mine.Global.size(); ++l)
      {
        potential = std::max(potential, std::abs(b.Potential[l] - a.Potential[mine.Global[l]]));
      }
      const MeshTopology::EdgeTable& edges = piece.Edges();
      for (std::int64_t e = 0; e < edges.NumberOfEdges(); ++e)
      {
        const std::int64_t w =
          whole.Edges().Find(mine.Global[edges.Vertices[2 * e]], mine.Global[edges.Vertices[2 * e + 1]]);
        stream = std::max(stream, std::abs(b.StreamFunction[e] - a.StreamFunction[w]));
      }
      for (std::size_t k = 0; k < mine.WholeTriangle.size(); ++k)
      {
        const std::size_t t = mine.WholeTriangle[k];
        for (int d = 0; d < 3; ++d)
        {
          parts = std::max({ parts, std::abs(b.CurlFree[3 * k + d] - a.CurlFree[3 * t + d]),
            std::abs(b.DivergenceFree[3 * k + d] - a.DivergenceFree[3 * t + d]),
            std::abs(b.Harmonic[3 * k + d] - a.Harmonic[3 * t + d]) });
        }
      }
      const char* names[] = { "torus", "annulus", "sphere", "cap" };
      const std::string label = std::string(names[static_cast<int>(shape)]) + ", boundary " +
        std::to_string(static_cast<int>(boundary)) + ", " + std::to_string(b.Iterations) + " iterations";
      EXPECT_TRUE(b.Converged) << label;
      EXPECT_LE(potential, 1e-8 * largest(a.Potential)) << label;
      EXPECT_LE(stream, 1e-8 * largest(a.StreamFunction)) << label;
      EXPECT_LE(parts, 1e-8 * largest(a.Tangent)) << label;
      for (int k = 0; k < 4; ++k)
      {
        EXPECT_NEAR(b.Energy[k], a.Energy[k], 1e-9 * a.Energy[0]) << label << ", energy " << k;
      }
      for (int k = 0; k < 3; ++k)
      {
        EXPECT_NEAR(b.InnerProducts[k], a.InnerProducts[k], 1e-9 * a.Energy[0]) << label << ", product " << k;
      }
      const bool harmonic = shape == Shape::Torus || shape == Shape::Annulus;
      EXPECT_EQ(b.Integrated, !harmonic) << label;
      EXPECT_EQ(a.Integrated, b.Integrated) << label;
      if (harmonic)
      {
        EXPECT_GT(a.Energy[3], 1e-3 * a.Energy[0]) << label; // (a harmonic part to recover)
      }
      std::printf("%s: potential %.1e, stream function %.1e, parts %.1e\n", label.c_str(), potential, stream, parts);
    }
  }
}
