// vtkIntrinsicParameterization (the parameterization family): a real
// disk-like mesh on a circle and with natural boundaries, a point
// constraint, closed input through an atlas (refused with the atlas off).
#include "TestHelpers.h"

#include "vtkIntrinsicParameterization.h"

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellData.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkSphereSource.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

using beltrami::test::MessageCollector;
using beltrami::test::ReadOFF;

namespace
{

/// The largest distance of a boundary point's UV (a point on an edge of one
/// triangle) from the circle of centre (0.5, 0.5) and radius 0.5, and the
/// largest distance of any UV outside it; `boundaryPoints` counts them.
void CircleDistances(vtkPolyData* out, double& boundaryOff, double& outside, int& boundaryPoints)
{
  std::map<std::pair<vtkIdType, vtkIdType>, int> edges;
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  auto it = vtk::TakeSmartPointer(out->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    it->GetCurrentCell(n, ids);
    for (vtkIdType k = 0; k < n; ++k)
    {
      ++edges[std::minmax(ids[k], ids[(k + 1) % n])];
    }
  }
  vtkDataArray* uv = out->GetPointData()->GetArray("UV");
  const auto radius = [uv](vtkIdType i) {
    return std::hypot(uv->GetComponent(i, 0) - 0.5, uv->GetComponent(i, 1) - 0.5);
  };
  std::set<vtkIdType> boundary;
  for (const auto& e : edges)
  {
    if (e.second == 1)
    {
      boundary.insert(e.first.first);
      boundary.insert(e.first.second);
    }
  }
  boundaryOff = outside = 0.0;
  for (vtkIdType i : boundary)
  {
    boundaryOff = std::max(boundaryOff, std::abs(radius(i) - 0.5));
  }
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    outside = std::max(outside, radius(i) - 0.5);
  }
  boundaryPoints = static_cast<int>(boundary.size());
}

} // namespace

TEST(IntrinsicParameterization, ConformalMapOfARealMeshOnACircle)
{
  const auto mushroom = ReadOFF("mushroom.off");
  vtkNew<vtkIntrinsicParameterization> f;
  f->SetInputData(mushroom);
  f->Update();
  vtkPolyData* out = f->GetOutput();
  vtkDataArray* uv = out->GetPointData()->GetArray("UV");
  ASSERT_NE(uv, nullptr);
  EXPECT_EQ(uv->GetNumberOfComponents(), 2);
  EXPECT_EQ(out->GetPointData()->GetTCoords(), uv);
  double boundaryOff = 1.0, outside = 1.0;
  int boundaryPoints = 0;
  CircleDistances(out, boundaryOff, outside, boundaryPoints);
  EXPECT_GT(boundaryPoints, 10);
  EXPECT_LT(boundaryOff, 1e-9); // the boundary on the circle
  EXPECT_LT(outside, 1e-9);     // nothing outside it
  EXPECT_EQ(f->GetNumberOfFlippedTriangles(), 0);
  EXPECT_LT(f->GetMeanAngleDistortion(), 5.0); // degrees
  std::printf("mushroom DCP: mean angle distortion %.3f degrees\n", f->GetMeanAngleDistortion());
  for (const char* name : { "AngleDistortion", "AreaDistortion", "EdgeDistortion" })
  {
    EXPECT_NE(out->GetCellData()->GetArray(name), nullptr) << name;
  }
  EXPECT_NE(out->GetFieldData()->GetArray("MeanAngleDistortion"), nullptr);
}

TEST(IntrinsicParameterization, NaturalBoundaryAndAPointConstraint)
{
  const auto mushroom = ReadOFF("mushroom.off");
  vtkNew<vtkIntrinsicParameterization> natural;
  natural->SetInputData(mushroom);
  natural->SetBoundary(vtkIntrinsicParameterization::NATURAL);
  natural->Update();
  vtkDataArray* uv = natural->GetOutput()->GetPointData()->GetArray("UV");
  ASSERT_NE(uv, nullptr);
  double lo = 1.0, hi = 0.0;
  for (vtkIdType i = 0; i < uv->GetNumberOfTuples(); ++i)
  {
    for (int k = 0; k < 2; ++k)
    {
      lo = std::min(lo, uv->GetComponent(i, k));
      hi = std::max(hi, uv->GetComponent(i, k));
    }
  }
  EXPECT_GE(lo, -1e-12); // fitted into [0, 1]^2
  EXPECT_LE(hi, 1.0 + 1e-12);
  EXPECT_EQ(natural->GetNumberOfFlippedTriangles(), 0);

  vtkNew<vtkIntrinsicParameterization> constrained;
  constrained->SetInputData(mushroom);
  constrained->AddPointConstraint(1000, 0.4, 0.45);
  constrained->Update();
  vtkDataArray* c = constrained->GetOutput()->GetPointData()->GetArray("UV");
  EXPECT_NEAR(c->GetComponent(1000, 0), 0.4, 1e-9);
  EXPECT_NEAR(c->GetComponent(1000, 1), 0.45, 1e-9);
}

TEST(IntrinsicParameterization, ClosedInputIsAClearErrorWithoutTheAtlas)
{
  vtkNew<vtkSphereSource> sphere;
  vtkNew<vtkIntrinsicParameterization> f;
  f->AtlasForNonDisksOff();
  vtkNew<MessageCollector> messages;
  messages->Watch(f);
  f->SetInputConnection(sphere->GetOutputPort());
  f->Update();
  ASSERT_FALSE(messages->Errors.empty());
  EXPECT_NE(messages->Errors[0].find("closed"), std::string::npos) << messages->Errors[0];
  EXPECT_EQ(f->GetOutput()->GetPointData()->GetArray("UV"), nullptr);
}

TEST(IntrinsicParameterization, ClosedInputThroughAnAtlasByDefault)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(32);
  sphere->SetPhiResolution(32);
  sphere->Update();
  vtkNew<vtkIntrinsicParameterization> f;
  EXPECT_TRUE(f->GetAtlasForNonDisks());
  f->SetBoundary(vtkIntrinsicParameterization::NATURAL);
  vtkNew<MessageCollector> messages;
  messages->Watch(f);
  f->SetInputConnection(sphere->GetOutputPort());
  f->Update();
  EXPECT_TRUE(messages->Errors.empty());
  EXPECT_TRUE(messages->WarnedAbout("atlas"));
  vtkPolyData* out = f->GetOutput();
  vtkDataArray* uv = out->GetPointData()->GetArray("UV");
  ASSERT_NE(uv, nullptr);
  EXPECT_GT(out->GetNumberOfPoints(), sphere->GetOutput()->GetNumberOfPoints()); // cut along the seams
  EXPECT_EQ(out->GetNumberOfCells(), sphere->GetOutput()->GetNumberOfCells());
  EXPECT_EQ(f->GetNumberOfFlippedTriangles(), 0);
  EXPECT_LT(f->GetMeanAngleDistortion(), 2.0); // natural charts
  EXPECT_NE(out->GetCellData()->GetArray("ChartId"), nullptr);
}
