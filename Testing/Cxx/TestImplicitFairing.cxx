// vtkImplicitFairing (the smoothing family): defaults in edge-length units,
// exact volume, fixed points, precision kept, bad input.
#include "TestHelpers.h"

#include "vtkImplicitFairing.h"

#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using beltrami::test::MeanEdgeLength;
using beltrami::test::MessageCollector;

namespace
{

/// A sphere of radius `radius` with noise along the radius (uniform in
/// +-`noise` of the radius), double points.
vtkSmartPointer<vtkPolyData> NoisySphere(double radius, double noise, unsigned seed = 3)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(60);
  sphere->SetPhiResolution(60);
  sphere->SetRadius(radius);
  sphere->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  sphere->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(sphere->GetOutput());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-noise, noise);
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    double x[3];
    out->GetPoint(i, x);
    const double f = 1.0 + u(rng);
    out->GetPoints()->SetPoint(i, f * x[0], f * x[1], f * x[2]);
  }
  return out;
}

/// RMS of |x| - radius over the points.
double RadialError(vtkPolyData* pd, double radius)
{
  double sum = 0.0;
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    double x[3];
    pd->GetPoint(i, x);
    const double e = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) - radius;
    sum += e * e;
  }
  return std::sqrt(sum / pd->GetNumberOfPoints());
}

vtkSmartPointer<vtkPolyData> Fair(vtkPolyData* input, vtkImplicitFairing* f, MessageCollector* messages = nullptr)
{
  return beltrami::test::RunOn(f, input, messages);
}

} // namespace

TEST(ImplicitFairing, DefaultsRemoveNoiseAndKeepTheVolumeOnAnyScale)
{
  // The same noisy sphere at two scales: with the defaults (one order-2 step
  // of 4 h^4, h the mean edge length) the relative results are the same.
  for (const double radius : { 1.0, 1000.0 })
  {
    const auto noisy = NoisySphere(radius, 0.01);
    vtkNew<vtkImplicitFairing> f;
    const auto out = Fair(noisy, f);
    ASSERT_EQ(out->GetNumberOfPoints(), noisy->GetNumberOfPoints());
    const double before = RadialError(noisy, radius) / radius, after = RadialError(out, radius) / radius;
    EXPECT_LT(after, 0.5 * before) << radius;
    vtkDataArray* invariant = out->GetFieldData()->GetArray("FairingInvariant");
    ASSERT_NE(invariant, nullptr);
    EXPECT_NEAR(invariant->GetComponent(1, 0), invariant->GetComponent(0, 0), 1e-12 * invariant->GetComponent(0, 0));
    EXPECT_NE(out->GetFieldData()->GetArray("FairingIterations"), nullptr);
    EXPECT_GT(f->GetNumberOfSolves(), 0);
  }
}

TEST(ImplicitFairing, EdgeLengthUnitsEqualPhysicalUnitsScaled)
{
  const auto noisy = NoisySphere(2.0, 0.02);
  const double h = MeanEdgeLength(noisy);
  vtkNew<vtkImplicitFairing> byDefault;
  byDefault->SetTimeStep(4.0); // (0, the default, chooses it)
  const auto a = Fair(noisy, byDefault);
  vtkNew<vtkImplicitFairing> physical;
  physical->SetUnits(vtkImplicitFairing::PHYSICAL);
  physical->SetTimeStep(4.0 * h * h * h * h); // the core uses its own mean edge length
  const auto b = Fair(noisy, physical);
  double largest = 0.0, moved = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3], x[3];
    a->GetPoint(i, p);
    b->GetPoint(i, q);
    noisy->GetPoint(i, x);
    largest = std::max(largest, std::sqrt(vtkMath::Distance2BetweenPoints(p, q)));
    moved = std::max(moved, std::sqrt(vtkMath::Distance2BetweenPoints(p, x)));
  }
  EXPECT_GT(moved, 0.1 * 0.02 * 2.0);
  EXPECT_LT(largest, 0.05 * moved); // the same step up to how the edges are counted
}

TEST(ImplicitFairing, FixedPointsStayAndFloatPointsStayFloat)
{
  auto noisy = NoisySphere(1.0, 0.01);
  vtkNew<vtkUnsignedCharArray> fixed;
  fixed->SetName("Fixed");
  fixed->SetNumberOfTuples(noisy->GetNumberOfPoints());
  for (vtkIdType i = 0; i < noisy->GetNumberOfPoints(); ++i)
  {
    fixed->SetValue(i, i % 7 == 0 ? 1 : 0);
  }
  noisy->GetPointData()->AddArray(fixed);
  vtkNew<vtkImplicitFairing> f;
  f->SetInputArrayToProcess(vtkImplicitFairing::FIXED_POINTS_ARRAY, 0, 0, 0, "Fixed");
  const auto out = Fair(noisy, f);
  EXPECT_EQ(out->GetPoints()->GetDataType(), VTK_DOUBLE);
  EXPECT_NE(out->GetPointData()->GetArray("Fixed"), nullptr); // point data passed
  double still = 0.0, moved = 0.0;
  for (vtkIdType i = 0; i < noisy->GetNumberOfPoints(); ++i)
  {
    double p[3], x[3];
    out->GetPoint(i, p);
    noisy->GetPoint(i, x);
    const double d = std::sqrt(vtkMath::Distance2BetweenPoints(p, x));
    (i % 7 == 0 ? still : moved) = std::max(i % 7 == 0 ? still : moved, d);
  }
  EXPECT_EQ(still, 0.0); // open constraints: no invariant rescales the surface
  EXPECT_GT(moved, 1e-4);

  vtkNew<vtkSphereSource> floats; // float points in, float points out
  floats->Update();
  vtkNew<vtkImplicitFairing> g;
  EXPECT_EQ(Fair(floats->GetOutput(), g)->GetPoints()->GetDataType(), VTK_FLOAT);
}

TEST(ImplicitFairing, BadInputGivesAMessageAndADefinedOutput)
{
  vtkNew<vtkPolyData> empty;
  vtkNew<MessageCollector> messages;
  vtkNew<vtkImplicitFairing> f;
  EXPECT_EQ(Fair(empty, f, messages)->GetNumberOfPoints(), 0);
  EXPECT_FALSE(messages->Warnings.empty());

  // All points at one place: no length to measure the time step in.
  auto collapsed = NoisySphere(1.0, 0.0);
  for (vtkIdType i = 0; i < collapsed->GetNumberOfPoints(); ++i)
  {
    collapsed->GetPoints()->SetPoint(i, 0.5, 0.5, 0.5);
  }
  vtkNew<MessageCollector> errors;
  vtkNew<vtkImplicitFairing> g;
  Fair(collapsed, g, errors);
  ASSERT_FALSE(errors->Errors.empty());
  EXPECT_NE(errors->Errors[0].find("mean edge length"), std::string::npos);

  // A NaN point is kept where it is, with a warning; the rest is smoothed.
  auto nan = NoisySphere(1.0, 0.01);
  nan->GetPoints()->SetPoint(5, std::nan(""), 0.0, 0.0);
  vtkNew<MessageCollector> warnings;
  vtkNew<vtkImplicitFairing> h;
  const auto out = Fair(nan, h, warnings);
  EXPECT_TRUE(warnings->WarnedAbout("invalid coordinates"));
  double x[3];
  out->GetPoint(100, x);
  EXPECT_TRUE(std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]));
}
