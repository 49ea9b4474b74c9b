// Intrinsic parameterizations (thesis chapter 5): reproduction of planar
// meshes, distortion on real meshes against CGAL 5.5's figures, natural
// conformal maps, constraints, near-optimal maps, the boundary basis and
// bad input.
#include "Maps/Parameterization.h"
#include "Solvers/DenseBlocks.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <random>

#include <cmath>

using namespace beltrami;
using beltrami::test::Mesh;

namespace
{

Mesh ReadMesh(const std::string& name)
{
  std::string error;
  Mesh m = test::ReadMesh(name, error);
  EXPECT_EQ(error, "");
  return m;
}

ParameterizationResult Solve(const Mesh& m, ParameterizationOptions o)
{
  const MeshTopology topo = m.Topology();
  ParameterizationResult r = Parameterize(topo, m.Points.data(), o);
  EXPECT_EQ(r.Error, "");
  return r;
}

DistortionReport Measure(const Mesh& m, const ParameterizationResult& r)
{
  return MeasureDistortion(m.Topology(), m.Points.data(), r.UV.data());
}

ParameterizationOptions Energy(double lambda, double mu, ParameterizationBoundary b)
{
  ParameterizationOptions o;
  o.ConformalWeight = lambda;
  o.AuthalicWeight = mu;
  o.Boundary = b;
  return o;
}

/// Largest distance between uv and the best similarity image of the xy
/// coordinates (least squares fit of u + iv = a (x + iy) + b).
double SimilarityResidual(const Mesh& m, const std::vector<double>& uv)
{
  const Index n = m.NumberOfVertices();
  Eigen::MatrixXd A(2 * n, 4);
  Eigen::VectorXd b(2 * n);
  for (Index i = 0; i < n; ++i)
  {
    const double x = m.Points[3 * i], y = m.Points[3 * i + 1];
    A.row(2 * i) << x, -y, 1, 0;
    A.row(2 * i + 1) << y, x, 0, 1;
    b[2 * i] = uv[2 * i];
    b[2 * i + 1] = uv[2 * i + 1];
  }
  const Eigen::VectorXd c = A.colPivHouseholderQr().solve(b);
  return (A * c - b).cwiseAbs().maxCoeff();
}

} // namespace

TEST(Parameterization, PlanarMeshIsItsOwnParameterization)
{
  // Barycentric property (section 5.3.5): for any mix, a flat mesh with its
  // own boundary is reproduced exactly, obtuse triangles included.
  const Mesh m = test::FlatIrregular(14, 3);
  std::vector<double> own(2 * m.NumberOfVertices());
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    own[2 * i] = m.Points[3 * i];
    own[2 * i + 1] = m.Points[3 * i + 1];
  }
  for (const auto& [lambda, mu] : { std::pair{ 1.0, 0.0 }, { 0.0, 1.0 }, { 0.3, 0.7 }, { 2.0, 5.0 } })
  {
    ParameterizationOptions o = Energy(lambda, mu, ParameterizationBoundary::Given);
    o.GivenUV = own.data();
    const ParameterizationResult r = Solve(m, o);
    double worst = 0;
    for (std::size_t k = 0; k < own.size(); ++k)
    {
      worst = std::max(worst, std::abs(r.UV[k] - own[k]));
    }
    EXPECT_LT(worst, 1e-9) << "lambda " << lambda << " mu " << mu;
  }
  // The natural conformal map of a flat mesh is a similarity of it.
  const ParameterizationResult natural = Solve(m, Energy(1, 0, ParameterizationBoundary::Natural));
  EXPECT_LT(SimilarityResidual(m, natural.UV), 1e-8); // the map spans [0,1]
  EXPECT_LT(Measure(m, natural).MaxAngle, 1e-6);
}

TEST(Parameterization, MushroomMatchesCGALDistortion)
{
  // CGAL 5.5 on mushroom.off with the arc-length circle boundary: DCP mean
  // angle distortion 3.478 deg, DAP 14.545 deg; free-boundary LSCM 1.725
  // deg.  Mean |log area ratio| (beltrami-benchmark-cgal-parameterization):
  // DCP 1.418, DAP 2.420 - on this mesh the authalic map has the larger area
  // distortion, in CGAL too.
  const Mesh m = ReadMesh("mushroom.off");
  const DistortionReport dcp = Measure(m, Solve(m, Energy(1, 0, ParameterizationBoundary::Circle)));
  const DistortionReport dap = Measure(m, Solve(m, Energy(0, 1, ParameterizationBoundary::Circle)));
  const DistortionReport natural = Measure(m, Solve(m, Energy(1, 0, ParameterizationBoundary::Natural)));
  EXPECT_NEAR(dcp.MeanAngle, 3.48, 0.01);
  EXPECT_NEAR(dap.MeanAngle, 14.545, 0.01);
  EXPECT_NEAR(dcp.MeanArea, 1.418, 0.002);
  EXPECT_NEAR(dap.MeanArea, 2.420, 0.002);
  EXPECT_LE(natural.MeanAngle, 1.73);
  EXPECT_EQ(dcp.FlippedTriangles, 0);
  EXPECT_EQ(dap.FlippedTriangles, 0);
  EXPECT_EQ(natural.FlippedTriangles, 0);
}

TEST(Parameterization, RealMeshesConformalVersusAuthalic)
{
  for (const char* name : { "mushroom.off", "nefertiti.off", "patch-01.off", "three_peaks.off" })
  {
    SCOPED_TRACE(name);
    const Mesh m = ReadMesh(name);
    const DistortionReport dcp = Measure(m, Solve(m, Energy(1, 0, ParameterizationBoundary::Circle)));
    const DistortionReport dap = Measure(m, Solve(m, Energy(0, 1, ParameterizationBoundary::Circle)));
    const DistortionReport natural = Measure(m, Solve(m, Energy(1, 0, ParameterizationBoundary::Natural)));
    EXPECT_LT(dcp.MeanAngle, dap.MeanAngle);
    EXPECT_LT(natural.MeanAngle, dcp.MeanAngle);
    EXPECT_EQ(dap.FlippedTriangles, 0); // the authalic weights are positive here
    if (std::string(name) != "three_peaks.off")
    {
      EXPECT_EQ(dcp.FlippedTriangles, 0);
    }
    // DAP has the lower area distortion on these two only; on mushroom and
    // patch-01 CGAL's DAP has the larger one too (see above).
    if (std::string(name) == "nefertiti.off" || std::string(name) == "three_peaks.off")
    {
      EXPECT_LT(dap.MeanArea, dcp.MeanArea);
    }
  }
}

TEST(Parameterization, SquareBoundaryAndUniformSpacing)
{
  const Mesh m = ReadMesh("patch-01.off");
  ParameterizationOptions o = Energy(1, 0, ParameterizationBoundary::Square);
  o.Spacing = BoundarySpacing::Uniform;
  const ParameterizationResult r = Solve(m, o);
  int corners = 0;
  for (Index v : r.OuterBoundary)
  {
    const double u = r.UV[2 * v], w = r.UV[2 * v + 1];
    EXPECT_TRUE(std::abs(u) < 1e-12 || std::abs(u - 1) < 1e-12 || std::abs(w) < 1e-12 ||
      std::abs(w - 1) < 1e-12);
    corners += (std::abs(u) < 1e-12 || std::abs(u - 1) < 1e-12) &&
      (std::abs(w) < 1e-12 || std::abs(w - 1) < 1e-12);
  }
  EXPECT_EQ(corners, 4);
  EXPECT_EQ(Measure(m, r).FlippedTriangles, 0);
}

TEST(Parameterization, SharpestSquareCornersFlattenNoTriangle)
{
  // A strip of 12 x 1 squares, each cut by a diagonal: every vertex is on
  // the boundary, two corners are the tips of single triangles.  Corners at
  // the quarters of the length would put triangles flat on the long sides.
  Mesh m;
  const int n = 12;
  for (int j = 0; j <= 1; ++j)
  {
    for (int i = 0; i <= n; ++i)
    {
      m.Points.insert(m.Points.end(), { double(i), double(j), 0.0 });
    }
  }
  for (int i = 0; i < n; ++i)
  {
    m.Triangles.insert(m.Triangles.end(), { i, i + 1, i + n + 2, i, i + n + 2, i + n + 1 });
  }
  for (const SquareCorners corners : { SquareCorners::QuarterLength, SquareCorners::Sharpest })
  {
    ParameterizationOptions o = Energy(1, 0, ParameterizationBoundary::Square);
    o.Corners = corners;
    const ParameterizationResult r = Solve(m, o);
    ASSERT_EQ(r.Error, "");
    const Index flat = Measure(m, r).FlippedTriangles;
    if (corners == SquareCorners::QuarterLength)
    {
      EXPECT_GT(flat, 0);
      continue;
    }
    EXPECT_EQ(flat, 0);
    for (Index v : { n, n + 1 }) // the tips of the ears are corners of the square
    {
      EXPECT_TRUE((r.UV[2 * v] == 0.0 || r.UV[2 * v] == 1.0) && (r.UV[2 * v + 1] == 0.0 || r.UV[2 * v + 1] == 1.0))
        << "vertex " << v;
    }
  }
  // The tip of every ear is a corner.
  const MeshTopology topology = m.Topology();
  const std::vector<Index> loop = topology.BoundaryLoops()[0];
  const std::array<std::size_t, 4> c = ChooseSquareCorners(topology, m.Points.data(), loop);
  for (Index tip : { n, n + 1 })
  {
    EXPECT_NE(std::find_if(c.begin(), c.end(), [&](std::size_t k) { return loop[k] == tip; }), c.end());
  }
}

TEST(Parameterization, PointConstraintsLandOnTheirTargets)
{
  const Mesh m = ReadMesh("nefertiti.off");
  const MeshTopology topo = m.Topology();
  std::vector<PointConstraint> constraints(3);
  // Two interior vertices and a point inside a triangle.
  Index interior[2] = { -1, -1 };
  for (Index v = 0, found = 0; v < m.NumberOfVertices() && found < 2; ++v)
  {
    if (topo.IsInterior(v) && (found == 0 || v > interior[0] + 50))
    {
      interior[found++] = v;
    }
  }
  constraints[0].Vertices = { interior[0], -1, -1 };
  constraints[0].Target[0] = 0.3;
  constraints[0].Target[1] = 0.4;
  constraints[1].Vertices = { interior[1], -1, -1 };
  constraints[1].Target[0] = 0.7;
  constraints[1].Target[1] = 0.6;
  const Index t = 100;
  constraints[2].Vertices = { m.Triangles[3 * t], m.Triangles[3 * t + 1], m.Triangles[3 * t + 2] };
  constraints[2].Weights = { 0.2, 0.5, 0.3 };
  constraints[2].Target[0] = 0.5;
  constraints[2].Target[1] = 0.2;
  const auto check = [&](const ParameterizationResult& r, std::size_t count) {
    for (std::size_t k = 0; k < count; ++k)
    {
      double u = 0, v = 0;
      for (int j = 0; j < 3; ++j)
      {
        if (constraints[k].Vertices[j] >= 0)
        {
          u += constraints[k].Weights[j] * r.UV[2 * constraints[k].Vertices[j]];
          v += constraints[k].Weights[j] * r.UV[2 * constraints[k].Vertices[j] + 1];
        }
      }
      EXPECT_NEAR(u, constraints[k].Target[0], 1e-9);
      EXPECT_NEAR(v, constraints[k].Target[1], 1e-9);
    }
  };
  for (const auto b : { ParameterizationBoundary::Circle, ParameterizationBoundary::Natural })
  {
    for (std::size_t count : { 1, 2, 3 })
    {
      for (double mu : { 0.0, 1.0 })
      {
        if (b == ParameterizationBoundary::Natural && mu != 0.0)
        {
          continue;
        }
        SCOPED_TRACE(std::to_string(static_cast<int>(b)) + " " + std::to_string(count) + " " + std::to_string(mu));
        ParameterizationOptions o = Energy(1.0 - mu, mu, b);
        o.Constraints.assign(constraints.begin(), constraints.begin() + count);
        check(Solve(m, o), count);
      }
    }
  }
}

namespace
{

/// Largest distance of the line's vertices from their targets: the segment
/// From-To at their arc-length fractions.
double LineResidual(const Mesh& m, const LineConstraint& line, const std::vector<double>& uv)
{
  std::vector<double> s(line.Path.size(), 0.0);
  for (std::size_t i = 1; i < line.Path.size(); ++i)
  {
    s[i] = s[i - 1] + (m.Point(line.Path[i]) - m.Point(line.Path[i - 1])).norm();
  }
  double worst = 0.0;
  for (std::size_t i = 0; i < line.Path.size(); ++i)
  {
    const double t = s[i] / s.back();
    for (int d = 0; d < 2; ++d)
    {
      worst = std::max(worst, std::abs(uv[2 * line.Path[i] + d] - (line.From[d] + t * (line.To[d] - line.From[d]))));
    }
  }
  return worst;
}

/// A shortest path along edges (by edge count) from a to b through interior vertices.
std::vector<Index> EdgePath(const MeshTopology& topo, Index a, Index b)
{
  const auto& e = topo.Edges();
  std::vector<Index> previous(topo.NumberOfVertices(), -2), queue{ a };
  previous[a] = -1;
  for (std::size_t k = 0; k < queue.size() && previous[b] == -2; ++k)
  {
    for (std::int64_t j = e.NeighborOffsets[queue[k]]; j < e.NeighborOffsets[queue[k] + 1]; ++j)
    {
      if (previous[e.Neighbors[j]] == -2 && topo.IsInterior(e.Neighbors[j]))
      {
        previous[e.Neighbors[j]] = queue[k];
        queue.push_back(e.Neighbors[j]);
      }
    }
  }
  std::vector<Index> path;
  for (Index v = b; v != -1; v = previous[v])
  {
    path.insert(path.begin(), v);
  }
  return path;
}

} // namespace

TEST(Parameterization, LineConstraintsLandOnTheirSegments)
{
  // Section 5.4.1: a line's vertices on the target segment at their
  // arc-length fractions.  A flat grid with its own boundary is its own DCP:
  // a line whose targets agree with it changes nothing, a bent one is met
  // exactly without a flipped triangle.
  const int n = 21;
  const Mesh m = test::HeightField([](double, double) { return 0.0; }, 1.0, n, 0.0, false, 1);
  std::vector<double> own(2 * m.NumberOfVertices());
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    own[2 * i] = m.Points[3 * i];
    own[2 * i + 1] = m.Points[3 * i + 1];
  }
  LineConstraint line; // the row y = 0 from x = -0.5 to 0.5
  for (int i = 5; i <= 15; ++i)
  {
    line.Path.push_back(i * n + 10);
  }
  line.From[0] = -0.5;
  line.To[0] = 0.5;
  ParameterizationOptions o = Energy(1, 0, ParameterizationBoundary::Given);
  o.GivenUV = own.data();
  o.Lines = { line };
  ParameterizationResult r = Solve(m, o);
  ASSERT_EQ(r.UV.size(), own.size());
  double moved = 0.0;
  for (std::size_t k = 0; k < own.size(); ++k)
  {
    moved = std::max(moved, std::abs(r.UV[k] - own[k]));
  }
  EXPECT_LT(moved, 1e-9);
  o.Lines[0].From[1] = -0.2;
  o.Lines[0].To[1] = 0.2;
  r = Solve(m, o);
  ASSERT_EQ(r.UV.size(), own.size());
  EXPECT_LT(LineResidual(m, o.Lines[0], r.UV), 1e-9);
  EXPECT_EQ(Measure(m, r).FlippedTriangles, 0);
  // A staircase along edges: each corner's neighbours on the path share a
  // diagonal edge, so the corner is left free (the three are a triangle that
  // a straight line would collapse); the diagonal through the other points
  // agrees with the plane, which stays as it is.
  LineConstraint stairs;
  for (int i = 4; i < 16; ++i)
  {
    stairs.Path.push_back(i * n + i);
    stairs.Path.push_back((i + 1) * n + i);
  }
  stairs.Path.push_back(16 * n + 16);
  stairs.From[0] = stairs.From[1] = own[2 * stairs.Path.front()];
  stairs.To[0] = stairs.To[1] = own[2 * stairs.Path.back()];
  o.Lines = { stairs };
  r = Solve(m, o);
  ASSERT_EQ(r.UV.size(), own.size());
  moved = 0.0;
  for (std::size_t k = 0; k < own.size(); ++k)
  {
    moved = std::max(moved, std::abs(r.UV[k] - own[k]));
  }
  EXPECT_LT(moved, 1e-9);
  // Natural boundary: a line that agrees with a similarity gives that
  // similarity (zero conformal energy), the line replacing the two pins.
  o = Energy(1, 0, ParameterizationBoundary::Natural);
  line.From[0] = 0.1;
  line.From[1] = 0.2;
  line.To[0] = 0.9;
  line.To[1] = 0.5;
  o.Lines = { line };
  r = Solve(m, o);
  ASSERT_EQ(r.UV.size(), own.size());
  EXPECT_LT(LineResidual(m, line, r.UV), 1e-9);
  EXPECT_LT(SimilarityResidual(m, r.UV), 1e-8);

  // A real face: a path of edges across it straightened between the places
  // its ends have in the unconstrained map (circle boundary).
  const Mesh face = ReadMesh("nefertiti.off");
  const MeshTopology topo = face.Topology();
  const ParameterizationResult free = Solve(face, Energy(1, 0, ParameterizationBoundary::Circle));
  Index a = -1, b = -1;
  for (Index v = 0; v < face.NumberOfVertices(); ++v)
  {
    const double u = free.UV[2 * v], w = free.UV[2 * v + 1];
    if (topo.IsInterior(v) && std::abs(w - 0.5) < 0.05 && (a < 0 || u < free.UV[2 * a]))
    {
      a = v;
    }
    if (topo.IsInterior(v) && std::abs(w - 0.5) < 0.05 && (b < 0 || u > free.UV[2 * b]))
    {
      b = v;
    }
  }
  LineConstraint across;
  across.Path = EdgePath(topo, a, b);
  across.From[0] = free.UV[2 * a];
  across.From[1] = free.UV[2 * a + 1];
  across.To[0] = free.UV[2 * b];
  across.To[1] = free.UV[2 * b + 1];
  ParameterizationOptions straight = Energy(1, 0, ParameterizationBoundary::Circle);
  straight.Lines = { across };
  const ParameterizationResult r2 = Solve(face, straight);
  ASSERT_EQ(r2.UV.size(), free.UV.size());
  const DistortionReport before = Measure(face, free), after = Measure(face, r2);
  std::printf("nefertiti: a %zu-vertex path straightened: residual %.1e, flipped %lld, mean angle distortion "
              "%.3f -> %.3f degrees\n",
    across.Path.size(), LineResidual(face, across, r2.UV), static_cast<long long>(after.FlippedTriangles),
    before.MeanAngle, after.MeanAngle);
  EXPECT_GE(across.Path.size(), 10u);
  EXPECT_LT(LineResidual(face, across, r2.UV), 1e-9);
  EXPECT_EQ(after.FlippedTriangles, 0);

  // Bad lines: clear errors.
  const auto error = [&](LineConstraint bad) {
    ParameterizationOptions e = Energy(1, 0, ParameterizationBoundary::Circle);
    e.Lines = { bad };
    return Parameterize(m.Topology(), m.Points.data(), e).Error;
  };
  LineConstraint gap = line;
  gap.Path.erase(gap.Path.begin() + 3);
  EXPECT_NE(error(gap).find("not joined by a mesh edge"), std::string::npos) << error(gap);
  LineConstraint single = line;
  single.Path.resize(1);
  EXPECT_NE(error(single).find("at least two points"), std::string::npos);
  LineConstraint twice = line;
  twice.Path.push_back(twice.Path[2]);
  EXPECT_NE(error(twice).find("twice"), std::string::npos);
  LineConstraint flat = line;
  flat.To[0] = flat.From[0];
  flat.To[1] = flat.From[1];
  EXPECT_NE(error(flat).find("distinct"), std::string::npos);
  LineConstraint toBoundary; // along the fixed boundary row y = -1: disagrees with the circle
  toBoundary.Path = { 0, n, 2 * n };
  EXPECT_NE(error(toBoundary).find("inconsistent"), std::string::npos) << error(toBoundary);
}

TEST(Parameterization, OptimalMixMinimisesTheEnergy)
{
  const Mesh m = ReadMesh("three_peaks.off");
  const MeshTopology topo = m.Topology();
  for (const auto energy : { DistortionEnergy::EdgeLength, DistortionEnergy::Area })
  {
    ParameterizationOptions o = Energy(1, 0, ParameterizationBoundary::Circle);
    o.OptimizeMix = true;
    o.OptimalEnergy = energy;
    const ParameterizationResult r = Solve(m, o);
    const std::vector<double> uvA = Solve(m, Energy(1, 0, ParameterizationBoundary::Circle)).UV;
    const std::vector<double> uvX = Solve(m, Energy(0, 1, ParameterizationBoundary::Circle)).UV;
    // The energy as the core evaluates it, at the same scale (the DCP map's area).
    double a2 = 0;
    for (Index t = 0; t < topo.NumberOfTriangles(); ++t)
    {
      const Index a = m.Triangles[3 * t], b = m.Triangles[3 * t + 1], c = m.Triangles[3 * t + 2];
      a2 += 0.5 * ((uvA[2 * b] - uvA[2 * a]) * (uvA[2 * c + 1] - uvA[2 * a + 1]) -
                    (uvA[2 * b + 1] - uvA[2 * a + 1]) * (uvA[2 * c] - uvA[2 * a]));
    }
    const double scale = std::sqrt(m.TotalArea() / a2);
    const auto at = [&](double l) {
      std::vector<double> uv(uvA.size());
      for (std::size_t k = 0; k < uv.size(); ++k)
      {
        uv[k] = l * uvA[k] + (1 - l) * uvX[k];
      }
      return DistortionEnergyValue(topo, m.Points.data(), uv.data(), scale, energy);
    };
    double scanBest = HUGE_VAL, scanArg = 0;
    for (int k = 0; k <= 1000; ++k)
    {
      if (at(k / 1000.0) < scanBest)
      {
        scanBest = at(k / 1000.0);
        scanArg = k / 1000.0;
      }
    }
    SCOPED_TRACE(static_cast<int>(energy));
    EXPECT_GT(r.OptimalMix, 0.0);
    EXPECT_LT(r.OptimalMix, 1.0); // an interior minimum on this mesh
    EXPECT_NEAR(r.OptimalMix, scanArg, 2e-3);
    EXPECT_LE(at(r.OptimalMix), scanBest * (1 + 1e-12));
    double worst = 0;
    for (std::size_t k = 0; k < uvA.size(); ++k)
    {
      worst = std::max(worst, std::abs(r.UV[k] - (r.OptimalMix * uvA[k] + (1 - r.OptimalMix) * uvX[k])));
    }
    EXPECT_LT(worst, 1e-12);
  }
}

TEST(Parameterization, BoundaryBasisReproducesSolvesAndOptimisationDescends)
{
  const Mesh m = ReadMesh("patch-01.off");
  ParameterizationOptions o = Energy(1, 0, ParameterizationBoundary::Circle);
  o.KeepBoundaryBasis = true;
  const ParameterizationResult circle = Solve(m, o);
  ASSERT_TRUE(circle.Basis);
  const BoundaryBasis& basis = *circle.Basis;
  // The square map through the basis equals a square solve (same boundary points).
  const ParameterizationResult square = Solve(m, Energy(1, 0, ParameterizationBoundary::Square));
  std::vector<double> p, uv(square.UV.size());
  for (Index v : basis.BoundaryVertices())
  {
    p.push_back(square.UV[2 * v]);
    p.push_back(square.UV[2 * v + 1]);
  }
  basis.Apply(p.data(), uv.data());
  double worst = 0;
  for (std::size_t k = 0; k < uv.size(); ++k)
  {
    worst = std::max(worst, std::abs(uv[k] - square.UV[k]));
  }
  EXPECT_LT(worst, 1e-10);

  for (const auto energy : { DistortionEnergy::EdgeLength, DistortionEnergy::Area })
  {
    ParameterizationOptions opt = Energy(1, 0, ParameterizationBoundary::Circle);
    opt.BoundaryOptimizationSteps = 15;
    opt.BoundaryEnergy = energy;
    const ParameterizationResult r = Solve(m, opt);
    ASSERT_GE(r.BoundaryEnergies.size(), 2u);
    for (std::size_t k = 1; k < r.BoundaryEnergies.size(); ++k)
    {
      EXPECT_LE(r.BoundaryEnergies[k], r.BoundaryEnergies[k - 1]);
    }
    EXPECT_LT(r.BoundaryEnergies.back(), 0.8 * r.BoundaryEnergies.front());
    EXPECT_EQ(Measure(m, r).FlippedTriangles, 0);
  }
}

TEST(Parameterization, BoundaryBasisAndOptimisationKeepPointAndLineConstraints)
{
  // Under constraints the basis is the constrained responses plus the map of
  // a zero boundary: any boundary placement through it equals a constrained
  // solve with that boundary given, and the boundary optimisation keeps the
  // constraints met while its energy descends.
  const Mesh m = ReadMesh("patch-01.off");
  const MeshTopology topo = m.Topology();
  ParameterizationOptions o = Energy(1, 0, ParameterizationBoundary::Circle);
  const ParameterizationResult free = Solve(m, o);
  std::vector<Index> interior;
  for (Index v = 0; v < m.NumberOfVertices(); ++v)
  {
    if (topo.IsInterior(v))
    {
      interior.push_back(v);
    }
  }
  ASSERT_GE(interior.size(), 100u);
  PointConstraint pc; // an interior point moved a little from its free place
  pc.Vertices = { interior[interior.size() / 3], -1, -1 };
  pc.Target[0] = free.UV[2 * pc.Vertices[0]] + 0.02;
  pc.Target[1] = free.UV[2 * pc.Vertices[0] + 1] - 0.01;
  const Index a = interior[2 * interior.size() / 3];
  const std::vector<Index> neighbours(topo.Edges().Neighbors.data() + topo.Edges().NeighborOffsets[a],
    topo.Edges().Neighbors.data() + topo.Edges().NeighborOffsets[a + 1]);
  LineConstraint line; // a two-point line: an edge at a, kept where the free map has it
  line.Path = { a, neighbours.front() };
  line.From[0] = free.UV[2 * a];
  line.From[1] = free.UV[2 * a + 1];
  line.To[0] = free.UV[2 * neighbours.front()];
  line.To[1] = free.UV[2 * neighbours.front() + 1];
  o.Constraints = { pc };
  o.Lines = { line };
  o.KeepBoundaryBasis = true;
  const ParameterizationResult circle = Solve(m, o);
  ASSERT_TRUE(circle.Basis);
  const auto meets = [&](const std::vector<double>& uv) {
    return std::max({ std::abs(uv[2 * pc.Vertices[0]] - pc.Target[0]), std::abs(uv[2 * pc.Vertices[0] + 1] - pc.Target[1]),
      std::abs(uv[2 * a] - line.From[0]), std::abs(uv[2 * neighbours.front() + 1] - line.To[1]) });
  };
  EXPECT_LT(meets(circle.UV), 1e-9);
  // The square boundary through the basis = a constrained solve with it given.
  const ParameterizationResult square = Solve(m, Energy(1, 0, ParameterizationBoundary::Square));
  std::vector<double> p, uv(square.UV.size());
  for (Index v : circle.Basis->BoundaryVertices())
  {
    p.push_back(square.UV[2 * v]);
    p.push_back(square.UV[2 * v + 1]);
  }
  circle.Basis->Apply(p.data(), uv.data());
  ParameterizationOptions given = Energy(1, 0, ParameterizationBoundary::Given);
  given.GivenUV = square.UV.data();
  given.Constraints = o.Constraints;
  given.Lines = o.Lines;
  const ParameterizationResult direct = Solve(m, given);
  double worst = 0.0;
  for (std::size_t k = 0; k < uv.size(); ++k)
  {
    worst = std::max(worst, std::abs(uv[k] - direct.UV[k]));
  }
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(meets(uv), 1e-9);
  double moved = 0.0; // the constraints matter: the map is not the free square map
  for (std::size_t k = 0; k < uv.size(); ++k)
  {
    moved = std::max(moved, std::abs(uv[k] - square.UV[k]));
  }
  EXPECT_GT(moved, 5e-3);
  // The circle's own boundary through the basis gives the solve back.
  p.clear();
  for (Index v : circle.Basis->BoundaryVertices())
  {
    p.push_back(circle.UV[2 * v]);
    p.push_back(circle.UV[2 * v + 1]);
  }
  circle.Basis->Apply(p.data(), uv.data());
  worst = 0.0;
  for (std::size_t k = 0; k < uv.size(); ++k)
  {
    worst = std::max(worst, std::abs(uv[k] - circle.UV[k]));
  }
  EXPECT_LT(worst, 1e-10);
  // Boundary optimisation with the constraints, also through the optimal mix.
  for (const bool mix : { false, true })
  {
    ParameterizationOptions opt = o;
    opt.KeepBoundaryBasis = false;
    opt.OptimizeMix = mix;
    opt.BoundaryOptimizationSteps = 15;
    const ParameterizationResult r = Solve(m, opt);
    ASSERT_GE(r.BoundaryEnergies.size(), 2u);
    for (std::size_t k = 1; k < r.BoundaryEnergies.size(); ++k)
    {
      EXPECT_LE(r.BoundaryEnergies[k], r.BoundaryEnergies[k - 1]);
    }
    EXPECT_LT(r.BoundaryEnergies.back(), 0.8 * r.BoundaryEnergies.front());
    EXPECT_LT(meets(r.UV), 1e-9) << "mix " << mix;
    EXPECT_EQ(Measure(m, r).FlippedTriangles, 0);
  }
}

TEST(Parameterization, BasisBeyondTheLimitIsKeptAsTheFactorization)
{
  // A basis over MaximumBasisBytes is kept as the factorization (the
  // conformal energy): its maps and pull-backs equal the dense basis', with
  // and without constraints, and so does the boundary optimisation.
  const Mesh m = ReadMesh("patch-01.off");
  const MeshTopology topo = m.Topology();
  Index inner = -1;
  for (Index v = 0; v < m.NumberOfVertices() && inner < 0; ++v)
  {
    inner = topo.IsInterior(v) && v > m.NumberOfVertices() / 2 ? v : -1;
  }
  for (const bool constrained : { false, true })
  {
    ParameterizationOptions o = Energy(1, 0, ParameterizationBoundary::Circle);
    o.KeepBoundaryBasis = true;
    if (constrained)
    {
      PointConstraint pc;
      pc.Vertices = { inner, -1, -1 };
      pc.Target[0] = 0.45;
      pc.Target[1] = 0.52;
      o.Constraints = { pc };
    }
    const ParameterizationResult dense = Solve(m, o);
    o.MaximumBasisBytes = 1.0;
    const ParameterizationResult held = Solve(m, o);
    ASSERT_TRUE(dense.Basis && held.Basis);
    EXPECT_TRUE(dense.Basis->IsDense());
    EXPECT_FALSE(held.Basis->IsDense());
    const std::size_t nb = dense.Basis->BoundaryVertices().size();
    std::vector<double> p(2 * nb), g(2 * m.NumberOfVertices()), a(g.size()), b(g.size()), ga(2 * nb), gb(2 * nb);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (double& x : p)
    {
      x = u(rng);
    }
    for (double& x : g)
    {
      x = u(rng);
    }
    dense.Basis->Apply(p.data(), a.data());
    held.Basis->Apply(p.data(), b.data());
    dense.Basis->PullBack(g.data(), ga.data());
    held.Basis->PullBack(g.data(), gb.data());
    double map = 0.0, pull = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k)
    {
      map = std::max(map, std::abs(a[k] - b[k]));
    }
    for (std::size_t k = 0; k < ga.size(); ++k)
    {
      pull = std::max(pull, std::abs(ga[k] - gb[k]));
    }
    EXPECT_LT(map, 1e-10) << "constrained " << constrained;
    EXPECT_LT(pull, 1e-9) << "constrained " << constrained;
    if (constrained)
    {
      EXPECT_NEAR(b[2 * inner], 0.45, 1e-9);
      EXPECT_NEAR(b[2 * inner + 1], 0.52, 1e-9);
    }
    o.KeepBoundaryBasis = false;
    o.BoundaryOptimizationSteps = 10;
    const ParameterizationResult descent = Solve(m, o);
    o.MaximumBasisBytes = 1e12;
    const ParameterizationResult reference = Solve(m, o);
    ASSERT_EQ(descent.BoundaryEnergies.size(), reference.BoundaryEnergies.size());
    for (std::size_t k = 0; k < descent.BoundaryEnergies.size(); ++k)
    {
      EXPECT_NEAR(descent.BoundaryEnergies[k], reference.BoundaryEnergies[k], 1e-9 * reference.BoundaryEnergies[0]);
    }
  }
  // The authalic energy's system is not symmetric: beyond the limit, an error.
  ParameterizationOptions dap = Energy(0, 1, ParameterizationBoundary::Circle);
  dap.KeepBoundaryBasis = true;
  dap.MaximumBasisBytes = 1.0;
  const std::string error = Parameterize(topo, m.Points.data(), dap).Error;
  EXPECT_NE(error.find("conformal energy alone"), std::string::npos) << error;
}

TEST(Parameterization, ResultsDoNotDependOnTheThreadCount)
{
  // Our threads only: the BLAS runs single-threaded in both runs (OpenBLAS's
  // SkylakeX kernels round differently with their own thread count, by
  // 3e-16 here; its Haswell and Zen kernels do not).
  const SingleThreadedBlas blas;
  const Mesh m = ReadMesh("mushroom.off");
  for (const auto b : { ParameterizationBoundary::Circle, ParameterizationBoundary::Natural })
  {
    ParameterizationOptions o = Energy(1, b == ParameterizationBoundary::Circle ? 0.5 : 0.0, b);
    o.NumberOfThreads = 1;
    const std::vector<double> one = Solve(m, o).UV;
    o.NumberOfThreads = 3;
    EXPECT_EQ(one, Solve(m, o).UV);
  }
}

TEST(Parameterization, BadInputGetsAClearError)
{
  const auto fails = [](const Mesh& m, const ParameterizationOptions& o, const std::string& expected) {
    const MeshTopology topo = m.Topology();
    const ParameterizationResult r = Parameterize(topo, m.Points.data(), o);
    EXPECT_FALSE(r.Error.empty());
    EXPECT_TRUE(r.UV.empty());
    EXPECT_NE(r.Error.find(expected), std::string::npos) << r.Error;
  };
  const ParameterizationOptions dcp;
  fails(test::OctahedronSphere(2), dcp, "closed"); // closed genus 0
  fails(Mesh{}, dcp, "no triangles");
  // Two disks: two components.
  Mesh two = test::FlatIrregular(5, 1);
  const Index offset = two.NumberOfVertices();
  const Mesh other = test::FlatIrregular(5, 2);
  for (Index i = 0; i < other.NumberOfVertices(); ++i)
  {
    two.AddPoint(other.Point(i) + Eigen::Vector3d(3, 0, 0));
  }
  for (Index t : other.Triangles)
  {
    two.Triangles.push_back(t + offset);
  }
  fails(two, dcp, "2 components");
  // An open cylinder (annulus) is fine; a torus with a hole is not genus 0.
  Mesh torus = test::Torus(2, 0.5, 24, 12, 0, 1);
  torus.Triangles.resize(torus.Triangles.size() - 3);
  fails(torus, dcp, "genus 1");
  // Non-manifold: a third triangle on an edge.
  Mesh fin = test::FlatIrregular(5, 4);
  const MeshTopology finTopology = fin.Topology();
  const auto& edges = finTopology.Edges();
  std::int64_t inner = 0;
  while (edges.FaceCount[inner] != 2)
  {
    ++inner;
  }
  const Index tip = fin.AddPoint({ 0, 0, 1 });
  fin.AddTriangle(edges.Vertices[2 * inner], edges.Vertices[2 * inner + 1], tip);
  fails(fin, dcp, "non-manifold");
  // NaN coordinates.
  Mesh nan = test::FlatIrregular(5, 5);
  nan.Points[3 * 7] = std::nan("");
  fails(nan, dcp, "non-finite");
  const Mesh disk = test::FlatIrregular(5, 6);
  fails(disk, Energy(0.5, 0.5, ParameterizationBoundary::Natural), "conformal energy only");
  fails(disk, Energy(0, 0, ParameterizationBoundary::Circle), "not both 0");
  fails(disk, Energy(1, 0, ParameterizationBoundary::Given), "none were supplied");
  ParameterizationOptions bad;
  bad.Constraints.resize(1);
  bad.Constraints[0].Vertices = { 100000, -1, -1 };
  fails(disk, bad, "not on the surface");
  bad.Constraints[0].Vertices = { 3, 4, -1 };
  bad.Constraints[0].Weights = { 0.5, 0.6, 0 };
  fails(disk, bad, "sum to 1");
  // Two constraints on one point with different targets.
  bad.Constraints.assign(2, PointConstraint{});
  bad.Constraints[0].Vertices = bad.Constraints[1].Vertices = { 12, -1, -1 };
  bad.Constraints[1].Target[0] = 1;
  fails(disk, bad, "inconsistent");
}

TEST(Parameterization, AnnulusHoleIsFreeAndUnflipped)
{
  // An open cylinder: its two loops are equally long; one is fixed on the
  // circle, the other (a hole) is free (natural for the Dirichlet energy).
  const Mesh m = test::Cylinder(1.0, 1.0, 32, 8);
  const ParameterizationResult r = Solve(m, Energy(1, 0, ParameterizationBoundary::Circle));
  EXPECT_EQ(Measure(m, r).FlippedTriangles, 0);
  EXPECT_EQ(r.OuterBoundary.size(), 32u);
}
