// The fairing's step chosen on a sample of a large surface
// (Flows/FairingStepChoice.h, FairWithSampledSearch; FairingOptions::
// StepSearchPoints): as near the clean surface as the whole surface's
// search, and the same sample whatever the order of the points.
#include "Flows/Fairing.h"
#include "TestMeshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using namespace beltrami;

namespace
{

/// bunny00 with normal noise of `level` times its diagonal along its
/// vertices' normals (fixed seed).
test::Mesh NoisyBunny(double level, double& diagonal)
{
  std::string error;
  test::Mesh m = test::ReadMesh("bunny00.off", error);
  EXPECT_EQ(error, "");
  const Index n = m.NumberOfVertices();
  std::vector<Eigen::Vector3d> normals(static_cast<std::size_t>(n), Eigen::Vector3d::Zero());
  Eigen::Vector3d low = m.Point(0), high = low;
  for (std::size_t t = 0; t < m.Triangles.size(); t += 3)
  {
    const Eigen::Vector3d a = m.Point(m.Triangles[t]), b = m.Point(m.Triangles[t + 1]), c = m.Point(m.Triangles[t + 2]);
    for (int k = 0; k < 3; ++k)
    {
      normals[m.Triangles[t + k]] += (b - a).cross(c - a);
    }
  }
  for (Index v = 0; v < n; ++v)
  {
    low = low.cwiseMin(m.Point(v));
    high = high.cwiseMax(m.Point(v));
  }
  diagonal = (high - low).norm();
  std::mt19937_64 random(5);
  std::normal_distribution<double> normal(0.0, level * diagonal);
  for (Index v = 0; v < n; ++v)
  {
    m.SetPoint(v, m.Point(v) + normal(random) * normals[v].normalized());
  }
  return m;
}

/// The defaults on `m` with StepSearchPoints `search`; the points into `out`.
FairingReport Faired(const test::Mesh& m, std::int64_t search, std::vector<double>& out)
{
  const MeshTopology topology = m.Topology();
  FairingOptions o;
  o.StepSearchPoints = search;
  o.NumberOfThreads = 2;
  out = m.Points;
  return FairSurface(topology, out.data(), o, FairingConstraints(), nullptr, nullptr);
}

/// The RMS distance between two point sets (3 per point) over `diagonal`.
double Rms(const std::vector<double>& a, const std::vector<double>& b, double diagonal)
{
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    sum += (a[k] - b[k]) * (a[k] - b[k]);
  }
  return std::sqrt(sum / static_cast<double>(a.size() / 3)) / diagonal;
}

} // namespace

TEST(FairingSample, TheStepChosenOnASampleEndsAsNearAsTheWholeSurfacesSearch)
{
  // bunny00 (37,706 points) with noise of 0.1%, 0.3% and 1% of its
  // diagonal: a sample of 4,096 points (eight balls) chooses a step that
  // ends within 10% of the whole surface's search in RMS from the clean
  // surface (a step of sqrt 2 more or less moves it a few percent).
  std::string error;
  const test::Mesh clean = test::ReadMesh("bunny00.off", error);
  for (const double level : { 0.001, 0.003, 0.01 })
  {
    double diagonal = 0.0;
    const test::Mesh noisy = NoisyBunny(level, diagonal);
    std::vector<double> whole, sampled;
    const FairingReport all = Faired(noisy, 0, whole), part = Faired(noisy, 4096, sampled);
    ASSERT_EQ(all.Error, "");
    ASSERT_EQ(part.Error, "");
    const double input = Rms(noisy.Points, clean.Points, diagonal);
    const double a = Rms(whole, clean.Points, diagonal), b = Rms(sampled, clean.Points, diagonal);
    std::printf("noise %g: input %.6f, whole surface's step %.4g (operator %d) %.6f, sample of %d points' step "
                "%.4g (operator %d) %.6f\n",
      level, input, all.ChosenTimeStep, static_cast<int>(all.OperatorUsed), a, static_cast<int>(part.SampledPoints),
      part.ChosenTimeStep, static_cast<int>(part.OperatorUsed), b);
    EXPECT_EQ(all.SampledPoints, 0);
    EXPECT_GT(part.SampledPoints, 3800);
    EXPECT_LE(part.SampledPoints, 4097);
    EXPECT_GT(part.ChosenTimeStep, 0.0);
    EXPECT_LE(b, 1.1 * a) << level;
    EXPECT_LT(b, 0.7 * input) << level;
  }
}

TEST(FairingSample, TheSampleDoesNotDependOnThePointsOrder)
{
  // The same noisy surface with its points renumbered backwards and its
  // triangles in reverse order: the same sample, noise, step and operator
  // (the sample is ordered by the points' coordinates), and the same points
  // to the solver's tolerance.
  double diagonal = 0.0;
  const test::Mesh noisy = NoisyBunny(0.003, diagonal);
  const Index n = noisy.NumberOfVertices();
  test::Mesh reversed;
  for (Index v = n - 1; v >= 0; --v)
  {
    reversed.Points.insert(reversed.Points.end(), noisy.Points.begin() + 3 * v, noisy.Points.begin() + 3 * v + 3);
  }
  for (std::size_t t = noisy.Triangles.size(); t >= 3; t -= 3)
  {
    for (int k = 0; k < 3; ++k)
    {
      reversed.Triangles.push_back(n - 1 - noisy.Triangles[t - 3 + k]);
    }
  }
  std::vector<double> a, b;
  const FairingReport first = Faired(noisy, 4096, a), second = Faired(reversed, 4096, b);
  EXPECT_EQ(first.SampledPoints, second.SampledPoints);
  EXPECT_EQ(first.Noise, second.Noise);
  EXPECT_EQ(first.ChosenTimeStep, second.ChosenTimeStep);
  EXPECT_EQ(first.OperatorUsed, second.OperatorUsed);
  EXPECT_EQ(first.EstimatedError, second.EstimatedError);
  double largest = 0.0;
  for (Index v = 0; v < n; ++v)
  {
    for (int c = 0; c < 3; ++c)
    {
      largest = std::max(largest, std::abs(a[3 * v + c] - b[3 * (n - 1 - v) + c]));
    }
  }
  EXPECT_LT(largest, 1e-3 * 0.003 * diagonal); // (the solves' tolerance, of the move)
}

TEST(FairingSample, ASampleThatWouldNotBeSmallerIsNotTaken)
{
  // Coordinates of 1e300, whose squared distances overflow (balls of
  // infinite radius, the sample the whole surface), and a surface whose
  // points are all one point: the whole surface's path (its report, no
  // sample), not a sample of it searched again and again.
  double diagonal = 0.0;
  test::Mesh huge = NoisyBunny(0.003, diagonal), same = huge;
  for (double& c : huge.Points)
  {
    c *= 1e300;
  }
  std::fill(same.Points.begin(), same.Points.end(), 1.0);
  for (const test::Mesh* m : { &huge, &same })
  {
    std::vector<double> a, b;
    const FairingReport whole = Faired(*m, 0, a), sampled = Faired(*m, 4096, b);
    EXPECT_EQ(sampled.SampledPoints, 0);
    EXPECT_EQ(sampled.Error, whole.Error);
    EXPECT_EQ(sampled.ChosenTimeStep, whole.ChosenTimeStep);
  }
}
