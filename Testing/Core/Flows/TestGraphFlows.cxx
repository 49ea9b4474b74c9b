// The graph (Beltrami) flows of section 3.8 on images and surfaces
// (Flows/GraphFlow) and the colour space of section 3.8.4 (Flows/ColorSpace),
// tested in the core: fixed points, denoising with edges kept, the
// noise-level stop, fixed values, thread independence, reference colours.
#include "TestMeshes.h"

#include "Flows/ColorSpace.h"
#include "Flows/GraphFlow.h"
#include "Flows/GraphFlowDiscretization.h"
#include "Flows/NoiseEstimation.h"
#include "Flows/TensorSpace.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

namespace beltrami
{
namespace
{

double RMS(const std::vector<double>& a, const std::vector<double>& b)
{
  double s = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    s += (a[k] - b[k]) * (a[k] - b[k]);
  }
  return std::sqrt(s / a.size());
}

/// Noise of `sigma` added where `noisy(k)` (the rest exactly as it is).
std::vector<double> WithNoiseWhere(std::vector<double> values, double sigma, unsigned seed,
  const std::function<bool(std::size_t)>& noisy)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (std::size_t k = 0; k < values.size(); ++k)
  {
    values[k] += noisy(k) ? noise(rng) : 0.0;
  }
  return values;
}

TEST(ColorSpace, ReferenceColoursAndRoundTrip)
{
  // White, black and sRGB red (D65): L*u*v* = (100, 0, 0), (0, 0, 0), (53.24, 175.01, 37.76), over 100.
  std::vector<double> c = { 1, 1, 1, 0, 0, 0, 1, 0, 0 };
  RGBToLuv(c.data(), 3, 3);
  EXPECT_NEAR(c[0], 1.0, 1e-6);
  EXPECT_NEAR(c[1], 0.0, 1e-6);
  EXPECT_NEAR(c[2], 0.0, 1e-6);
  EXPECT_NEAR(c[3], 0.0, 1e-9);
  EXPECT_NEAR(c[6], 0.5324, 2e-4);
  EXPECT_NEAR(c[7], 1.7501, 5e-4);
  EXPECT_NEAR(c[8], 0.3776, 5e-4);
  // Random colours with a fourth (alpha) value that must not change; 1 and 2 threads agree bit for bit.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> rgba(4 * 5000);
  for (double& v : rgba)
  {
    v = u(rng);
  }
  std::vector<double> one = rgba, two = rgba;
  RGBToLuv(one.data(), 5000, 4, 1);
  RGBToLuv(two.data(), 5000, 4, 2);
  EXPECT_EQ(one, two);
  LuvToRGB(one.data(), 5000, 4, 2);
  double worst = 0.0;
  for (std::size_t k = 0; k < rgba.size(); ++k)
  {
    worst = std::max(worst, std::abs(one[k] - rgba[k]));
    if (k % 4 == 3)
    {
      EXPECT_EQ(one[k], rgba[k]);
    }
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(ImageGraphFlow, RampsAndConstantsAreFixedPoints)
{
  PixelGrid grid{ 40, 30, 1.0, 1.0 };
  std::vector<double> ramp(40 * 30), constant(40 * 30, 0.7);
  for (Index y = 0; y < 30; ++y)
  {
    for (Index x = 0; x < 40; ++x)
    {
      ramp[y * 40 + x] = 0.03 * x - 0.02 * y + 0.5;
    }
  }
  const std::vector<double> ramp0 = ramp, constant0 = constant;
  GraphFlowOptions o;
  o.ContrastScale = 10.0;
  o.NumberOfIterations = 20;
  o.Stop = GraphFlowStop::Iterations;
  for (GraphFlowIntegration integration : { GraphFlowIntegration::Explicit, GraphFlowIntegration::SemiImplicit })
  {
    o.Integration = integration;
    ASSERT_EQ(RunImageGraphFlow(grid, 1, ramp.data(), nullptr, o).Error, "");
    ASSERT_EQ(RunImageGraphFlow(grid, 1, constant.data(), nullptr, o).Error, "");
    EXPECT_LT(RMS(ramp, ramp0), 1e-7);
    EXPECT_EQ(constant, constant0);
  }
}

/// One explicit step of the image flow at an interior pixel, from a
/// reference in long double: the cotangent weights and mixed areas of the
/// four triangles of each of its cells (both triangulations), the graph
/// points (x sx, y sy, alpha u) in R^(2+NC).
template <int NC>
std::vector<double> ReferenceStep(const PixelGrid& g, const std::vector<double>& u, double alpha, double dt)
{
  using Real = long double;
  const Index w = g.Width, h = g.Height;
  std::vector<Real> mass(w * h, 0), ku(w * h * NC, 0);
  const auto point = [&](Index i, Real* p) {
    p[0] = (i % w) * g.SpacingX;
    p[1] = (i / w) * g.SpacingY;
    for (int k = 0; k < NC; ++k)
    {
      p[2 + k] = alpha * u[i * NC + k];
    }
  };
  const auto triangle = [&](Index a, Index b, Index c) {
    const Index v[3] = { a, b, c };
    Real p[3][2 + NC];
    for (int t = 0; t < 3; ++t)
    {
      point(v[t], p[t]);
    }
    const auto dot = [&](int o, int x, int y) { // (p[x] - p[o]).(p[y] - p[o])
      Real s = 0;
      for (int d = 0; d < 2 + NC; ++d)
      {
        s += (p[x][d] - p[o][d]) * (p[y][d] - p[o][d]);
      }
      return s;
    };
    const Real area2 = dot(0, 1, 1) * dot(0, 2, 2) - dot(0, 1, 2) * dot(0, 1, 2); // (twice the area)^2
    const Real twice = std::sqrt(area2);
    Real cot[3], len2[3]; // at vertex t; the squared length of the edge opposite t
    for (int t = 0; t < 3; ++t)
    {
      cot[t] = dot(t, (t + 1) % 3, (t + 2) % 3) / twice;
      len2[t] = dot((t + 1) % 3, (t + 2) % 3, (t + 2) % 3);
    }
    for (int t = 0; t < 3; ++t)
    {
      const int q = (t + 1) % 3, r = (t + 2) % 3; // edge (q, r) opposite t
      for (int k = 0; k < NC; ++k)
      {
        const Real flux = cot[t] / 2 * (u[v[q] * NC + k] - u[v[r] * NC + k]);
        ku[v[q] * NC + k] += flux;
        ku[v[r] * NC + k] -= flux;
      }
      const bool obtuse = cot[t] < 0, other = cot[q] < 0 || cot[r] < 0;
      mass[v[t]] += obtuse ? twice / 4 : other ? twice / 8 : (len2[q] * cot[q] + len2[r] * cot[r]) / 8;
    }
  };
  for (Index y = 0; y + 1 < h; ++y)
  {
    for (Index x = 0; x + 1 < w; ++x)
    {
      const Index a = y * w + x, b = a + 1, d = a + w, c = d + 1;
      triangle(a, b, c);
      triangle(a, c, d);
      triangle(a, b, d);
      triangle(b, c, d);
    }
  }
  std::vector<double> next(u.size());
  for (Index i = 0; i < w * h; ++i)
  {
    for (int k = 0; k < NC; ++k)
    {
      next[i * NC + k] = static_cast<double>(u[i * NC + k] - dt * ku[i * NC + k] / mass[i]);
    }
  }
  return next;
}

TEST(ImageGraphFlow, SinglePrecisionCellsMatchALongDoubleReferenceAcrossSteepEdges)
{
  // Colour and grey noise on steps of 1 at contrast scales of 50 and 400
  // (rises of 50-400 per pixel), anisotropic spacing; the pixels inside the
  // border compared.  Measured (2-core x86-64): 6e-6 and 5e-7 of the change at 50
  // (grey, colour), 3.3e-4 and 4e-7 at 400; with the areas from
  // |u|^2 |v|^2 - (u.v)^2 in single precision 6e-4 and 1.9e-5 at 400.
  const auto compare = [](auto nc, double alpha, double dt, double bound) {
    constexpr int NC = decltype(nc)::value;
    PixelGrid g{ 48, 40, 0.8, 1.25 };
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 0.1);
    std::vector<double> u(g.Width * g.Height * NC);
    for (Index i = 0; i < g.Width * g.Height; ++i)
    {
      for (int k = 0; k < NC; ++k)
      {
        u[i * NC + k] = ((i % g.Width) > 20 + 5 * k ? 1.0 : 0.0) + ((i / g.Width) > 25 ? 0.5 : 0.0) + noise(rng);
      }
    }
    GraphFlowOptions o;
    o.ContrastScale = alpha;
    o.TimeStep = dt; // (one step: its stability does not matter here)
    o.NumberOfIterations = 1;
    o.Stop = GraphFlowStop::Iterations;
    std::vector<double> flowed = u;
    ASSERT_EQ(RunImageGraphFlow(g, NC, flowed.data(), nullptr, o).Error, "");
    const std::vector<double> reference = ReferenceStep<NC>(g, u, alpha, dt);
    double change = 0.0, error = 0.0;
    for (Index y = 1; y + 1 < g.Height; ++y)
    {
      for (Index x = 1; x + 1 < g.Width; ++x)
      {
        for (int k = 0; k < NC; ++k)
        {
          const std::size_t j = (y * g.Width + x) * NC + k;
          change = std::max(change, std::abs(reference[j] - u[j]));
          error = std::max(error, std::abs(flowed[j] - reference[j]));
        }
      }
    }
    EXPECT_GT(change, 0.005) << NC << " components, contrast " << alpha;
    EXPECT_LT(error, bound * change) << NC << " components, contrast " << alpha << ": " << error
                                     << " of a change of " << change;
  };
  compare(std::integral_constant<int, 1>(), 50.0, 2.0, 3e-5);
  compare(std::integral_constant<int, 3>(), 50.0, 2.0, 3e-6);
  compare(std::integral_constant<int, 1>(), 400.0, 40.0, 1e-3);
  compare(std::integral_constant<int, 3>(), 400.0, 40.0, 3e-6);
}

/// A vertical step of height 1 plus Gaussian noise of 0.1 (64 x 64).
struct NoisyStep
{
  PixelGrid Grid{ 64, 64, 1.0, 1.0 };
  std::vector<double> Clean, Noisy;
  NoisyStep()
  {
    std::mt19937 rng(2);
    std::normal_distribution<double> noise(0.0, 0.1);
    for (Index y = 0; y < 64; ++y)
    {
      for (Index x = 0; x < 64; ++x)
      {
        Clean.push_back(x < 32 ? 0.0 : 1.0);
        Noisy.push_back(Clean.back() + noise(rng));
      }
    }
  }
  double StepHeight(const std::vector<double>& f) const // mean of the columns next to the edge
  {
    double left = 0, right = 0;
    for (Index y = 0; y < 64; ++y)
    {
      left += f[y * 64 + 31];
      right += f[y * 64 + 32];
    }
    return (right - left) / 64;
  }
};

TEST(ImageGraphFlow, RemovesNoiseKeepsTheEdgeAndStopsAtTheNoiseLevel)
{
  NoisyStep s;
  GraphFlowOptions o;
  o.ContrastScale = 15.0; // 1.5 / sigma
  o.Stop = GraphFlowStop::NoiseLevel;
  o.NoiseLevel = 0.1;
  std::vector<double> f = s.Noisy;
  const GraphFlowResult r = RunImageGraphFlow(s.Grid, 1, f.data(), nullptr, o);
  ASSERT_EQ(r.Error, "");
  EXPECT_LT(r.Iterations, 200); // the noise-level stop ended it
  EXPECT_NEAR(r.RMSChange, 0.1, 1e-3);
  EXPECT_LT(r.FinalArea, r.InitialArea);
  EXPECT_LT(RMS(f, s.Clean), 0.5 * RMS(s.Noisy, s.Clean));
  // The edge is kept: linear diffusion (alpha -> 0) stopped at the same
  // noise level flattens it much more.
  std::vector<double> linear = s.Noisy;
  GraphFlowOptions heat = o;
  heat.ContrastScale = 1e-3;
  ASSERT_EQ(RunImageGraphFlow(s.Grid, 1, linear.data(), nullptr, heat).Error, "");
  std::printf("step height: Beltrami %.3f, linear diffusion %.3f; RMS error %.4f vs %.4f\n", s.StepHeight(f),
    s.StepHeight(linear), RMS(f, s.Clean), RMS(linear, s.Clean));
  EXPECT_GT(s.StepHeight(f), 0.75);
  EXPECT_GT(s.StepHeight(f), s.StepHeight(linear) + 0.1);
  EXPECT_LT(RMS(f, s.Clean), RMS(linear, s.Clean));
  // The same run on 1 thread: the same values (deterministic sums).
  std::vector<double> g = s.Noisy;
  o.NumberOfThreads = 1;
  RunImageGraphFlow(s.Grid, 1, g.data(), nullptr, o);
  EXPECT_EQ(f, g);
}

TEST(ImageGraphFlow, FixedPixelsKeepTheirValuesAndBadInputIsAnError)
{
  NoisyStep s;
  std::vector<std::uint8_t> fixed(s.Noisy.size(), 0);
  for (std::size_t k = 0; k < fixed.size(); k += 7)
  {
    fixed[k] = 1;
  }
  GraphFlowOptions o;
  o.ContrastScale = 15.0;
  std::vector<double> f = s.Noisy;
  ASSERT_EQ(RunImageGraphFlow(s.Grid, 1, f.data(), fixed.data(), o).Error, "");
  for (std::size_t k = 0; k < fixed.size(); ++k)
  {
    if (fixed[k])
    {
      EXPECT_EQ(f[k], s.Noisy[k]);
    }
  }
  f[5] = std::nan("");
  const std::vector<double> before = f;
  EXPECT_NE(RunImageGraphFlow(s.Grid, 1, f.data(), nullptr, o).Error, "");
  o.ContrastScale = -1.0;
  EXPECT_NE(RunImageGraphFlow(s.Grid, 1, f.data(), nullptr, o).Error, "");
  for (std::size_t k = 0; k < f.size(); ++k) // nothing changed (NaN stays NaN)
  {
    EXPECT_TRUE(f[k] == before[k] || (std::isnan(f[k]) && std::isnan(before[k])));
  }
}

TEST(GraphFlowOptions, AutomaticStepAndEdgeLengthUnitsAreTheFiltersDefaults)
{
  // Images (vtkImageBeltramiDenoising's defaults, GraphFlowOptions{}):
  // TimeStep 0 means 0.2 explicit steps on pixel grids.
  PixelGrid grid{ 24, 20, 1.0, 1.0 };
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<double> image(24 * 20);
  for (double& v : image)
  {
    v = 0.5 + noise(rng);
  }
  std::vector<double> automatic = image, spelledOut = image;
  const GraphFlowResult a = RunImageGraphFlow(grid, 1, automatic.data(), nullptr, GraphFlowOptions{});
  GraphFlowOptions explicitSteps;
  explicitSteps.TimeStep = 0.2;
  RunImageGraphFlow(grid, 1, spelledOut.data(), nullptr, explicitSteps);
  EXPECT_EQ(a.LastTimeStep, 0.2);
  EXPECT_EQ(automatic, spelledOut);
  EXPECT_LT(RMS(automatic, std::vector<double>(image.size(), 0.5)), 0.5 * RMS(image, std::vector<double>(image.size(), 0.5)));

  // Meshes (the mesh filters' defaults, ForMeshes()): semi-implicit steps of
  // 0.1 h^2 with the mesh measured in its mean edge length h - the same
  // numbers as physical units on the mesh scaled by 1/h (to rounding: the
  // automatic contrast scale is relative to the mean edge length, 1 there);
  // the time and the area come back in the mesh's units.
  test::Mesh sphere = test::OctahedronSphere(3);
  for (double& x : sphere.Points)
  {
    x *= 7.0;
  }
  const MeshTopology topo = sphere.Topology();
  const Index n = topo.NumberOfVertices();
  const double h = MeanEdgeLength(topo, sphere.Points.data());
  std::vector<double> f(n);
  for (Index i = 0; i < n; ++i)
  {
    f[i] = sphere.Points[3 * i + 2] / 7.0 + noise(rng);
  }
  std::vector<double> inEdgeLengths = f, inPhysical = f;
  const GraphFlowOptions defaults = GraphFlowOptions::ForMeshes();
  EXPECT_EQ(defaults.Integration, GraphFlowIntegration::SemiImplicit);
  const GraphFlowResult r = RunSurfaceGraphFlow(topo, sphere.Points.data(), 1, inEdgeLengths.data(), nullptr, defaults);
  ASSERT_EQ(r.Error, "");
  std::vector<double> scaled = sphere.Points;
  for (double& x : scaled)
  {
    x /= h;
  }
  GraphFlowOptions physical = defaults;
  physical.Units = LengthUnit::Physical;
  const GraphFlowResult p = RunSurfaceGraphFlow(topo, scaled.data(), 1, inPhysical.data(), nullptr, physical);
  for (Index i = 0; i < n; ++i)
  {
    EXPECT_NEAR(inEdgeLengths[i], inPhysical[i], 1e-9);
  }
  EXPECT_EQ(r.Iterations, p.Iterations);
  EXPECT_GT(r.Iterations, 0);
  EXPECT_NEAR(r.Time, p.Time * h * h, 1e-12 * r.Time);
  EXPECT_NEAR(r.InitialArea, p.InitialArea * h * h, 1e-12 * r.InitialArea);
  EXPECT_NEAR(r.Time, r.Iterations * 0.1 * h * h, 1e-12 * r.Time);
}

TEST(SurfaceGraphFlow, SmoothsDataOnASphereAndKeepsConstantsAndFixedPoints)
{
  const test::Mesh sphere = test::OctahedronSphere(4);
  const MeshTopology topo = sphere.Topology();
  const Index n = topo.NumberOfVertices();
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<double> clean(n), noisy(n), constant(n, 2.5);
  std::vector<std::uint8_t> fixed(n, 0);
  for (Index i = 0; i < n; ++i)
  {
    clean[i] = sphere.Points[3 * i + 2]; // f = z
    noisy[i] = clean[i] + noise(rng);
    fixed[i] = i % 11 == 0;
  }
  GraphFlowOptions o;
  o.Units = LengthUnit::Physical; // settings in the mesh's own units
  o.Integration = GraphFlowIntegration::SemiImplicit;
  o.ContrastScale = 0.2;
  o.TimeStep = 0.002;
  o.NumberOfIterations = 5;
  o.Stop = GraphFlowStop::Iterations;
  std::vector<double> f = noisy;
  const GraphFlowResult r = RunSurfaceGraphFlow(topo, sphere.Points.data(), 1, f.data(), fixed.data(), o);
  ASSERT_EQ(r.Error, "");
  EXPECT_GT(r.SolverIterations, 0);
  EXPECT_LT(RMS(f, clean), 0.6 * RMS(noisy, clean));
  for (Index i = 0; i < n; ++i)
  {
    if (fixed[i])
    {
      EXPECT_EQ(f[i], noisy[i]);
    }
  }
  const std::vector<double> constant0 = constant;
  ASSERT_EQ(RunSurfaceGraphFlow(topo, sphere.Points.data(), 1, constant.data(), nullptr, o).Error, "");
  EXPECT_LT(RMS(constant, constant0), 1e-9);
}

TEST(SurfaceGraphFlow, SemiImplicitSolvesReachTheirToleranceOrSaySo)
{
  // Data on a fan of 2,000 slivers round one point (test::FannedDisk), at
  // the defaults (the least-risk stop, its solves to 1e-8): Jacobi alone
  // stopped short of the tolerance in some of them, unsaid; the solves go
  // on with the algebraic multigrid there.  With too few iterations for
  // any solve, the result says so.
  const test::Mesh disk = test::FannedDisk(2000);
  const MeshTopology topo = disk.Topology();
  const Index n = topo.NumberOfVertices();
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<double> values(n);
  for (Index i = 0; i < n; ++i)
  {
    values[i] = disk.Points[3 * i] + noise(rng);
  }
  GraphFlowOptions o;
  o.Integration = GraphFlowIntegration::SemiImplicit;
  for (int most : { 500, 2 })
  {
    o.MaximumSolverIterations = most;
    std::vector<double> f = values;
    const GraphFlowResult r = RunSurfaceGraphFlow(topo, disk.Points.data(), 1, f.data(), nullptr, o);
    ASSERT_EQ(r.Error, "");
    std::printf("at most %d iterations a solve: %d steps, %d iterations, %s (largest residual %.3g)\n", most,
      r.Iterations, r.SolverIterations, r.SolverConverged ? "converged" : "short", r.LargestSolverResidual);
    EXPECT_GT(r.Iterations, 0);
    EXPECT_EQ(r.SolverConverged, most == 500);
    EXPECT_EQ(r.LargestSolverResidual > 0.0, most == 2);
  }
}

TEST(LeastRiskStop, TheSemiImplicitProbeSolvesOnlyItsDifferenceToTheMainRun)
{
  // The risk's probe differs from the data by 1% of the noise; its solves
  // start from the main run's new state plus the last difference, so the
  // solver tolerance applies to the difference: the same estimated errors
  // and stop at the default tolerance as at 1e-12, for fewer iterations
  // than solving both runs to 1e-8.
  const test::Mesh sphere = test::OctahedronSphere(5);
  const MeshTopology topo = sphere.Topology();
  const Index n = topo.NumberOfVertices();
  std::vector<double> clean(n);
  for (Index i = 0; i < n; ++i)
  {
    clean[i] = (sphere.Points[3 * i] > 0.1 ? 1.0 : 0.0) + std::sin(3.0 * sphere.Points[3 * i + 1]);
  }
  const std::vector<double> noisy = WithNoiseWhere(clean, 0.05, 4, [](std::size_t) { return true; });
  const auto run = [&](double tolerance, std::vector<double>& f) {
    GraphFlowOptions o = GraphFlowOptions::ForMeshes();
    o.NoiseLevel = 0.05;
    o.SolverTolerance = tolerance;
    f = noisy;
    return RunSurfaceGraphFlow(topo, sphere.Points.data(), 1, f.data(), nullptr, o);
  };
  std::vector<double> f[3];
  const GraphFlowResult strict = run(1e-12, f[0]), tight = run(1e-8, f[1]), loose = run(1e-4, f[2]);
  std::printf("steps %d %d %d, estimated error %.6f %.6f %.6f (true %.6f), solver iterations %d %d %d\n",
    strict.Iterations, tight.Iterations, loose.Iterations, strict.FinalRisk, tight.FinalRisk, loose.FinalRisk,
    RMS(f[2], clean), strict.SolverIterations, tight.SolverIterations, loose.SolverIterations);
  ASSERT_GT(strict.Iterations, 10);
  EXPECT_EQ(loose.Iterations, strict.Iterations);
  EXPECT_NEAR(loose.FinalRisk, strict.FinalRisk, 1e-4 * strict.FinalRisk);
  EXPECT_LT(RMS(f[2], f[0]), 1e-5 * 0.05);
  EXPECT_NEAR(strict.FinalRisk, RMS(f[0], clean), 0.1 * RMS(f[0], clean));
  EXPECT_LT(loose.SolverIterations, 0.8 * tight.SolverIterations);
}

TEST(NoiseEstimation, WithinTenPercentOnASyntheticImageWithEdges)
{
  // A 256 x 256 image with a ramp, a smooth bump and a step edge (the
  // structure a plain mask would count as noise), two components, plus
  // Gaussian noise; and pure noise on a constant image.
  const Index n = 256;
  PixelGrid grid{ n, n, 1.0, 1.0 };
  std::vector<double> clean(2 * n * n);
  for (Index y = 0; y < n; ++y)
  {
    for (Index x = 0; x < n; ++x)
    {
      const double bump = 0.3 * std::exp(-((x - 80.0) * (x - 80.0) + (y - 150.0) * (y - 150.0)) / 800.0);
      clean[2 * (y * n + x)] = 0.002 * x + bump + (x > 170 ? 0.5 : 0.0);
      clean[2 * (y * n + x) + 1] = 0.5 + 0.2 * std::sin(0.05 * x) * std::cos(0.04 * y);
    }
  }
  for (double sigma : { 0.02, 0.05, 0.1, 0.2 })
  {
    std::mt19937 rng(17);
    std::normal_distribution<double> noise(0.0, sigma);
    std::vector<double> noisy = clean, flat(n * n, 0.5);
    for (double& v : noisy)
    {
      v += noise(rng);
    }
    for (double& v : flat)
    {
      v += noise(rng);
    }
    const double estimate = EstimateImageNoise(grid, 2, noisy.data());
    const double pure = EstimateImageNoise(grid, 1, flat.data());
    std::printf("sigma %.2f: estimated %.4f (%+.1f%%), on pure noise %.4f (%+.1f%%)\n", sigma, estimate,
      100 * (estimate / sigma - 1), pure, 100 * (pure / sigma - 1));
    EXPECT_NEAR(estimate, sigma, 0.1 * sigma);
    EXPECT_NEAR(pure, sigma, 0.03 * sigma);
  }
  PixelGrid tiny{ 2, 5, 1.0, 1.0 };
  std::vector<double> few(10, 1.0);
  EXPECT_EQ(EstimateImageNoise(tiny, 1, few.data()), 0.0);
}


TEST(NoiseEstimation, FlatRegionsNeitherHideTheNoiseNorTurnCleanEdgesIntoNoise)
{
  // Noisy data on a part, the rest exactly flat (a masked background, a
  // black border: from a quarter of the samples on, the estimate was 0);
  // and clean piecewise-constant data with curved and slanted edges (no
  // noise: 0, as the flat samples are most of them).  Image: shapes on a
  // black background, a third of the pixels noisy.
  const Index n = 256;
  PixelGrid grid{ n, n, 1.0, 1.0 };
  std::vector<double> shapes(n * n, 0.0);
  std::vector<std::uint8_t> inside(n * n, 0);
  for (Index y = 0; y < n; ++y)
  {
    for (Index x = 0; x < n; ++x)
    {
      const bool disk = (x - 90.0) * (x - 90.0) + (y - 110.0) * (y - 110.0) < 70.0 * 70.0;
      const bool band = std::abs(0.6 * x + 0.8 * y - 250.0) < 25.0 && x > 120; // a slanted strip
      inside[y * n + x] = disk || band;
      shapes[y * n + x] = disk ? 0.7 : band ? 0.4 : 0.0;
    }
  }
  // Volume: a ball of radius 20 in 56^3 (19% of the voxels), exactly 0 around it.
  // (The estimate of a smaller ball is high even without flat data: at
  // radius 15 and sigma 0.02 by 16% over its voxels, the windows across its
  // edge; 5% over a volume all noisy.)
  VoxelGrid volume;
  volume.Width = volume.Height = volume.Depth = 56;
  std::vector<double> ball(56 * 56 * 56);
  for (std::size_t k = 0; k < ball.size(); ++k)
  {
    const double x = k % 56 - 27.3, y = k / 56 % 56 - 28.1, z = k / 3136 - 26.7;
    ball[k] = x * x + y * y + z * z < 20.0 * 20.0 ? 1.0 + 0.002 * x : 0.0;
  }
  // Point data on a sphere: noisy on the cap z > 0.2 (40% of the vertices), 0 elsewhere;
  // clean: 1 on the cap.
  const test::Mesh sphere = test::OctahedronSphere(5);
  const MeshTopology topo = sphere.Topology();
  const Index nv = topo.NumberOfVertices();
  std::vector<double> cap(nv);
  for (Index i = 0; i < nv; ++i)
  {
    cap[i] = sphere.Points[3 * i + 2] > 0.2 ? 1.0 + sphere.Points[3 * i] : 0.0;
  }
  GraphFlowOptions report; // (no step: the estimate alone)
  report.Stop = GraphFlowStop::Iterations;
  report.NumberOfIterations = 0;
  const auto onSphere = [&](std::vector<double> f) {
    return RunSurfaceGraphFlow(topo, sphere.Points.data(), 1, f.data(), nullptr, report).EstimatedNoiseLevel;
  };
  for (double sigma : { 0.02, 0.05, 0.1, 0.2 })
  {
    const double image = EstimateImageNoise(grid, 1,
      WithNoiseWhere(shapes, sigma, 3, [&](std::size_t k) { return inside[k] != 0; }).data());
    const double voxels = EstimateVolumeNoise(volume, 1,
      WithNoiseWhere(ball, sigma, 4, [&](std::size_t k) { return ball[k] != 0.0; }).data());
    const double points = onSphere(WithNoiseWhere(cap, sigma, 5, [&](std::size_t k) { return cap[k] != 0.0; }));
    std::printf("sigma %.2f, noise on a part only: image %.4f (%+.1f%%), volume %.4f (%+.1f%%), sphere %.4f (%+.1f%%)\n",
      sigma, image, 100 * (image / sigma - 1), voxels, 100 * (voxels / sigma - 1), points, 100 * (points / sigma - 1));
    EXPECT_NEAR(image, sigma, 0.1 * sigma);
    EXPECT_NEAR(voxels, sigma, 0.1 * sigma);
    EXPECT_NEAR(points, sigma, 0.1 * sigma);
  }
  EXPECT_EQ(EstimateImageNoise(grid, 1, shapes.data()), 0.0);
  EXPECT_EQ(EstimateVolumeNoise(volume, 1, ball.data()), 0.0);
  std::vector<double> cleanCap(nv);
  std::transform(cap.begin(), cap.end(), cleanCap.begin(), [](double v) { return v != 0.0 ? 1.0 : 0.0; });
  EXPECT_EQ(onSphere(cleanCap), 0.0);
}


TEST(LeastRiskStop, AWindowedProbeStopsWhereTheFullProbeDoes)
{
  // A volume of more than 2^21 voxels (96 x 96 x 256): the risk's probe runs
  // on a band of 16 planes plus margins, compared with the main run there,
  // an eighth of the work of a probe over everything; the stop, the result
  // and the estimated error stay those of the full probe.
  VoxelGrid grid;
  grid.Width = grid.Height = 96;
  grid.Depth = 256;
  const std::size_t n = static_cast<std::size_t>(grid.Width * grid.Height * grid.Depth);
  std::vector<double> clean(n), noisy(n);
  std::mt19937 rng(21);
  std::normal_distribution<double> noise(0.0, 0.08);
  for (std::int64_t z = 0, k = 0; z < grid.Depth; ++z)
  {
    for (std::int64_t y = 0; y < grid.Height; ++y)
    {
      for (std::int64_t x = 0; x < grid.Width; ++x, ++k)
      {
        clean[k] = 0.4 + 0.25 * std::sin(x / 9.0) * std::cos(y / 7.0 + z / 11.0) + 0.3 * ((x + z / 3) % 64 < 32);
        noisy[k] = clean[k] + noise(rng);
      }
    }
  }
  GraphFlowResult results[2];
  double psnr[2];
  for (int windowed : { 0, 1 })
  {
    std::vector<double> v = noisy;
    GraphFlowOptions o; // the defaults: automatic contrast, least-risk stop
    o.WindowedRisk = windowed;
    results[windowed] = RunVolumeGraphFlow(grid, 1, v.data(), nullptr, o);
    ASSERT_EQ(results[windowed].Error, "");
    psnr[windowed] = -10 * std::log10(RMS(v, clean) * RMS(v, clean));
  }
  std::printf("least-risk stop, full probe: %d steps, %.3f dB, estimated error %.5f; windowed: %d steps, %.3f dB, "
              "%.5f\n", results[0].Iterations, psnr[0], results[0].FinalRisk, results[1].Iterations, psnr[1],
    results[1].FinalRisk);
  EXPECT_GT(results[0].Iterations, 5);
  EXPECT_LE(std::abs(results[1].Iterations - results[0].Iterations), 2);
  EXPECT_NEAR(psnr[1], psnr[0], 0.05);
  EXPECT_NEAR(results[1].FinalRisk, results[0].FinalRisk, 0.1 * results[0].FinalRisk);
  EXPECT_NEAR(results[1].InitialRisk, results[0].InitialRisk, 1e-9); // the noise level: SURE of the input
}

TEST(LeastRiskStop, AColourImageOfMoreThan2To21ValuesProbesABandOfRows)
{
  // 1024 x 768 RGB (2.4M values): the probe runs on a band of 1/8 of the
  // rows plus margins; the stop stays within two steps of the full probe's
  // and the result within 0.1 dB (the times printed).  The image's
  // content changes from row to row (a band of 1/16 of the rows stopped
  // later on photographs).
  PixelGrid grid{ 1024, 768, 1.0, 1.0 };
  const std::size_t n = static_cast<std::size_t>(grid.Width * grid.Height) * 3;
  std::vector<double> clean(n), noisy(n);
  std::mt19937 rng(29);
  std::normal_distribution<double> noise(0.0, 0.1);
  for (std::int64_t y = 0, k = 0; y < grid.Height; ++y)
  {
    for (std::int64_t x = 0; x < grid.Width; ++x)
    {
      const double r = std::hypot(x - 400.0, y - 300.0);
      for (int c = 0; c < 3; ++c, ++k)
      {
        clean[k] = 0.5 + 0.2 * std::sin((x + 40 * c) / (12.0 + y / 64.0)) * std::cos(y / 23.0) +
          0.25 * (r < 180.0 + 30 * c) - 0.2 * ((x / 128 + y / 96) % 2);
        noisy[k] = clean[k] + noise(rng);
      }
    }
  }
  GraphFlowResult results[2];
  double psnr[2], seconds[2];
  for (int windowed : { 0, 1 })
  {
    std::vector<double> v = noisy;
    GraphFlowOptions o; // the defaults: automatic contrast, least-risk stop
    o.WindowedRisk = windowed;
    const auto start = std::chrono::steady_clock::now();
    results[windowed] = RunImageGraphFlow(grid, 3, v.data(), nullptr, o);
    seconds[windowed] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_EQ(results[windowed].Error, "");
    psnr[windowed] = -10 * std::log10(RMS(v, clean) * RMS(v, clean));
  }
  std::printf("colour image, full probe: %d steps, %.3f dB, %.2f s; band of rows: %d steps, %.3f dB, %.2f s\n",
    results[0].Iterations, psnr[0], seconds[0], results[1].Iterations, psnr[1], seconds[1]);
  EXPECT_GT(results[0].Iterations, 5);
  EXPECT_LE(std::abs(results[1].Iterations - results[0].Iterations), 2);
  EXPECT_NEAR(psnr[1], psnr[0], 0.1);
  EXPECT_NEAR(results[1].InitialRisk, results[0].InitialRisk, 1e-9);
}

TEST(LeastRiskStop, FusedStepsReportTheFiguresOfTheStatesTheyStepFrom)
{
  // Explicit volume steps evaluate the state they step from: the input's
  // area comes with the first step and the least-risk state's with the
  // step after it (no pass of its own).  The figures are those of runs
  // that evaluate the same states on their own, and a run of no step
  // leaves the data bit-exact.
  VoxelGrid grid;
  grid.Width = grid.Height = grid.Depth = 40;
  std::vector<double> noisy(40 * 40 * 40);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (std::size_t k = 0; k < noisy.size(); ++k)
  {
    noisy[k] = 0.5 + 0.3 * ((k % 40) < 20) + noise(rng);
  }
  std::vector<double> least = noisy, fixed = noisy, input = noisy;
  GraphFlowOptions o;
  const GraphFlowResult risk = RunVolumeGraphFlow(grid, 1, least.data(), nullptr, o);
  ASSERT_EQ(risk.Error, "");
  ASSERT_GT(risk.Iterations, 3);
  o.Stop = GraphFlowStop::Iterations;
  o.ContrastScale = risk.ContrastScale;
  o.NumberOfIterations = risk.Iterations;
  const GraphFlowResult steps = RunVolumeGraphFlow(grid, 1, fixed.data(), nullptr, o);
  o.NumberOfIterations = 0;
  const GraphFlowResult none = RunVolumeGraphFlow(grid, 1, input.data(), nullptr, o);
  EXPECT_EQ(least, fixed);
  EXPECT_EQ(input, noisy);
  EXPECT_EQ(risk.InitialArea, none.InitialArea);
  EXPECT_EQ(steps.InitialArea, none.InitialArea);
  EXPECT_EQ(risk.FinalArea, steps.FinalArea);
  EXPECT_LT(risk.FinalArea, 0.9 * risk.InitialArea);
  EXPECT_EQ(risk.SmallestStableStep, std::min(steps.SmallestStableStep, risk.SmallestStableStep));
}

/// The base discretization's probe signs (a minimal discretization).
struct SignsOnly final : detail::FlowDiscretization
{
  void Update(const double*) override {}
  void Apply(const double*, double*, bool) override {}
  double EstimateNoise(const double*) const override { return 0.0; }
};

TEST(LeastRiskStop, TheProbeSignsOfAWindowAreThoseOfTheWholeSequence)
{
  // A probe window's signs are the whole sequence's at its values (the
  // state jumped ahead to the window's start), so a windowed probe sees
  // the signs a full probe would.
  SignsOnly d;
  d.Size = 40000;
  d.Components = 3;
  UninitializedVector<double> all, window;
  d.ProbeSigns(0, 120000, all);
  ASSERT_EQ(all.size(), 120000u);
  double sum = 0.0;
  for (double b : all)
  {
    ASSERT_TRUE(b == 1.0 || b == -1.0);
    sum += b;
  }
  EXPECT_LT(std::abs(sum), 5.0 * std::sqrt(120000.0)); // balanced
  for (std::size_t begin : { std::size_t(0), std::size_t(1), std::size_t(777), std::size_t(65536), std::size_t(99999) })
  {
    d.ProbeSigns(begin, begin + 20001, window);
    EXPECT_TRUE(std::equal(window.begin(), window.end(), all.begin() + static_cast<std::ptrdiff_t>(begin))) << begin;
  }
}

} // namespace
} // namespace beltrami

using namespace beltrami;

TEST(TensorSpace, LogCoordinatesRoundTripAndMeasureTheLogEuclideanDistance)
{
  // Random SPD tensors (VTK order XX, YY, ZZ, XY, YZ, XZ) and back.
  std::mt19937 rng(8);
  std::normal_distribution<double> g;
  std::vector<double> t;
  for (int i = 0; i < 200; ++i)
  {
    Eigen::Matrix3d a;
    for (int k = 0; k < 9; ++k)
    {
      a(k / 3, k % 3) = g(rng);
    }
    const Eigen::Matrix3d spd = a * a.transpose() + 0.01 * Eigen::Matrix3d::Identity();
    t.insert(t.end(), { spd(0, 0), spd(1, 1), spd(2, 2), spd(0, 1), spd(1, 2), spd(0, 2) });
  }
  std::vector<double> logs = t;
  EXPECT_EQ(SymmetricTensorsToLog(logs.data(), 200, 6, 1e-12, 2), 0);
  std::vector<double> back = logs;
  LogToSymmetricTensors(back.data(), 200, 6, 2);
  double worst = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k)
  {
    worst = std::max(worst, std::abs(back[k] - t[k]) / (1.0 + std::abs(t[k])));
  }
  EXPECT_LT(worst, 1e-10);
  // The identity is 0; diag(e, 1, 1) rotated by 45 degrees about z has the
  // log coordinates of (1/2)[[1, 1, 0], [1, 1, 0], [0, 0, 0]]: off-diagonal
  // times sqrt 2, so the 6-vector's norm is the Frobenius norm (1).
  const double c = std::exp(1.0);
  std::vector<double> two = { 1, 1, 1, 0, 0, 0, (c + 1) / 2, (c + 1) / 2, 1, (c - 1) / 2, 0, 0 };
  SymmetricTensorsToLog(two.data(), 2, 6, 1e-12);
  const std::vector<double> expected = { 0, 0, 0, 0, 0, 0, 0.5, 0.5, 0, 0.5 * std::sqrt(2.0), 0, 0 };
  for (std::size_t k = 0; k < two.size(); ++k)
  {
    EXPECT_NEAR(two[k], expected[k], 1e-12) << k;
  }
  // Indefinite tensors are raised to the floor and counted.
  std::vector<double> bad = { 1, 1, 1, 0, 0, 0, 1, -1, 1, 0, 0, 0 };
  EXPECT_EQ(SymmetricTensorsToLog(bad.data(), 2, 6, 1e-3), 1);
  LogToSymmetricTensors(bad.data(), 2, 6);
  EXPECT_NEAR(bad[7], 1e-3, 1e-12);
}
