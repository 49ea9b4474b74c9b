// The denoising family (vtkImageBeltramiDenoising, vtkSurfaceDataDenoising,
// vtkTetrahedralBeltramiDenoising): noise removed with edges kept, linear
// fields kept, fixed points, the report, bad input.
#include "TestHelpers.h"

#include "vtkImageBeltramiDenoising.h"
#include "vtkSurfaceDataDenoising.h"
#include "vtkTetrahedralBeltramiDenoising.h"

#include <vtkDataSetTriangleFilter.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkSphereSource.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using beltrami::test::AddPointField;
using beltrami::test::MessageCollector;

namespace
{

/// RMS difference of two point arrays (first component).
double RMS(vtkDataArray* a, vtkDataArray* b)
{
  double sum = 0.0;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
  {
    const double d = a->GetComponent(i, 0) - b->GetComponent(i, 0);
    sum += d * d;
  }
  return std::sqrt(sum / a->GetNumberOfTuples());
}

/// A 64 x 64 image: 0 left, 1 right ("clean"), and the same with Gaussian
/// noise of standard deviation sigma ("values", the active scalars).
vtkSmartPointer<vtkImageData> NoisyStep(double sigma)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(64, 64, 1);
  vtkNew<vtkFloatArray> clean, values;
  clean->SetName("clean");
  values->SetName("values");
  clean->SetNumberOfTuples(64 * 64);
  values->SetNumberOfTuples(64 * 64);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, sigma);
  for (vtkIdType i = 0; i < 64 * 64; ++i)
  {
    const double c = i % 64 < 32 ? 0.0 : 1.0;
    clean->SetValue(i, static_cast<float>(c));
    values->SetValue(i, static_cast<float>(c + noise(rng)));
  }
  image->GetPointData()->AddArray(clean);
  image->GetPointData()->SetScalars(values);
  return image;
}

} // namespace

TEST(ImageBeltramiDenoising, RemovesNoiseKeepsTheEdgeAndReports)
{
  const double sigma = 0.1;
  const auto image = NoisyStep(sigma);
  vtkNew<vtkImageBeltramiDenoising> f;
  f->SetInputData(image);
  f->SetContrastScale(1.5 / sigma); // the documented setting for noise sigma
  f->SetNoiseLevel(sigma);
  f->SetStoppingRule(vtkImageBeltramiDenoising::NOISE_LEVEL);
  f->SetNumberOfIterations(200);
  f->Update();
  vtkImageData* out = f->GetOutput();
  vtkDataArray* smoothed = out->GetPointData()->GetArray("values");
  vtkDataArray* clean = image->GetPointData()->GetArray("clean");
  ASSERT_NE(smoothed, nullptr);
  EXPECT_EQ(smoothed->GetDataType(), VTK_FLOAT); // the input's type
  const double before = RMS(image->GetPointData()->GetScalars(), clean), after = RMS(smoothed, clean);
  std::printf("image: RMS error %.4f -> %.4f\n", before, after);
  EXPECT_LT(after, 0.4 * before);
  // The edge: the jump across the middle column stays close to 1.
  double jump = 0.0;
  for (int y = 0; y < 64; ++y)
  {
    jump += smoothed->GetComponent(y * 64 + 32, 0) - smoothed->GetComponent(y * 64 + 31, 0);
  }
  EXPECT_GT(jump / 64, 0.7);
  // The noise-level stop: the RMS change is the noise level.
  vtkDataArray* change = out->GetFieldData()->GetArray("FlowRMSChange");
  ASSERT_NE(change, nullptr);
  EXPECT_NEAR(change->GetComponent(0, 0), sigma, 1e-3);
  EXPECT_NE(out->GetFieldData()->GetArray("FlowIterations"), nullptr);
}

TEST(ImageBeltramiDenoising, FixedPixelsAndMissingArrays)
{
  auto image = NoisyStep(0.1);
  vtkNew<vtkUnsignedCharArray> mask;
  mask->SetName("mask");
  mask->SetNumberOfTuples(64 * 64);
  for (vtkIdType i = 0; i < 64 * 64; ++i)
  {
    mask->SetValue(i, i % 5 == 0 ? 1 : 0);
  }
  image->GetPointData()->AddArray(mask);
  vtkNew<vtkImageBeltramiDenoising> f;
  f->SetInputData(image);
  f->SetInputArrayToProcess(vtkImageBeltramiDenoising::FIXED_POINTS_ARRAY, 0, 0, 0, "mask");
  f->Update();
  vtkDataArray* in = image->GetPointData()->GetScalars();
  vtkDataArray* out = f->GetOutput()->GetPointData()->GetArray("values");
  for (vtkIdType i = 0; i < 64 * 64; i += 5)
  {
    ASSERT_EQ(out->GetComponent(i, 0), in->GetComponent(i, 0)) << i;
  }
  EXPECT_GT(RMS(in, out), 0.01);

  vtkNew<vtkImageBeltramiDenoising> g;
  vtkNew<MessageCollector> messages;
  messages->Watch(g);
  g->SetInputData(image);
  g->SetInputArrayToProcess(vtkImageBeltramiDenoising::SMOOTHED_ARRAY, 0, 0, 0, "no such array");
  g->Update();
  EXPECT_FALSE(messages->Errors.empty());
}

TEST(SurfaceDataDenoising, DefaultsSmoothNoisyDataOnASphere)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(60);
  sphere->SetPhiResolution(60);
  sphere->SetRadius(5.0);
  sphere->Update();
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->ShallowCopy(sphere->GetOutput());
  const auto height = [](const double* x) { return x[2] / 5.0; };
  vtkDoubleArray* clean = AddPointField(mesh, "clean", height);
  vtkDoubleArray* values = AddPointField(mesh, "values", height, 0.05, 5);
  mesh->GetPointData()->SetScalars(values);
  vtkNew<vtkSurfaceDataDenoising> f; // semi-implicit steps of 0.1 h^2, automatic settings
  f->SetInputData(mesh);
  f->Update();
  vtkDataArray* out = f->GetOutput()->GetPointData()->GetArray("values");
  ASSERT_NE(out, nullptr);
  const double before = RMS(values, clean), after = RMS(out, clean);
  std::printf("surface data: RMS error %.4f -> %.4f\n", before, after);
  EXPECT_LT(after, 0.6 * before);
  EXPECT_EQ(f->GetOutput()->GetNumberOfCells(), mesh->GetNumberOfCells());
  vtkDataArray* time = f->GetOutput()->GetFieldData()->GetArray("FlowTime");
  ASSERT_NE(time, nullptr);
  const double h = beltrami::test::MeanEdgeLength(mesh);
  vtkFieldData* fd = f->GetOutput()->GetFieldData();
  const double steps = fd->GetArray("FlowIterations")->GetComponent(0, 0);
  EXPECT_GT(steps, 0);
  EXPECT_NEAR(time->GetComponent(0, 0), steps * 0.1 * h * h, 1e-9 * h * h); // in the mesh's units
  // The noise estimated from the data alone, used by the stop.
  EXPECT_NEAR(fd->GetArray("EstimatedNoiseLevel")->GetComponent(0, 0), 0.05, 0.005);
  EXPECT_EQ(fd->GetArray("FlowNoiseLevel")->GetComponent(0, 0), fd->GetArray("EstimatedNoiseLevel")->GetComponent(0, 0));
}

TEST(TetrahedralBeltramiDenoising, LinearFieldsStayAndNoiseGoes)
{
  vtkNew<vtkImageData> grid;
  grid->SetDimensions(9, 9, 9);
  grid->SetSpacing(0.5, 0.5, 0.5);
  vtkDoubleArray* linear =
    AddPointField(grid, "linear", [](const double* x) { return 0.3 * x[0] - 0.2 * x[1] + 0.1 * x[2] + 1.0; });
  vtkDoubleArray* noisy = AddPointField(grid, "noisy", [](const double*) { return 1.0; }, 0.1, 2);
  vtkNew<vtkDataSetTriangleFilter> tetrahedralize;
  tetrahedralize->SetInputData(grid);
  tetrahedralize->Update();
  vtkUnstructuredGrid* tets = tetrahedralize->GetOutput();
  ASSERT_GT(tets->GetNumberOfCells(), 0);

  // Linear precision: with the boundary values held (the fixed-points
  // array), a linear field is a fixed point of the flow.
  vtkNew<vtkUnsignedCharArray> boundary;
  boundary->SetName("boundary");
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    const double* x = grid->GetPoint(i);
    bool onBoundary = false;
    for (int k = 0; k < 3; ++k)
    {
      onBoundary = onBoundary || x[k] == 0.0 || x[k] == 4.0;
    }
    boundary->InsertNextValue(onBoundary ? 1 : 0);
  }
  tets->GetPointData()->AddArray(boundary);
  vtkNew<vtkTetrahedralBeltramiDenoising> f;
  f->SetInputData(tets);
  f->SetInputArrayToProcess(vtkTetrahedralBeltramiDenoising::SMOOTHED_ARRAY, 0, 0, 0, "linear");
  f->SetInputArrayToProcess(vtkTetrahedralBeltramiDenoising::FIXED_POINTS_ARRAY, 0, 0, 0, "boundary");
  f->Update();
  vtkDataArray* out = f->GetOutput()->GetPointData()->GetArray("linear");
  double largest = 0.0;
  for (vtkIdType i = 0; i < out->GetNumberOfTuples(); ++i)
  {
    largest = std::max(largest, std::abs(out->GetComponent(i, 0) - linear->GetComponent(i, 0)));
  }
  EXPECT_LT(largest, 1e-9);

  vtkNew<vtkTetrahedralBeltramiDenoising> g;
  g->SetInputData(tets);
  g->SetInputArrayToProcess(vtkTetrahedralBeltramiDenoising::SMOOTHED_ARRAY, 0, 0, 0, "noisy");
  g->Update();
  vtkNew<vtkDoubleArray> one;
  one->SetNumberOfTuples(noisy->GetNumberOfTuples());
  one->Fill(1.0);
  const double before = RMS(noisy, one), after = RMS(g->GetOutput()->GetPointData()->GetArray("noisy"), one);
  std::printf("tetrahedra: RMS error %.4f -> %.4f\n", before, after);
  EXPECT_LT(after, 0.6 * before);

  // Wrong input: no tetrahedra (a mesh of triangles only) is reported.
  vtkNew<vtkUnstructuredGrid> triangles;
  triangles->SetPoints(tets->GetPoints());
  triangles->GetPointData()->ShallowCopy(tets->GetPointData());
  vtkIdType tri[3] = { 0, 1, 2 };
  triangles->InsertNextCell(VTK_TRIANGLE, 3, tri);
  vtkNew<vtkTetrahedralBeltramiDenoising> h;
  vtkNew<MessageCollector> messages;
  messages->Watch(h);
  h->SetInputData(triangles);
  h->SetInputArrayToProcess(vtkTetrahedralBeltramiDenoising::SMOOTHED_ARRAY, 0, 0, 0, "noisy");
  h->Update();
  EXPECT_FALSE(messages->Warnings.empty() && messages->Errors.empty());
}
