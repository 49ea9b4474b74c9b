// The fairing's step search (Flows/FairingStepChoice.h) on a run whose risk
// is known in closed form: a smoothing of noisy heights in the eigenbasis of
// a Laplacian (each height one eigen-coefficient).
#include "Flows/FairingStepChoice.h"
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

/// Coefficients z_i = s_i + n_i of the eigenvalues lambda_i = 4 sin^2(pi
/// (i + 1/2) / 2N) of a periodic chain's Laplacian (signal of variance
/// Signal / lambda_i: a smooth shape; white noise of deviation 1), smoothed
/// by the implicit step f_i(z) = z_i / (1 + dt lambda_i): its expected
/// squared error per point is the mean of Signal / lambda_i (dt lambda_i /
/// (1 + dt lambda_i))^2 + 1 / (1 + dt lambda_i)^2.
struct SpectralSmoothing
{
  double Signal;
  std::vector<double> Lambda, Noisy, Perturbed;
  double Epsilon = detail::ProbeDeviation; // the filter's probe (the noise's deviation is 1)
  mutable int Runs = 0;

  SpectralSmoothing(int points, double signal)
    : Signal(signal)
  {
    std::mt19937_64 random(7);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::bernoulli_distribution sign(0.5);
    for (int i = 0; i < points; ++i)
    {
      const double s = std::sin(M_PI * (i + 0.5) / (2.0 * points));
      Lambda.push_back(4.0 * s * s);
      const double z = std::sqrt(Signal / Lambda.back()) * normal(random) + normal(random);
      const double probe = sign(random) ? Epsilon : -Epsilon;
      const double x = i, y = 0.5 * i;
      Noisy.insert(Noisy.end(), { x, y, z });
      Perturbed.insert(Perturbed.end(), { x, y, z + probe });
    }
  }

  double ExpectedError(double dt) const
  {
    double sum = 0.0;
    for (const double l : Lambda)
    {
      const double keep = 1.0 / (1.0 + dt * l);
      sum += Signal / l * (1.0 - keep) * (1.0 - keep) + keep * keep;
    }
    return std::sqrt(sum / static_cast<double>(Lambda.size()));
  }

  /// The least expected error over steps 2^(k/16) (k from -512 to 320).
  double LeastError() const
  {
    double least = ExpectedError(0.0);
    for (int k = -512; k <= 320; ++k)
    {
      least = std::min(least, ExpectedError(std::exp2(k / 16.0)));
    }
    return least;
  }

  /// The search over this run with the noise's deviation taken as `noise`
  /// (1: the truth); Runs counts the runs it made.
  detail::StepChoice Search(double noise = 1.0) const
  {
    const detail::SmoothingRun smooth = [&](double dt, double* p, detail::RunStart&) {
      ++Runs;
      for (std::size_t i = 0; i < Lambda.size(); ++i)
      {
        p[3 * i + 2] /= 1.0 + dt * Lambda[i];
      }
      return true;
    };
    const std::vector<std::uint8_t> moving(Lambda.size(), 1);
    return detail::ChooseTimeStep(smooth, Noisy, Perturbed, Epsilon, moving, noise, 0.0, 1.0, nullptr);
  }
};

} // namespace

TEST(FairingStepChoice, TheSearchEndsNextToTheStepOfLeastRisk)
{
  // Two shapes, the best steps 11.3 and 90.5 (unit 2^(7/2) and 2^(13/2)):
  // the step found is within 1% of the least expected error in RMS, its
  // error estimated (Stein's) within 3%, in five and six tries of two runs
  // (j = 0, 4, ... to one past the least, and the parabola's vertex).
  for (const double signal : { 0.1, 0.01 })
  {
    const SpectralSmoothing data(100000, signal);
    const detail::StepChoice choice = data.Search();
    const double least = data.LeastError();
    std::printf("signal %g: step %g, error %.4f (least %.4f), estimated %.4f, %d tries\n", signal, choice.TimeStep,
      data.ExpectedError(choice.TimeStep), least, choice.EstimatedError, choice.Evaluations);
    EXPECT_LT(data.ExpectedError(choice.TimeStep), 1.01 * least) << signal;
    EXPECT_NEAR(choice.EstimatedError, data.ExpectedError(choice.TimeStep), 0.03 * least) << signal;
    EXPECT_FALSE(choice.AtLimit);
    EXPECT_FALSE(choice.ShapeDetail);
    EXPECT_EQ(choice.Evaluations, signal == 0.1 ? 5 : 6);
    EXPECT_EQ(data.Runs, 2 * choice.Evaluations); // the points and the probe
  }
}

TEST(FairingStepChoice, TheStepDoesNotFollowTheNoiseEstimatesError)
{
  // Generalized cross-validation needs no noise level: with the noise
  // overestimated by half (as the coarse scans' detail inflates it) the
  // same step (11.3), where Stein's estimate with that level would take 64;
  // the estimated error (Stein's, with the level given) is what changes:
  // too low (it counts the phantom noise as removed).
  const SpectralSmoothing data(100000, 0.1);
  const detail::StepChoice truth = data.Search(1.0), inflated = data.Search(1.5);
  EXPECT_EQ(inflated.TimeStep, truth.TimeStep);
  EXPECT_LT(inflated.EstimatedError, truth.EstimatedError);
}

TEST(FairingStepChoice, ANoiseEstimateTooLowForWhatTheStepRemovesIsRaised)
{
  // The noise taken as 0.3 of its deviation (as noise that crumples part of
  // a surface is measured): with it Stein's risk of the best step is above
  // the input's, which would leave the points as they are; the noise is
  // then cross-validation's own estimate at the step, and the step and its
  // estimated error are the truth's.
  const SpectralSmoothing data(100000, 0.1);
  const detail::StepChoice truth = data.Search(1.0), low = data.Search(0.3);
  std::printf("noise taken as 0.3: step %g (truth %g), estimated error %.4f (truth %.4f)\n", low.TimeStep,
    truth.TimeStep, low.EstimatedError, truth.EstimatedError);
  EXPECT_FALSE(low.ShapeDetail);
  EXPECT_EQ(low.TimeStep, truth.TimeStep);
  EXPECT_NEAR(low.EstimatedError, truth.EstimatedError, 0.1 * truth.EstimatedError);
}

TEST(FairingStepChoice, ABestStepThatLeavesMostOfTheNoiseIsTakenForShapeDetail)
{
  // A shape ten times stronger: the best step leaves 0.92 of the noise,
  // above MostKeptNoise: no step.
  const SpectralSmoothing data(100000, 10.0);
  const detail::StepChoice choice = data.Search();
  EXPECT_GT(data.LeastError(), detail::MostKeptNoise);
  EXPECT_TRUE(choice.ShapeDetail);
  EXPECT_EQ(choice.TimeStep, 0.0);
  EXPECT_NEAR(choice.EstimatedError, 1.0, 1e-12); // the input's own (the noise)
}

TEST(FairingStepChoice, PureNoiseTakesTheLargestStepAndSaysSo)
{
  // Without signal the more a step smooths the better: the search walks to
  // its largest step (unit 2^12) and says it stopped there.
  const SpectralSmoothing data(50000, 0.0);
  const detail::StepChoice choice = data.Search();
  EXPECT_TRUE(choice.AtLimit);
  EXPECT_DOUBLE_EQ(choice.TimeStep, 4096.0);
  EXPECT_LT(choice.EstimatedError, 0.1);
}

// MoveCoherence: white noise's moves are about independent over the edges
// (the filter keeps runs below MostCoherentMove and MostCoherentNormalMove),
// a shrinking or a translation moves neighbours together, and held points
// do not count.  A tube three triangles round shrunk: its neighbours move
// in directions 120 degrees apart (negative in space) but all inwards.
TEST(FairingStepChoice, MovesOfNoiseAreIncoherentAndAShrinkingIsCoherent)
{
  const test::Mesh sphere = test::OctahedronSphere(4);
  const MeshTopology topo = sphere.Topology();
  const std::vector<double>& x = sphere.Points;
  const std::vector<std::uint8_t> free(x.size() / 3, 0);
  std::mt19937 random(7);
  std::normal_distribution<double> normal(0.0, 1e-3);
  std::vector<double> noise = x, shrunk = x, moved = x;
  for (std::size_t k = 0; k < x.size(); ++k)
  {
    noise[k] += normal(random);
    shrunk[k] *= 0.99;
    moved[k] += k % 3 == 0 ? 0.01 : 0.0;
  }
  const detail::MoveCorrelations white = detail::MoveCoherence(topo, x.data(), noise.data(), free, nullptr);
  EXPECT_LT(std::abs(white.InSpace), 0.05);
  EXPECT_LT(white.InSpace, detail::MostCoherentMove);
  EXPECT_LT(std::abs(white.AlongNormals), 0.05);
  const detail::MoveCorrelations shrinking = detail::MoveCoherence(topo, x.data(), shrunk.data(), free, nullptr);
  EXPECT_GT(shrinking.InSpace, 0.9);
  EXPECT_GT(shrinking.AlongNormals, 0.99);
  EXPECT_NEAR(detail::MoveCoherence(topo, x.data(), moved.data(), free, nullptr).InSpace, 1.0, 1e-12);
  EXPECT_EQ(detail::MoveCoherence(topo, x.data(), x.data(), free, nullptr).InSpace, 0.0);
  EXPECT_EQ(detail::MoveCoherence(topo, x.data(), x.data(), free, nullptr).AlongNormals, 0.0);
  const std::vector<std::uint8_t> held(x.size() / 3, 1);
  EXPECT_EQ(detail::MoveCoherence(topo, x.data(), noise.data(), held, nullptr).InSpace, 0.0);
  EXPECT_EQ(detail::MoveCoherence(topo, x.data(), noise.data(), held, nullptr).AlongNormals, 0.0);

  const test::Mesh tube = test::Cylinder(1.0, 4.0, 3, 12);
  const MeshTopology tubeTopology = tube.Topology();
  std::vector<double> thinner = tube.Points;
  std::vector<std::uint8_t> ends(tube.Points.size() / 3, 0);
  for (std::size_t v = 0; v < ends.size(); ++v)
  {
    thinner[3 * v] *= 0.9;
    thinner[3 * v + 1] *= 0.9;
    ends[v] = tubeTopology.IsInterior(static_cast<Index>(v)) ? 0 : 1;
  }
  const detail::MoveCorrelations tubeShrinking =
    detail::MoveCoherence(tubeTopology, tube.Points.data(), thinner.data(), ends, nullptr);
  EXPECT_LT(tubeShrinking.InSpace, detail::MostCoherentMove);
  EXPECT_GT(tubeShrinking.AlongNormals, detail::MostCoherentNormalMove);
}
