// The operators of section 2.8 on data seen as graphs, as outputs
// (Flows/GraphOperators), against analytic graphs: the
// Laplace-Beltrami operator of the data, the mean and Gaussian curvatures
// and the edge indicator of a Gaussian image, volume and point data, zero
// on linear data, and the image and volume paths equal to the mesh paths
// on the same triangulation.
#include "TestMeshes.h"

#include "Flows/GraphOperators.h"
#include "Mesh/Tetrahedra.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace beltrami
{
namespace
{

/// u = alpha f for f = exp(-|x|^2 / (2 s^2)) in 2 or 3 dimensions, and its
/// graph's analytic quantities at x.
struct GaussianGraph
{
  double Alpha = 1.0, S = 1.0;
  int Dimension = 2;

  struct Values
  {
    double Beltrami, MeanCurvature, Gaussian, Indicator;
  };

  double F(const double* x) const
  {
    double r2 = 0.0;
    for (int a = 0; a < Dimension; ++a)
    {
      r2 += x[a] * x[a];
    }
    return std::exp(-r2 / (2 * S * S));
  }

  Values At(const double* x) const
  {
    const double u = Alpha * F(x), s2 = S * S;
    double g[3], h[3][3], g2 = 0.0, lap = 0.0;
    for (int a = 0; a < Dimension; ++a)
    {
      g[a] = -x[a] / s2 * u;
      g2 += g[a] * g[a];
    }
    for (int a = 0; a < Dimension; ++a)
    {
      for (int b = 0; b < Dimension; ++b)
      {
        h[a][b] = (x[a] * x[b] / (s2 * s2) - (a == b ? 1.0 / s2 : 0.0)) * u;
      }
      lap += h[a][a];
    }
    double hgg = 0.0;
    for (int a = 0; a < Dimension; ++a)
    {
      for (int b = 0; b < Dimension; ++b)
      {
        hgg += g[a] * h[a][b] * g[b];
      }
    }
    const double w2 = 1.0 + g2, w = std::sqrt(w2);
    const double divergence = (w2 * lap - hgg) / (w2 * w); // div(grad u / W)
    Values v;
    v.Beltrami = divergence / w / Alpha;                   // (1/W) div(grad u / W) / alpha
    v.MeanCurvature = std::abs(divergence) / Dimension;
    v.Gaussian = Dimension == 2 ? (h[0][0] * h[1][1] - h[0][1] * h[0][1]) / (w2 * w2) : 0.0;
    v.Indicator = 1.0 / w;
    return v;
  }
};

struct Maps
{
  std::vector<double> Normal, Beltrami, Mean, Gauss, Indicator;
  GraphOperatorOutputs Outputs(Index n, int base, int components)
  {
    Normal.assign(static_cast<std::size_t>(n) * (base + components), 0.0);
    Beltrami.assign(static_cast<std::size_t>(n) * components, 0.0);
    Mean.assign(n, 0.0);
    Gauss.assign(n, 0.0);
    Indicator.assign(n, 0.0);
    return { Normal.data(), Beltrami.data(), Mean.data(), Gauss.data(), Indicator.data() };
  }
};

/// Largest errors against the analytic graph over the vertices `use` accepts.
struct Errors
{
  double Beltrami = 0, Mean = 0, Gauss = 0, Indicator = 0;
  double BeltramiScale = 0, MeanScale = 0, GaussScale = 0;
  void Add(const GaussianGraph::Values& v, double beltrami, double mean, double gauss, double indicator, bool gaussian)
  {
    Beltrami = std::max(Beltrami, std::abs(beltrami - v.Beltrami));
    Mean = std::max(Mean, std::abs(mean - v.MeanCurvature));
    Indicator = std::max(Indicator, std::abs(indicator - v.Indicator));
    BeltramiScale = std::max(BeltramiScale, std::abs(v.Beltrami));
    MeanScale = std::max(MeanScale, v.MeanCurvature);
    if (gaussian)
    {
      Gauss = std::max(Gauss, std::abs(gauss - v.Gaussian));
      GaussScale = std::max(GaussScale, std::abs(v.Gaussian));
    }
  }
};

/// The Gaussian image of n x n pixels on [-4, 4]^2 (s = 1), spacing 8/(n-1).
Errors ImageErrors(int n, double alpha)
{
  GaussianGraph graph;
  graph.Alpha = alpha;
  PixelGrid grid;
  grid.Width = grid.Height = n;
  grid.SpacingX = grid.SpacingY = 8.0 / (n - 1);
  std::vector<double> f(n * n);
  for (int y = 0; y < n; ++y)
  {
    for (int x = 0; x < n; ++x)
    {
      const double p[2] = { -4 + x * grid.SpacingX, -4 + y * grid.SpacingY };
      f[y * n + x] = graph.F(p);
    }
  }
  GraphOperatorOptions o;
  o.ContrastScale = alpha;
  Maps m;
  const GraphOperatorReport r = ComputeImageGraphOperators(grid, 1, f.data(), o, m.Outputs(n * n, 2, 1));
  EXPECT_TRUE(r.Error.empty()) << r.Error;
  EXPECT_EQ(r.ContrastScale, alpha);
  Errors e;
  for (int i = 0; i < n * n; ++i)
  {
    const double p[2] = { -4 + (i % n) * grid.SpacingX, -4 + (i / n) * grid.SpacingY };
    e.Add(graph.At(p), m.Beltrami[i], m.Mean[i], m.Gauss[i], m.Indicator[i], true);
    // K's data part is -alpha Delta_g f; its base part is tangent to the base plane.
    EXPECT_NEAR(m.Normal[3 * i + 2], -alpha * m.Beltrami[i], 1e-12 * (1 + std::abs(m.Normal[3 * i + 2])));
  }
  return e;
}

TEST(GraphOperators, GaussianImageMatchesTheAnalyticGraphAndConverges)
{
  // alpha 2: the graph's slope reaches 1.2, so W matters (a flat-data
  // Laplacian would be 45% off at the steepest pixels).
  const Errors coarse = ImageErrors(65, 2.0), fine = ImageErrors(129, 2.0);
  std::printf("Gaussian image, largest error / largest value at 65^2 and 129^2:\n"
              "  Delta_g f %.2e %.2e, H %.2e %.2e, K %.2e %.2e, 1/W %.2e %.2e\n",
    coarse.Beltrami / coarse.BeltramiScale, fine.Beltrami / fine.BeltramiScale, coarse.Mean / coarse.MeanScale,
    fine.Mean / fine.MeanScale, coarse.Gauss / coarse.GaussScale, fine.Gauss / fine.GaussScale, coarse.Indicator,
    fine.Indicator);
  EXPECT_LT(fine.Beltrami, 0.01 * fine.BeltramiScale);
  EXPECT_LT(fine.Mean, 0.01 * fine.MeanScale);
  EXPECT_LT(fine.Gauss, 0.02 * fine.GaussScale);
  EXPECT_LT(fine.Indicator, 3e-3);
  EXPECT_GT(coarse.Indicator / fine.Indicator, 3.0);
  // Second order: halving the spacing divides each error by about 4.
  EXPECT_GT(coarse.Beltrami / fine.Beltrami, 3.0);
  EXPECT_GT(coarse.Mean / fine.Mean, 3.0);
  EXPECT_GT(coarse.Gauss / fine.Gauss, 3.0);
}

TEST(GraphOperators, LinearDataGiveZeroEverywhere)
{
  // A two-component ramp over an anisotropic grid, borders included (the
  // linear continuation); the indicator is 1/sqrt(1 + alpha^2 |grad f|^2)
  // with both components' gradients.
  PixelGrid grid;
  grid.Width = 23;
  grid.Height = 17;
  grid.SpacingX = 0.5;
  grid.SpacingY = 1.5;
  std::vector<double> f(2 * 23 * 17);
  for (int y = 0; y < 17; ++y)
  {
    for (int x = 0; x < 23; ++x)
    {
      f[2 * (y * 23 + x)] = 0.3 * x * 0.5 - 0.2 * y * 1.5 + 1.0;
      f[2 * (y * 23 + x) + 1] = 0.1 * y * 1.5;
    }
  }
  GraphOperatorOptions o;
  o.ContrastScale = 3.0;
  Maps m;
  ComputeImageGraphOperators(grid, 2, f.data(), o, m.Outputs(23 * 17, 2, 2));
  // Gram matrix of the graph's tangents: G = I + alpha^2 J^T J; area factor sqrt(det G).
  const double a2 = 9.0, gxx = 1 + a2 * 0.09, gyy = 1 + a2 * (0.04 + 0.01), gxy = a2 * (0.3 * -0.2);
  const double indicator = 1.0 / std::sqrt(gxx * gyy - gxy * gxy);
  double worst = 0.0, worstIndicator = 0.0;
  for (std::size_t k = 0; k < m.Normal.size(); ++k)
  {
    worst = std::max(worst, std::abs(m.Normal[k]));
  }
  for (std::size_t i = 0; i < m.Mean.size(); ++i)
  {
    worst = std::max({ worst, std::abs(m.Gauss[i]), m.Mean[i] });
    worstIndicator = std::max(worstIndicator, std::abs(m.Indicator[i] - indicator));
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worstIndicator, 1e-12);
}

/// The Gaussian volume of n^3 voxels on [-4, 4]^3 (s = 1): the grid path's
/// errors, and the largest difference to the tetrahedral mesh path on the
/// same Kuhn tetrahedra at the mesh's interior vertices (the mesh's
/// boundary vertices are undefined there).
Errors VolumeErrors(int n, double alpha, double* sameMesh)
{
  GaussianGraph graph;
  graph.Alpha = alpha;
  graph.Dimension = 3;
  VoxelGrid grid;
  grid.Width = grid.Height = grid.Depth = n;
  grid.SpacingX = grid.SpacingY = grid.SpacingZ = 8.0 / (n - 1);
  const Index count = n * n * n;
  std::vector<double> f(count), points(3 * count);
  for (Index i = 0; i < count; ++i)
  {
    const double p[3] = { -4 + (i % n) * grid.SpacingX, -4 + (i / n % n) * grid.SpacingY,
      -4 + (i / (n * n)) * grid.SpacingZ };
    f[i] = graph.F(p);
    std::copy(p, p + 3, &points[3 * i]);
  }
  GraphOperatorOptions o;
  o.ContrastScale = alpha;
  Maps volume;
  ComputeVolumeGraphOperators(grid, 1, f.data(), o, volume.Outputs(count, 3, 1));
  Errors e;
  for (Index i = 0; i < count; ++i)
  {
    e.Add(graph.At(&points[3 * i]), volume.Beltrami[i], volume.Mean[i], 0.0, volume.Indicator[i], false);
  }
  if (sameMesh)
  {
    Maps mesh;
    const TetrahedralMesh tets(count, GridTetrahedra(n, n, n));
    const GraphOperatorReport r =
      ComputeTetrahedralGraphOperators(tets, points.data(), 1, f.data(), o, mesh.Outputs(count, 3, 1));
    EXPECT_EQ(r.UndefinedVertices, 6 * (n - 2) * (n - 2) + 12 * (n - 2) + 8); // the cube's surface
    Index interior = 0;
    *sameMesh = 0.0;
    for (Index i = 0; i < count; ++i)
    {
      if (!std::isnan(mesh.Beltrami[i]))
      {
        ++interior;
        for (int a = 0; a < 4; ++a)
        {
          *sameMesh = std::max(*sameMesh, std::abs(mesh.Normal[4 * i + a] - volume.Normal[4 * i + a]));
        }
        *sameMesh = std::max(*sameMesh, std::abs(mesh.Indicator[i] - volume.Indicator[i]));
      }
    }
    EXPECT_EQ(interior, (n - 2) * (n - 2) * (n - 2));
  }
  return e;
}

TEST(GraphOperators, GaussianVolumeMatchesTheAnalyticGraphAndTheTetrahedralMesh)
{
  // 3-manifold (x, y, z, alpha f) in R^4: Delta_g f against (1/W) div(grad u / W) / alpha.
  double sameMesh = 1.0;
  const Errors tiny = VolumeErrors(17, 1.5, &sameMesh);
  const Errors coarse = VolumeErrors(33, 1.5, nullptr), fine = VolumeErrors(65, 1.5, nullptr);
  std::printf("Gaussian volume, largest error / largest value at 17^3, 33^3 and 65^3:\n"
              "  Delta_g f %.2e %.2e %.2e, H %.2e %.2e %.2e, 1/W %.2e %.2e %.2e; grid vs mesh path %.1e\n",
    tiny.Beltrami / tiny.BeltramiScale, coarse.Beltrami / coarse.BeltramiScale, fine.Beltrami / fine.BeltramiScale,
    tiny.Mean / tiny.MeanScale, coarse.Mean / coarse.MeanScale, fine.Mean / fine.MeanScale, tiny.Indicator,
    coarse.Indicator, fine.Indicator, sameMesh);
  EXPECT_LT(sameMesh, 1e-12); // the padded grid is the explicit mesh inside
  // The Kuhn tetrahedra (the flows' split) converge at second order, with a
  // larger constant than the pixel grid's two triangulations (their long
  // diagonals): the largest error is at the bump's top.
  EXPECT_GT(coarse.Beltrami / fine.Beltrami, 3.0);
  EXPECT_GT(coarse.Mean / fine.Mean, 3.0);
  EXPECT_GT(coarse.Indicator / fine.Indicator, 3.0);
  EXPECT_LT(fine.Beltrami, 0.04 * fine.BeltramiScale);
  EXPECT_LT(fine.Mean, 0.04 * fine.MeanScale);
  EXPECT_LT(fine.Indicator, 0.015);
  // A linear field gives zero on the whole grid, borders included.
  VoxelGrid grid;
  grid.Width = 9;
  grid.Height = 7;
  grid.Depth = 5;
  grid.SpacingZ = 2.5;
  std::vector<double> f(9 * 7 * 5);
  for (int i = 0; i < 9 * 7 * 5; ++i)
  {
    f[i] = 0.2 * (i % 9) - 0.1 * 2.5 * (i / 63) + 0.05 * (i / 9 % 7);
  }
  GraphOperatorOptions o;
  o.ContrastScale = 2.0;
  Maps volume;
  ComputeVolumeGraphOperators(grid, 1, f.data(), o, volume.Outputs(9 * 7 * 5, 3, 1));
  double worst = 0.0;
  for (const double v : volume.Normal)
  {
    worst = std::max(worst, std::abs(v));
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(GraphOperators, PointDataOnASurfaceMatchTheAnalyticGraph)
{
  // Point data over a flat regular mesh: the graph (x, y, 0, alpha f) in R^4
  // is the image's graph; the mesh boundary is undefined (NaN).
  GaussianGraph graph;
  graph.Alpha = 2.0;
  const int n = 129;
  const test::Mesh m = test::HeightField([](double, double) { return 0.0; }, 4.0, n, 0.0, false, 1);
  const MeshTopology topo = m.Topology();
  std::vector<double> f(m.NumberOfVertices());
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    f[i] = graph.F(&m.Points[3 * i]);
  }
  GraphOperatorOptions o;
  o.ContrastScale = graph.Alpha;
  Maps out;
  const GraphOperatorReport r = ComputeSurfaceGraphOperators(topo, m.Points.data(), 1, f.data(), o,
    out.Outputs(m.NumberOfVertices(), 3, 1));
  EXPECT_EQ(r.UndefinedVertices, 4 * (n - 1));
  Errors e;
  for (Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    if (!topo.IsInterior(i))
    {
      EXPECT_TRUE(std::isnan(out.Beltrami[i]) && std::isnan(out.Gauss[i]));
      continue;
    }
    e.Add(graph.At(&m.Points[3 * i]), out.Beltrami[i], out.Mean[i], out.Gauss[i], out.Indicator[i], true);
  }
  std::printf("Gaussian point data, 129^2 mesh of one diagonal: Delta_g f %.2e, H %.2e, K %.2e of the largest\n",
    e.Beltrami / e.BeltramiScale, e.Mean / e.MeanScale, e.Gauss / e.GaussScale);
  EXPECT_LT(e.Beltrami, 0.01 * e.BeltramiScale);
  EXPECT_LT(e.Mean, 0.01 * e.MeanScale);
  EXPECT_LT(e.Gauss, 0.02 * e.GaussScale);
  EXPECT_LT(e.Indicator, 5e-3);
}

TEST(GraphOperators, AutomaticContrastAndBadInput)
{
  // Noise of 0.05 on a smooth image: the automatic contrast scale is the
  // flows' 1.5 h / sigma with sigma estimated.
  const int n = 128;
  PixelGrid grid;
  grid.Width = grid.Height = n;
  grid.SpacingX = grid.SpacingY = 2.0;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<double> f(n * n);
  for (int i = 0; i < n * n; ++i)
  {
    f[i] = 0.5 + 0.3 * std::sin(0.05 * (i % n)) + noise(rng);
  }
  Maps m;
  GraphOperatorReport r = ComputeImageGraphOperators(grid, 1, f.data(), {}, m.Outputs(n * n, 2, 1));
  EXPECT_TRUE(r.Error.empty());
  EXPECT_NEAR(r.EstimatedNoiseLevel, 0.05, 0.005);
  EXPECT_DOUBLE_EQ(r.ContrastScale, 1.5 * 2.0 / r.EstimatedNoiseLevel);
  GraphOperatorOptions given;
  given.NoiseLevel = 0.1;
  r = ComputeImageGraphOperators(grid, 1, f.data(), given, m.Outputs(n * n, 2, 1));
  EXPECT_DOUBLE_EQ(r.ContrastScale, 30.0);
  EXPECT_EQ(r.EstimatedNoiseLevel, 0.0);
  // Errors, nothing written.
  GraphOperatorOptions bad;
  bad.ContrastScale = -1.0;
  m.Outputs(n * n, 2, 1);
  EXPECT_FALSE(ComputeImageGraphOperators(grid, 1, f.data(), bad, m.Outputs(n * n, 2, 1)).Error.empty());
  EXPECT_FALSE(ComputeImageGraphOperators(grid, 7, f.data(), {}, m.Outputs(n * n, 2, 1)).Error.empty());
  grid.SpacingX = 0.0;
  EXPECT_FALSE(ComputeImageGraphOperators(grid, 1, f.data(), {}, m.Outputs(n * n, 2, 1)).Error.empty());
  EXPECT_EQ(m.Mean[0], 0.0);
  // One pixel: defined, the continuation is constant.
  PixelGrid one;
  one.Width = one.Height = 1;
  const double v = 3.0;
  Maps single;
  r = ComputeImageGraphOperators(one, 1, &v, {}, single.Outputs(1, 2, 1));
  EXPECT_TRUE(r.Error.empty());
  EXPECT_EQ(single.Mean[0], 0.0);
  EXPECT_EQ(single.Indicator[0], 1.0);
}

} // namespace
} // namespace beltrami
