// vtkSurfaceAtlas (the parameterization family, chapter 4): the cut surface
// of a closed real mesh, its charts' UVs, seams, carried data, bad input.
#include "TestHelpers.h"

#include "vtkDiscreteCurvatures.h"
#include "vtkSurfaceAtlas.h"

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFieldData.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>

using beltrami::test::AddPointField;
using beltrami::test::MessageCollector;
using beltrami::test::ReadOFF;
using beltrami::test::RunOn;

namespace
{

/// Total area of the triangles of `pd`, in 3D or (uv) in the plane (signed).
double Area(vtkPolyData* pd, vtkDataArray* uv = nullptr, vtkIdType* flipped = nullptr)
{
  double total = 0.0;
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  auto it = vtk::TakeSmartPointer(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    it->GetCurrentCell(n, ids);
    if (uv)
    {
      const double* a = uv->GetTuple2(ids[0]);
      const double a0 = a[0], a1 = a[1];
      const double* b = uv->GetTuple2(ids[1]);
      const double b0 = b[0], b1 = b[1];
      const double* c = uv->GetTuple2(ids[2]);
      const double area = 0.5 * ((b0 - a0) * (c[1] - a1) - (b1 - a1) * (c[0] - a0));
      total += area;
      if (flipped && !(area > 0.0))
      {
        ++*flipped;
      }
      continue;
    }
    double p[3][3], e1[3], e2[3], cross[3];
    for (int k = 0; k < 3; ++k)
    {
      pd->GetPoint(ids[k], p[k]);
    }
    vtkMath::Subtract(p[1], p[0], e1);
    vtkMath::Subtract(p[2], p[0], e2);
    vtkMath::Cross(e1, e2, cross);
    total += 0.5 * vtkMath::Norm(cross);
  }
  return total;
}

/// The distance of x from the plane of triangle `cell` of pd.
double DistanceToCellPlane(vtkPolyData* pd, vtkIdType cell, const double x[3])
{
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  pd->GetCellPoints(cell, n, ids);
  double a[3], b[3], d[3], e1[3], e2[3], normal[3], r[3];
  pd->GetPoint(ids[0], a);
  pd->GetPoint(ids[1], b);
  pd->GetPoint(ids[2], d);
  vtkMath::Subtract(b, a, e1);
  vtkMath::Subtract(d, a, e2);
  vtkMath::Cross(e1, e2, normal);
  vtkMath::Normalize(normal);
  vtkMath::Subtract(x, a, r);
  return std::abs(vtkMath::Dot(r, normal));
}

} // namespace

TEST(SurfaceAtlas, ClosedRealMeshIsCutIntoValidCharts)
{
  auto bunny = ReadOFF("bunny00.off");
  AddPointField(bunny, "height", [](const double* x) { return x[1]; });
  vtkNew<vtkSurfaceAtlas> f;
  f->SetMapResolution(0); // the maps: GeometryMapsOfEveryChart
  const auto out = RunOn(f.Get(), bunny);
  ASSERT_GT(out->GetNumberOfCells(), 0);
  EXPECT_EQ(out->GetNumberOfCells(), bunny->GetNumberOfCells());
  EXPECT_GT(out->GetNumberOfPoints(), bunny->GetNumberOfPoints()); // seam points duplicated
  vtkDataArray* uv = out->GetPointData()->GetArray("UV");
  vtkDataArray* chartUV = out->GetPointData()->GetArray("ChartUV");
  vtkDataArray* original = out->GetPointData()->GetArray("vtkOriginalPointIds");
  vtkDataArray* height = out->GetPointData()->GetArray("height");
  ASSERT_TRUE(uv && chartUV && original && height);
  EXPECT_EQ(out->GetPointData()->GetTCoords(), uv);
  double worst = 0.0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    for (int k = 0; k < 2; ++k)
    {
      ASSERT_GE(uv->GetComponent(i, k), 0.0);
      ASSERT_LE(uv->GetComponent(i, k), 1.0);
    }
    const vtkIdType o = static_cast<vtkIdType>(original->GetComponent(i, 0));
    double a[3], b[3];
    out->GetPoint(i, a);
    bunny->GetPoint(o, b);
    worst = std::max(worst, vtkMath::Distance2BetweenPoints(a, b));
    ASSERT_EQ(height->GetComponent(i, 0), bunny->GetPointData()->GetArray("height")->GetComponent(o, 0));
  }
  EXPECT_EQ(worst, 0.0); // every cut point is its original, exactly
  vtkIdType flipped = 0;
  EXPECT_GT(Area(out, uv, &flipped), 0.3); // the charts' share of [0, 1]^2
  EXPECT_EQ(flipped, 0);
  EXPECT_NEAR(Area(out), Area(bunny), 1e-9 * Area(bunny));
  vtkDataArray* chartId = out->GetCellData()->GetArray("ChartId");
  vtkDataArray* charts = out->GetFieldData()->GetArray("AtlasCharts");
  vtkDataArray* efficiency = out->GetFieldData()->GetArray("AtlasPackingEfficiency");
  ASSERT_TRUE(chartId && charts && efficiency);
  EXPECT_GE(charts->GetComponent(0, 0), 2.0); // a closed surface needs two charts at least
  EXPECT_EQ(chartId->GetRange()[1] + 1, charts->GetComponent(0, 0));
  EXPECT_NEAR(efficiency->GetComponent(0, 0), Area(out, uv), 1e-6);
  std::printf("bunny00 atlas: %g charts, packing %.1f%%\n", charts->GetComponent(0, 0),
    100.0 * efficiency->GetComponent(0, 0));
  EXPECT_NE(out->GetCellData()->GetArray("vtkOriginalCellIds"), nullptr);
}

TEST(SurfaceAtlas, BadInputIsReportedWithAnEmptyOutput)
{
  vtkNew<vtkPolyData> empty;
  vtkNew<vtkSurfaceAtlas> f;
  vtkNew<MessageCollector> warnings;
  EXPECT_EQ(RunOn(f.Get(), empty, warnings)->GetNumberOfPoints(), 0);
  EXPECT_FALSE(warnings->Warnings.empty());

  // A Moebius strip (12 quads, its last one joined with a half turn): not
  // orientable, an error.
  vtkNew<vtkPoints> strip;
  const int n = 12;
  for (int i = 0; i < n; ++i)
  {
    const double angle = 2.0 * vtkMath::Pi() * i / n;
    for (const double side : { -0.3, 0.3 })
    {
      const double r = 1.0 + side * std::cos(0.5 * angle);
      strip->InsertNextPoint(r * std::cos(angle), r * std::sin(angle), side * std::sin(0.5 * angle));
    }
  }
  vtkNew<vtkCellArray> quads;
  for (int i = 0; i < n; ++i)
  {
    const vtkIdType a = 2 * i, b = 2 * i + 1;
    const vtkIdType c = i + 1 < n ? 2 * i + 2 : 1, d = i + 1 < n ? 2 * i + 3 : 0; // (the half turn)
    const vtkIdType first[3] = { a, c, b }, second[3] = { b, c, d };
    quads->InsertNextCell(3, first);
    quads->InsertNextCell(3, second);
  }
  vtkNew<vtkPolyData> moebius;
  moebius->SetPoints(strip);
  moebius->SetPolys(quads);
  vtkNew<vtkSurfaceAtlas> g;
  vtkNew<MessageCollector> errors;
  EXPECT_EQ(RunOn(g.Get(), moebius, errors)->GetNumberOfPoints(), 0);
  ASSERT_FALSE(errors->Errors.empty());
  EXPECT_NE(errors->Errors[0].find("consistently oriented"), std::string::npos) << errors->Errors[0];
}

TEST(SurfaceAtlas, ThreeTrianglesOnAnEdgeAreCutApart)
{
  // A fin: three triangles on one edge, which joins none of them.  Each
  // becomes a chart of its own, its points copies of the input's, with a
  // warning.
  vtkNew<vtkPoints> points;
  for (const auto& p : { std::array<double, 3>{ 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 } })
  {
    points->InsertNextPoint(p.data());
  }
  vtkNew<vtkCellArray> cells;
  for (const auto& t : { std::array<vtkIdType, 3>{ 0, 1, 2 }, { 1, 0, 3 }, { 0, 1, 4 } })
  {
    cells->InsertNextCell(3, t.data());
  }
  vtkNew<vtkPolyData> fins;
  fins->SetPoints(points);
  fins->SetPolys(cells);
  vtkNew<vtkSurfaceAtlas> f;
  vtkNew<MessageCollector> warnings;
  const auto out = RunOn(f.Get(), fins, warnings);
  ASSERT_EQ(out->GetNumberOfCells(), 3);
  EXPECT_EQ(out->GetNumberOfPoints(), 9);
  ASSERT_FALSE(warnings->Warnings.empty());
  EXPECT_NE(warnings->Warnings[0].find("1 edge of three or more triangles"), std::string::npos)
    << warnings->Warnings[0];
  vtkDataArray* original = out->GetPointData()->GetArray("vtkOriginalPointIds");
  ASSERT_NE(original, nullptr);
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const vtkIdType o = static_cast<vtkIdType>(original->GetComponent(i, 0));
    ASSERT_GE(o, 0);
    ASSERT_LT(o, 5);
    double a[3], b[3];
    out->GetPoint(i, a);
    fins->GetPoint(o, b);
    EXPECT_EQ(vtkMath::Distance2BetweenPoints(a, b), 0.0);
  }
  EXPECT_EQ(out->GetFieldData()->GetArray("AtlasCharts")->GetComponent(0, 0), 3.0);
}

TEST(SurfaceAtlas, SeamLabelsAndSharpEdgesBoundTheCharts)
{
  auto fandisk = ReadOFF("fandisk.off");
  // User seams: a cell array of labels (the halves on either side of a plane).
  vtkNew<vtkIntArray> part;
  part->SetName("Part");
  double bounds[6];
  fandisk->GetBounds(bounds);
  for (vtkIdType c = 0; c < fandisk->GetNumberOfCells(); ++c)
  {
    double p[3];
    fandisk->GetPoint(fandisk->GetCell(c)->GetPointId(0), p);
    part->InsertNextValue(p[0] > 0.5 * (bounds[0] + bounds[1]) ? 1 : 0);
  }
  fandisk->GetCellData()->AddArray(part);
  vtkNew<vtkSurfaceAtlas> f;
  f->SetMapResolution(0);
  f->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "Part");
  const auto out = RunOn(f.Get(), fandisk);
  vtkDataArray* chart = out->GetCellData()->GetArray("ChartId");
  vtkDataArray* carried = out->GetCellData()->GetArray("Part");
  ASSERT_TRUE(chart && carried);
  std::map<int, int> labelOfChart;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    const int id = static_cast<int>(chart->GetTuple1(c)), label = static_cast<int>(carried->GetTuple1(c));
    EXPECT_EQ(labelOfChart.emplace(id, label).first->second, label) << "chart " << id << " spans two labels";
  }
  const int seams = static_cast<int>(out->GetFieldData()->GetArray("AtlasCutEdges")->GetTuple1(0));
  EXPECT_GT(seams, 20);

  // Sharp edges as chart boundaries: more charts, the creases among the seams.
  vtkNew<vtkSurfaceAtlas> plain, sharp;
  plain->SetMapResolution(0);
  sharp->SetMapResolution(0);
  sharp->SplitAtFeaturesOn();
  const auto charts = [](vtkPolyData* pd) { return pd->GetFieldData()->GetArray("AtlasCharts")->GetTuple1(0); };
  const auto withFeatures = RunOn(sharp.Get(), fandisk);
  EXPECT_GT(charts(withFeatures), charts(RunOn(plain.Get(), fandisk)));
  EXPECT_GT(withFeatures->GetFieldData()->GetArray("AtlasCutEdges")->GetTuple1(0), 600); // fandisk: 699 above 60 deg

  // A missing label array is a warning (no seams); a 3-component one an error.
  vtkNew<vtkSurfaceAtlas> missing;
  missing->SetMapResolution(0);
  missing->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "NoSuchArray");
  vtkNew<MessageCollector> warnings;
  EXPECT_GT(RunOn(missing.Get(), fandisk, warnings)->GetNumberOfCells(), 0);
  ASSERT_FALSE(warnings->Warnings.empty());
  EXPECT_NE(warnings->Warnings[0].find("NoSuchArray"), std::string::npos);
  vtkNew<vtkDoubleArray> vectors;
  vectors->SetName("Vectors");
  vectors->SetNumberOfComponents(3);
  vectors->SetNumberOfTuples(fandisk->GetNumberOfCells());
  vectors->Fill(0.0);
  fandisk->GetCellData()->AddArray(vectors);
  vtkNew<vtkSurfaceAtlas> wrong;
  wrong->SetMapResolution(0);
  wrong->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "Vectors");
  vtkNew<MessageCollector> errors;
  EXPECT_EQ(RunOn(wrong.Get(), fandisk, errors)->GetNumberOfCells(), 0);
  ASSERT_FALSE(errors->Errors.empty());
  EXPECT_NE(errors->Errors[0].find("component"), std::string::npos) << errors->Errors[0];
}

TEST(SurfaceAtlas, GeometryMapsOfEveryChart)
{
  auto bunny = ReadOFF("bunny00.off");
  AddPointField(bunny, "height", [](const double* x) { return x[1]; });
  vtkNew<vtkSurfaceAtlas> f;
  f->SetMapResolution(384);
  f->SetInputData(bunny);
  f->Update();
  vtkMultiBlockDataSet* maps = vtkMultiBlockDataSet::SafeDownCast(f->GetOutputDataObject(1));
  vtkDataArray* areas = f->GetOutput()->GetFieldData()->GetArray("AtlasChartArea");
  ASSERT_TRUE(maps && areas);
  ASSERT_EQ(static_cast<vtkIdType>(maps->GetNumberOfBlocks()), areas->GetNumberOfTuples());
  vtkNew<vtkDiscreteCurvatures> curvatures;
  curvatures->SetInputData(bunny);
  curvatures->Update();
  vtkDataArray* vertexH = curvatures->GetOutput()->GetPointData()->GetArray("MeanCurvature");
  double worstArea = 0.0, worstHeight = 0.0, worstOff = 0.0, outsideH = 0.0;
  vtkIdType inside = 0;
  for (unsigned int c = 0; c < maps->GetNumberOfBlocks(); ++c)
  {
    vtkImageData* image = vtkImageData::SafeDownCast(maps->GetBlock(c));
    ASSERT_NE(image, nullptr);
    ASSERT_EQ(image->GetNumberOfPoints(), 384 * 384);
    vtkDataArray* face = image->GetPointData()->GetArray("FaceId");
    vtkDataArray* embedding = image->GetPointData()->GetArray("Embedding");
    vtkDataArray* ratio = image->GetPointData()->GetArray("AreaRatio");
    vtkDataArray* height = image->GetPointData()->GetArray("height");
    vtkDataArray* meanH = image->GetPointData()->GetArray("MeanCurvature");
    ASSERT_TRUE(face && embedding && ratio && height && meanH && image->GetPointData()->GetArray("GaussianCurvature"));
    double integral = 0.0;
    for (vtkIdType p = 0; p < image->GetNumberOfPoints(); ++p)
    {
      const vtkIdType cell = static_cast<vtkIdType>(face->GetComponent(p, 0));
      if (cell < 0)
      {
        ASSERT_TRUE(std::isnan(embedding->GetComponent(p, 0)));
        continue;
      }
      ++inside;
      integral += ratio->GetComponent(p, 0) / (384.0 * 384.0);
      double x[3];
      embedding->GetTuple(p, x);
      // A linear point array is reproduced exactly; the point is on its cell.
      worstHeight = std::max(worstHeight, std::abs(height->GetComponent(p, 0) - x[1]));
      worstOff = std::max(worstOff, DistanceToCellPlane(bunny, cell, x));
      vtkIdType n = 0;
      const vtkIdType* ids = nullptr;
      bunny->GetCellPoints(cell, n, ids);
      // The curvature map between its triangle's vertex values (the filter's).
      double lo = HUGE_VAL, hi = -HUGE_VAL;
      for (int k = 0; k < 3; ++k)
      {
        lo = std::min(lo, vertexH->GetComponent(ids[k], 0));
        hi = std::max(hi, vertexH->GetComponent(ids[k], 0));
      }
      const double h = meanH->GetComponent(p, 0);
      outsideH = std::max(outsideH, std::max(lo - h, h - hi) / std::max(1.0, std::abs(hi)));
    }
    worstArea = std::max(worstArea, std::abs(integral - areas->GetComponent(c, 0)) / areas->GetComponent(c, 0));
  }
  double bounds[6];
  bunny->GetBounds(bounds);
  const double diagonal = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) + (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  std::printf("bunny00 maps at 384^2: %lld pixels inside, area %.2e, linear data %.2e, off the cell %.2e, "
              "curvature outside its corners %.2e\n", static_cast<long long>(inside), worstArea, worstHeight,
    worstOff / diagonal, outsideH);
  EXPECT_GT(inside, 0);
  EXPECT_LT(worstArea, 3e-3); // pixel coverage of the chart outline: about 1/n (1e-3 at 512^2 on eight.off, core test)
  EXPECT_LT(worstHeight, 1e-12 * diagonal);
  EXPECT_LT(worstOff, 1e-6 * diagonal);
  EXPECT_LT(outsideH, 1e-12);
}

TEST(SurfaceAtlas, ManyChartsShareTheMapsPixels)
{
  // 300 separate octahedra (a scan's debris): 600 charts, far more than
  // one per 2,000 triangles. Their maps share the pixels of 64 charts at
  // full size, with a warning (2,000 of them took 53 s and 11 GB).
  const std::array<std::array<double, 3>, 6> corners{ { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 },
    { 0, 0, 1 }, { 0, 0, -1 } } };
  const std::array<std::array<vtkIdType, 3>, 8> faces{ { { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 },
    { 2, 0, 5 }, { 1, 2, 5 }, { 3, 1, 5 }, { 0, 3, 5 } } };
  constexpr int Count = 300;
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> cells;
  for (int k = 0; k < Count; ++k)
  {
    const double offset[3] = { 3.0 * (k % 10), 3.0 * ((k / 10) % 10), 3.0 * (k / 100) };
    for (const auto& c : corners)
    {
      points->InsertNextPoint(c[0] + offset[0], c[1] + offset[1], c[2] + offset[2]);
    }
    for (auto f : faces)
    {
      for (vtkIdType& v : f)
      {
        v += 6 * k;
      }
      cells->InsertNextCell(3, f.data());
    }
  }
  vtkNew<vtkPolyData> debris;
  debris->SetPoints(points);
  debris->SetPolys(cells);
  vtkNew<vtkSurfaceAtlas> f;
  vtkNew<MessageCollector> messages;
  RunOn(f.Get(), debris, messages);
  vtkMultiBlockDataSet* maps = vtkMultiBlockDataSet::SafeDownCast(f->GetOutputDataObject(1));
  const double charts = f->GetOutput()->GetFieldData()->GetArray("AtlasCharts")->GetComponent(0, 0);
  ASSERT_NE(maps, nullptr);
  ASSERT_GE(charts, Count);
  ASSERT_EQ(maps->GetNumberOfBlocks(), static_cast<unsigned int>(charts));
  const int side = static_cast<int>(256.0 * std::sqrt(64.0 / charts));
  vtkIdType inside = 0;
  for (unsigned int c = 0; c < maps->GetNumberOfBlocks(); ++c)
  {
    vtkImageData* image = vtkImageData::SafeDownCast(maps->GetBlock(c));
    ASSERT_NE(image, nullptr);
    int dims[3];
    image->GetDimensions(dims);
    ASSERT_EQ(dims[0], side);
    ASSERT_EQ(dims[1], side);
    vtkDataArray* face = image->GetPointData()->GetArray("FaceId");
    for (vtkIdType p = 0; p < image->GetNumberOfPoints(); ++p)
    {
      inside += face->GetComponent(p, 0) >= 0 ? 1 : 0;
    }
  }
  std::printf("%d octahedra: %g charts, maps of %d x %d, %lld pixels inside\n", Count, charts, side, side,
    static_cast<long long>(inside));
  EXPECT_LE(charts * side * side, 64.0 * 256 * 256);
  EXPECT_GT(inside, charts * side * side / 4); // every chart's map covers its chart
  EXPECT_TRUE(messages->WarnedAbout("instead")) << (messages->Warnings.empty() ? "" : messages->Warnings[0]);
}

TEST(SurfaceAtlas, OneAtlasImageOfThePackedCharts)
{
  const auto bunny = ReadOFF("bunny00.off");
  vtkNew<vtkSurfaceAtlas> f;
  f->SetMapLayout(vtkSurfaceAtlas::ATLAS);
  f->SetMapResolution(512);
  f->SetInputData(bunny);
  f->Update();
  vtkMultiBlockDataSet* maps = vtkMultiBlockDataSet::SafeDownCast(f->GetOutputDataObject(1));
  ASSERT_TRUE(maps && maps->GetNumberOfBlocks() == 1);
  EXPECT_STREQ(maps->GetMetaData(0u)->Get(vtkCompositeDataSet::NAME()), "Atlas");
  vtkImageData* image = vtkImageData::SafeDownCast(maps->GetBlock(0));
  ASSERT_TRUE(image && image->GetNumberOfPoints() == 512 * 512);
  // The chart of every input cell, from the cut surface.
  vtkPolyData* cut = f->GetOutput();
  vtkDataArray* cutChart = cut->GetCellData()->GetArray("ChartId");
  vtkDataArray* cutCell = cut->GetCellData()->GetArray("vtkOriginalCellIds");
  ASSERT_TRUE(cutChart && cutCell);
  std::vector<int> chartOf(bunny->GetNumberOfCells(), -1);
  for (vtkIdType c = 0; c < cut->GetNumberOfCells(); ++c)
  {
    chartOf[static_cast<vtkIdType>(cutCell->GetComponent(c, 0))] = static_cast<int>(cutChart->GetComponent(c, 0));
  }
  vtkDataArray* face = image->GetPointData()->GetArray("FaceId");
  vtkDataArray* chart = image->GetPointData()->GetArray("ChartId");
  vtkDataArray* ratio = image->GetPointData()->GetArray("AreaRatio");
  vtkDataArray* embedding = image->GetPointData()->GetArray("Embedding");
  ASSERT_TRUE(face && chart && ratio && embedding && image->GetPointData()->GetArray("MeanCurvature"));
  double integral = 0.0, worstOff = 0.0;
  vtkIdType inside = 0, wrongChart = 0;
  for (vtkIdType p = 0; p < image->GetNumberOfPoints(); ++p)
  {
    const vtkIdType cell = static_cast<vtkIdType>(face->GetComponent(p, 0));
    if (cell < 0)
    {
      EXPECT_EQ(chart->GetComponent(p, 0), -1.0);
      continue;
    }
    ++inside;
    wrongChart += chartOf[cell] != static_cast<int>(chart->GetComponent(p, 0));
    integral += ratio->GetComponent(p, 0) / (512.0 * 512.0);
    double x[3];
    embedding->GetTuple(p, x);
    worstOff = std::max(worstOff, DistanceToCellPlane(bunny, cell, x));
  }
  vtkDataArray* areas = cut->GetFieldData()->GetArray("AtlasChartArea");
  double total = 0.0;
  for (vtkIdType c = 0; c < areas->GetNumberOfTuples(); ++c)
  {
    total += areas->GetComponent(c, 0);
  }
  const double packing = cut->GetFieldData()->GetArray("AtlasPackingEfficiency")->GetComponent(0, 0);
  std::printf("bunny00 atlas image at 512^2: %lld texels inside (packing %.3f), area %.2e\n",
    static_cast<long long>(inside), packing, std::abs(integral - total) / total);
  EXPECT_EQ(wrongChart, 0);
  EXPECT_NEAR(inside / (512.0 * 512.0), packing, 0.05);
  EXPECT_LT(std::abs(integral - total) / total, 1e-3);
  EXPECT_LT(worstOff, 1e-6 * bunny->GetLength());
}

TEST(SurfaceAtlas, AbortLeavesAnEmptyOutput)
{
  const auto bunny = ReadOFF("bunny00.off");
  vtkNew<vtkSurfaceAtlas> f;
  f->SetInputData(bunny);
  f->SetNumberOfThreads(1);
  vtkNew<vtkCallbackCommand> abort;
  abort->SetCallback([](vtkObject* caller, unsigned long, void*, void*) {
    auto* alg = static_cast<vtkAlgorithm*>(caller);
    if (alg->GetProgress() > 0.1)
    {
      alg->SetAbortExecute(1);
    }
  });
  f->AddObserver(vtkCommand::ProgressEvent, abort);
  f->Update();
  EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_EQ(vtkMultiBlockDataSet::SafeDownCast(f->GetOutputDataObject(1))->GetNumberOfBlocks(), 0u);
}
