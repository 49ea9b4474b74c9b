// vtkDiscreteCurvatures: outputs, real meshes, polygon input and bad input.
#include "TestHelpers.h"

#include "vtkDiscreteCurvatures.h"
#include "vtkOFFReader.h"

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCylinderSource.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <cmath>

using beltrami::test::DataFile;
using beltrami::test::MessageCollector;
using beltrami::test::ReadOFF;
using beltrami::test::Value;

namespace
{

vtkSmartPointer<vtkPolyData> RunFilter(vtkPolyData* input, vtkDiscreteCurvatures* filter = nullptr,
  MessageCollector* messages = nullptr)
{
  vtkNew<vtkDiscreteCurvatures> local;
  return beltrami::test::RunOn(filter ? filter : local.Get(), input, messages);
}

double TotalCurvature(vtkPolyData* pd)
{
  double sum = 0;
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
  {
    sum += Value(pd, "GaussianCurvature", i) * Value(pd, "MixedArea", i);
  }
  return sum;
}

/// A polydata from raw points and triangles.
vtkSmartPointer<vtkPolyData> MakeMesh(
  const std::vector<double>& xyz, const std::vector<std::vector<vtkIdType>>& cells)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  for (std::size_t i = 0; i < xyz.size(); i += 3)
  {
    pts->InsertNextPoint(xyz[i], xyz[i + 1], xyz[i + 2]);
  }
  vtkNew<vtkCellArray> polys;
  for (const auto& c : cells)
  {
    polys->InsertNextCell(static_cast<vtkIdType>(c.size()), c.data());
  }
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  return pd;
}

/// An octahedron (closed, 6 points) plus whatever extra points/cells a test adds.
std::vector<double> OctahedronPoints()
{
  return { 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1 };
}
std::vector<std::vector<vtkIdType>> OctahedronCells()
{
  return { { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 }, { 2, 0, 5 }, { 1, 2, 5 },
    { 3, 1, 5 }, { 0, 3, 5 } };
}

} // namespace

TEST(DiscreteCurvatures, OutputArraysAndSwitches)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(40);
  sphere->SetPhiResolution(40);
  sphere->SetRadius(3);
  sphere->Update();
  vtkPolyData* in = sphere->GetOutput();
  const auto out = RunFilter(in);
  EXPECT_EQ(out->GetNumberOfCells(), in->GetNumberOfCells());
  const struct
  {
    const char* Name;
    int Components;
  } expected[] = { { "MeanCurvatureNormal", 3 }, { "MixedArea", 1 }, { "MeanCurvature", 1 },
    { "GaussianCurvature", 1 }, { "MaximumCurvature", 1 }, { "MinimumCurvature", 1 },
    { "PrincipalDirection1", 3 }, { "PrincipalDirection2", 3 }, { "Normals", 3 },
    { "VertexStatus", 1 } };
  for (const auto& e : expected)
  {
    vtkDataArray* a = out->GetPointData()->GetArray(e.Name);
    ASSERT_NE(a, nullptr) << e.Name;
    EXPECT_EQ(a->GetNumberOfComponents(), e.Components) << e.Name;
    EXPECT_EQ(a->GetNumberOfTuples(), in->GetNumberOfPoints()) << e.Name;
  }
  EXPECT_STREQ(out->GetPointData()->GetNormals()->GetName(), "Normals");
  EXPECT_STREQ(out->GetPointData()->GetScalars()->GetName(), "MeanCurvature");
  double meanH = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    meanH += Value(out, "MeanCurvature", i);
  }
  EXPECT_NEAR(meanH / out->GetNumberOfPoints(), 1.0 / 3.0, 1e-3);

  vtkNew<vtkDiscreteCurvatures> f;
  f->ComputeMeanCurvatureNormalOff();
  f->ComputePrincipalDirectionsOff();
  f->ComputeNormalsOff();
  f->ComputeVertexStatusOff();
  const auto fewer = RunFilter(in, f);
  EXPECT_EQ(fewer->GetPointData()->GetArray("MeanCurvatureNormal"), nullptr);
  EXPECT_EQ(fewer->GetPointData()->GetArray("PrincipalDirection1"), nullptr);
  // The source's own normals pass through untouched.
  EXPECT_EQ(fewer->GetPointData()->GetArray("Normals"), in->GetPointData()->GetArray("Normals"));
  EXPECT_EQ(fewer->GetPointData()->GetArray("VertexStatus"), nullptr);
  ASSERT_NE(fewer->GetPointData()->GetArray("MaximumCurvature"), nullptr);
  for (vtkIdType i = 0; i < in->GetNumberOfPoints(); ++i)
  {
    EXPECT_EQ(Value(fewer, "MaximumCurvature", i), Value(out, "MaximumCurvature", i));
  }
}

// Gauss-Bonnet on real meshes of genus 0, 1 and 2: sum kappa_G A = 2 pi chi.
TEST(DiscreteCurvatures, GaussBonnetOnRealMeshes)
{
  const struct
  {
    const char* File;
    int Chi;
  } cases[] = { { "bunny00.off", 2 }, { "knot1.off", 0 }, { "eight.off", -2 } };
  for (const auto& c : cases)
  {
    MessageCollector* messages = MessageCollector::New();
    const auto out = RunFilter(ReadOFF(c.File), nullptr, messages);
    EXPECT_TRUE(messages->Warnings.empty()) << c.File;
    messages->Delete();
    EXPECT_NEAR(TotalCurvature(out), 2 * M_PI * c.Chi, 1e-9) << c.File;
  }
}

// Polygons are triangulated internally (quads and 64-gon caps), cells are kept.
TEST(DiscreteCurvatures, PolygonInput)
{
  vtkNew<vtkCylinderSource> cylinder;
  cylinder->SetResolution(64);
  cylinder->SetRadius(0.5);
  cylinder->SetHeight(2);
  cylinder->CappingOn();
  cylinder->Update();
  vtkPolyData* in = cylinder->GetOutput();
  // vtkCylinderSource duplicates points along the cap edges; it is still a
  // closed surface for curvature only after merging, so check the side.
  const auto out = RunFilter(in);
  EXPECT_EQ(out->GetNumberOfCells(), in->GetNumberOfCells());
  EXPECT_EQ(out->GetCellType(0), in->GetCellType(0));

  vtkNew<vtkPlaneSource> plane; // quads, flat
  plane->SetResolution(12, 9);
  plane->Update();
  const auto flat = RunFilter(plane->GetOutput());
  for (vtkIdType i = 0; i < flat->GetNumberOfPoints(); ++i)
  {
    if (Value(flat, "VertexStatus", i) == 0)
    {
      EXPECT_NEAR(Value(flat, "MeanCurvature", i), 0, 1e-9);
      EXPECT_NEAR(Value(flat, "GaussianCurvature", i), 0, 1e-9);
    }
  }
  EXPECT_EQ(flat->GetCellType(0), VTK_QUAD);
}

TEST(DiscreteCurvatures, FloatAndDoublePoints)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(30);
  sphere->SetPhiResolution(30);
  sphere->SetOutputPointsPrecision(vtkAlgorithm::SINGLE_PRECISION);
  sphere->Update();
  const auto f = RunFilter(sphere->GetOutput());
  sphere->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  sphere->Update();
  const auto d = RunFilter(sphere->GetOutput());
  for (vtkIdType i = 0; i < f->GetNumberOfPoints(); ++i)
  {
    EXPECT_NEAR(Value(f, "MeanCurvature", i), Value(d, "MeanCurvature", i), 1e-4);
  }
}

TEST(DiscreteCurvatures, BoundaryHandling)
{
  const auto mesh = ReadOFF("mushroom.off");
  MessageCollector* messages = MessageCollector::New();
  const auto nan = RunFilter(mesh, nullptr, messages);
  EXPECT_TRUE(messages->Warnings.empty()); // a boundary is not a defect
  messages->Delete();
  vtkNew<vtkDiscreteCurvatures> f;
  f->SetBoundaryHandling(vtkDiscreteCurvatures::INTERIOR_AVERAGE);
  const auto avg = RunFilter(mesh, f);
  int boundary = 0;
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    const int status = static_cast<int>(Value(nan, "VertexStatus", i));
    if (status & 1)
    {
      ++boundary;
      EXPECT_TRUE(std::isnan(Value(nan, "MeanCurvature", i)));
      EXPECT_TRUE(std::isfinite(Value(avg, "MeanCurvature", i)));
      EXPECT_TRUE(std::isfinite(Value(nan, "Normals", i)));
      EXPECT_GT(Value(nan, "MixedArea", i), 0);
    }
    else
    {
      EXPECT_TRUE(std::isfinite(Value(nan, "MeanCurvature", i)));
    }
  }
  EXPECT_GT(boundary, 10);
}

TEST(BadInput, EmptyAndPointOnlyInput)
{
  {
    vtkNew<vtkPolyData> empty;
    MessageCollector* messages = MessageCollector::New();
    const auto out = RunFilter(empty, nullptr, messages);
    EXPECT_EQ(out->GetNumberOfPoints(), 0);
    EXPECT_TRUE(messages->WarnedAbout("no points"));
    EXPECT_TRUE(messages->Errors.empty());
    messages->Delete();
  }
  {
    auto pd = MakeMesh({ 0, 0, 0, 1, 0, 0, 0, 1, 0 }, {});
    vtkNew<vtkCellArray> verts;
    for (vtkIdType i = 0; i < 3; ++i)
    {
      verts->InsertNextCell(1, &i);
    }
    pd->SetVerts(verts);
    MessageCollector* messages = MessageCollector::New();
    const auto out = RunFilter(pd, nullptr, messages);
    EXPECT_TRUE(messages->WarnedAbout("no polygons"));
    ASSERT_NE(out->GetPointData()->GetArray("MeanCurvature"), nullptr);
    for (vtkIdType i = 0; i < 3; ++i)
    {
      EXPECT_TRUE(std::isnan(Value(out, "MeanCurvature", i)));
      EXPECT_EQ(Value(out, "VertexStatus", i), 16);
    }
    EXPECT_EQ(out->GetNumberOfVerts(), 3);
    messages->Delete();
  }
}

TEST(BadInput, TopologicalDefectsAreFlaggedNotFatal)
{
  struct Case
  {
    const char* Name;
    std::vector<double> ExtraPoints;
    std::vector<std::vector<vtkIdType>> ExtraCells;
    const char* Warning;
    vtkIdType FlaggedPoint;
    int Bit;
  };
  const Case cases[] = {
    { "non-manifold edge", { 1, 1, 1 }, { { 0, 2, 6 } }, "non-manifold edges", 0, 2 },
    { "non-manifold vertex", { 3, 0, 0, 3, 1, 0 }, { { 0, 6, 7 } }, "non-manifold vertices", 0, 2 },
    { "isolated point", { 5, 5, 5 }, {}, "used by no triangle", 6, 16 },
    // (Repaired: the copy is dropped, and its points are regular.)
    { "duplicate triangle", {}, { { 0, 2, 4 } }, "repeated triangles were dropped", -1, 0 },
    // (Repaired: the triangle is turned back, and its points are regular.)
    { "inconsistent orientation", {}, {}, "triangles were turned to orient the surface consistently", -1, 0 },
    { "bad point ids", {}, { { 0, 1, 99 }, { -4, 1, 2 } }, "out of range", -1, 0 },
  };
  for (const Case& c : cases)
  {
    auto xyz = OctahedronPoints();
    xyz.insert(xyz.end(), c.ExtraPoints.begin(), c.ExtraPoints.end());
    auto cells = OctahedronCells();
    if (std::string(c.Name) == "inconsistent orientation")
    {
      std::swap(cells[0][0], cells[0][1]);
    }
    cells.insert(cells.end(), c.ExtraCells.begin(), c.ExtraCells.end());
    const auto mesh = MakeMesh(xyz, cells);
    MessageCollector* messages = MessageCollector::New();
    const auto out = RunFilter(mesh, nullptr, messages);
    EXPECT_TRUE(messages->WarnedAbout(c.Warning)) << c.Name;
    EXPECT_TRUE(messages->Errors.empty()) << c.Name;
    messages->Delete();
    ASSERT_EQ(out->GetNumberOfPoints(), mesh->GetNumberOfPoints()) << c.Name;
    if (c.FlaggedPoint >= 0)
    {
      EXPECT_TRUE(static_cast<int>(Value(out, "VertexStatus", c.FlaggedPoint)) & c.Bit) << c.Name;
    }
    for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
    {
      // Defined output: either a finite value or NaN with a status bit saying why.
      const double h = Value(out, "MeanCurvature", i);
      const int status = static_cast<int>(Value(out, "VertexStatus", i));
      EXPECT_TRUE(std::isfinite(h) || (std::isnan(h) && status != 0)) << c.Name << " point " << i;
    }
  }
}

TEST(BadInput, DegenerateTrianglesAndNaN)
{
  // A flat fan around point 0 with a zero-area sliver (points 0, 3, 4 collinear)
  // and a repeated point (5 == 1).
  {
    const auto mesh = MakeMesh({ 0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, -2, 0, 0, 1, 0, 0, 0, -1, 0 },
      { { 0, 1, 2 }, { 0, 2, 3 }, { 0, 3, 4 }, { 0, 3, 6 }, { 0, 6, 1 }, { 0, 1, 5 } });
    MessageCollector* messages = MessageCollector::New();
    const auto out = RunFilter(mesh, nullptr, messages);
    EXPECT_TRUE(messages->WarnedAbout("zero-area"));
    messages->Delete();
    EXPECT_TRUE(static_cast<int>(Value(out, "VertexStatus", 0)) & 32);
    for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
    {
      EXPECT_FALSE(std::isinf(Value(out, "MeanCurvature", i)));
      EXPECT_FALSE(std::isinf(Value(out, "MixedArea", i)));
    }
  }
  // NaN coordinates: outputs NaN in the 1-ring, other points unaffected.
  {
    auto xyz = OctahedronPoints();
    vtkNew<vtkSphereSource> sphere;
    sphere->SetThetaResolution(20);
    sphere->SetPhiResolution(20);
    sphere->Update();
    vtkNew<vtkPolyData> pd;
    pd->DeepCopy(sphere->GetOutput());
    pd->GetPoints()->SetPoint(100, std::nan(""), 0, 0);
    MessageCollector* messages = MessageCollector::New();
    const auto out = RunFilter(pd, nullptr, messages);
    EXPECT_TRUE(messages->WarnedAbout("NaN"));
    messages->Delete();
    EXPECT_TRUE(std::isnan(Value(out, "MeanCurvature", 100)));
    EXPECT_TRUE(static_cast<int>(Value(out, "VertexStatus", 100)) & 32);
    int finite = 0;
    for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
    {
      finite += std::isfinite(Value(out, "MeanCurvature", i));
    }
    EXPECT_GT(finite, out->GetNumberOfPoints() - 10);
  }
}

TEST(DiscreteCurvatures, AbortLeavesADefinedOutput)
{
  const auto mesh = ReadOFF("bunny00.off");
  vtkNew<vtkDiscreteCurvatures> f;
  f->SetInputData(mesh);
  f->SetNumberOfThreads(1);
  vtkNew<vtkCallbackCommand> abort;
  abort->SetCallback([](vtkObject* caller, unsigned long, void*, void*) {
    auto* alg = static_cast<vtkAlgorithm*>(caller);
    if (alg->GetProgress() > 0.3)
    {
      alg->SetAbortExecute(1);
    }
  });
  f->AddObserver(vtkCommand::ProgressEvent, abort);
  f->Update();
  EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), mesh->GetNumberOfPoints());
  EXPECT_EQ(f->GetOutput()->GetPointData()->GetArray("MeanCurvature"), nullptr);
}

TEST(DiscreteCurvatures, RigidMotionInvariance)
{
  const auto mesh = ReadOFF("knot1.off");
  vtkNew<vtkTransform> t;
  t->Translate(5, -2, 7);
  t->RotateWXYZ(33, 1, 2, 3);
  vtkNew<vtkTransformPolyDataFilter> move;
  move->SetTransform(t);
  move->SetInputData(mesh);
  move->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  move->Update();
  const auto a = RunFilter(mesh);
  const auto b = RunFilter(move->GetOutput());
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    const double h = Value(a, "MeanCurvature", i);
    EXPECT_NEAR(Value(b, "MeanCurvature", i), h, 1e-8 * (1 + std::abs(h)));
    EXPECT_NEAR(Value(b, "GaussianCurvature", i), Value(a, "GaussianCurvature", i),
      1e-8 * (1 + h * h));
  }
}
