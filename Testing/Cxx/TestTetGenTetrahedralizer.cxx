// vtkTetGenTetrahedralizer (the tetrahedralization family): the volume of a
// closed surface filled exactly, input points first with their data, open
// surfaces refused.
#include "TestHelpers.h"

#include "vtkTetGenTetrahedralizer.h"

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkSphereSource.h>
#include <vtkUnstructuredGrid.h>

#include <gtest/gtest.h>

#include <cmath>

using beltrami::test::MessageCollector;
using beltrami::test::ReadOFF;

namespace
{

/// Signed volume of the tetrahedra.
double TetrahedraVolume(vtkUnstructuredGrid* grid)
{
  double total = 0.0;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, ids);
    double p[4][3];
    for (int k = 0; k < 4; ++k)
    {
      grid->GetPoint(ids->GetId(k), p[k]);
    }
    double a[3], b[3], d[3], n[3];
    for (int k = 0; k < 3; ++k)
    {
      a[k] = p[1][k] - p[0][k];
      b[k] = p[2][k] - p[0][k];
      d[k] = p[3][k] - p[0][k];
    }
    vtkMath::Cross(a, b, n);
    total += vtkMath::Dot(n, d) / 6.0;
  }
  return total;
}

/// Volume enclosed by a closed, outward-oriented triangle surface.
double EnclosedVolume(vtkPolyData* surface)
{
  double total = 0.0;
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  auto it = vtk::TakeSmartPointer(surface->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    it->GetCurrentCell(n, ids);
    double p0[3], p1[3], p2[3], c[3];
    surface->GetPoint(ids[0], p0);
    for (vtkIdType k = 1; k + 1 < n; ++k)
    {
      surface->GetPoint(ids[k], p1);
      surface->GetPoint(ids[k + 1], p2);
      vtkMath::Cross(p1, p2, c);
      total += vtkMath::Dot(p0, c) / 6.0;
    }
  }
  return total;
}

} // namespace

TEST(TetGenTetrahedralizer, FillsARealClosedSurfaceExactly)
{
  auto elephant = ReadOFF("elephant.off");
  vtkNew<vtkDoubleArray> height; // a linear field: extended exactly to new points
  height->SetName("height");
  for (vtkIdType i = 0; i < elephant->GetNumberOfPoints(); ++i)
  {
    const double* x = elephant->GetPoint(i);
    height->InsertNextValue(2.0 * x[2] - x[0] + 0.5);
  }
  elephant->GetPointData()->AddArray(height);
  vtkNew<vtkTetGenTetrahedralizer> f;
  f->SetInputData(elephant);
  f->Update();
  vtkUnstructuredGrid* out = f->GetOutput();
  ASSERT_GT(out->GetNumberOfCells(), 1000);
  const double volume = EnclosedVolume(elephant), filled = TetrahedraVolume(out);
  std::printf("elephant: %lld tetrahedra, volume %.9g of %.9g\n", static_cast<long long>(out->GetNumberOfCells()),
    filled, volume);
  EXPECT_NEAR(filled, volume, 1e-9 * std::abs(volume)); // preserved surface: the same volume
  ASSERT_GE(out->GetNumberOfPoints(), elephant->GetNumberOfPoints());
  for (vtkIdType i = 0; i < elephant->GetNumberOfPoints(); i += 97) // input points first
  {
    double a[3], b[3];
    elephant->GetPoint(i, a);
    out->GetPoint(i, b);
    EXPECT_EQ(vtkMath::Distance2BetweenPoints(a, b), 0.0);
  }
  vtkDataArray* extended = out->GetPointData()->GetArray("height");
  ASSERT_NE(extended, nullptr);
  double worst = 0.0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const double* x = out->GetPoint(i);
    worst = std::max(worst, std::abs(extended->GetComponent(i, 0) - (2.0 * x[2] - x[0] + 0.5)));
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_NE(out->GetFieldData()->GetAbstractArray("TetGenSwitches"), nullptr);
}

TEST(TetGenTetrahedralizer, OpenSurfaceIsAnErrorWithAnEmptyOutput)
{
  vtkNew<vtkPlaneSource> plane;
  plane->SetResolution(4, 4);
  vtkNew<vtkTetGenTetrahedralizer> f;
  vtkNew<MessageCollector> messages;
  messages->Watch(f);
  f->SetInputConnection(plane->GetOutputPort());
  f->Update();
  ASSERT_FALSE(messages->Errors.empty());
  EXPECT_NE(messages->Errors[0].find("closed manifold"), std::string::npos) << messages->Errors[0];
  EXPECT_EQ(f->GetOutput()->GetNumberOfCells(), 0);

  vtkNew<vtkPolyData> empty;
  vtkNew<vtkTetGenTetrahedralizer> g;
  g->SetInputData(empty);
  g->Update();
  EXPECT_EQ(g->GetOutput()->GetNumberOfPoints(), 0);
}
