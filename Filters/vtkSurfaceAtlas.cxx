#include "vtkSurfaceAtlas.h"
#include "vtkBeltramiSettings.h"

#include "vtkBeltramiSurface.h"

#include "Maps/Atlas.h"
#include "Maps/GeometryImages.h"
#include "Mesh/Curvatures.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <string>
#include <vector>

BELTRAMI_SAME_ENUM(vtkSurfaceAtlas::CIRCLE, beltrami::ParameterizationBoundary::Circle);
BELTRAMI_SAME_ENUM(vtkSurfaceAtlas::SQUARE, beltrami::ParameterizationBoundary::Square);
BELTRAMI_SAME_ENUM(vtkSurfaceAtlas::NATURAL, beltrami::ParameterizationBoundary::Natural);

vtkStandardNewMacro(vtkSurfaceAtlas);

vtkSurfaceAtlas::vtkSurfaceAtlas()
{
  this->SetNumberOfOutputPorts(2);
  // The defaults have one source: the core's AtlasOptions.
  beltrami::AtlasOptions defaults;
  this->CopySettings(defaults, vtkBeltramiCopy::FromCore);
  // Input array 0: seam labels (a cell array; none by default).
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, static_cast<const char*>(nullptr));
}

bool vtkSurfaceAtlas::ReadSeamLabels(const vtkBeltramiSurface& surface, beltrami::AtlasOptions& options)
{
  std::string error;
  vtkDataArray* labels = vtkBeltramiSurface::SelectedCellArray(this, surface.Input(), 0, 1, "seam label", error);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  const beltrami::MeshTopology& topology = surface.Topology();
  for (beltrami::Index t = 0; labels && t < topology.NumberOfTriangles(); ++t)
  {
    const double label = labels->GetComponent(surface.TriangleCell(topology.OriginalTriangleIds()[t]), 0);
    // NaN labels form a region of their own.
    options.SeamLabels.push_back(std::isfinite(label) ? static_cast<int>(std::llround(label)) : INT_MIN);
  }
  return true;
}

void vtkSurfaceAtlas::SetChartBoundary(int boundary)
{
  if ((boundary == CIRCLE || boundary == SQUARE || boundary == NATURAL) && boundary != this->ChartBoundary)
  {
    this->ChartBoundary = boundary;
    this->Modified();
  }
}

void vtkSurfaceAtlas::CopySettings(beltrami::AtlasOptions& o, vtkBeltramiCopy direction)
{
  BeltramiCopySetting(this->NumberOfCharts, o.NumberOfCharts, direction);
  BeltramiCopySetting(this->MaximumChartArea, o.MaximumChartArea, direction);
  BeltramiCopySetting(this->BalanceAreas, o.BalanceAreas, direction);
  BeltramiCopySetting(this->SplitAtFeatures, o.SplitAtFeatures, direction);
  BeltramiCopySetting(this->FeatureAngle, o.FeatureAngle, direction);
  BeltramiCopySetting(this->ChartBoundary, o.ChartBoundary, direction);
  BeltramiCopySetting(this->TextureSize, o.TextureSize, direction);
  BeltramiCopySetting(this->MarginTexels, o.MarginTexels, direction);
  BeltramiCopySetting(this->NumberOfThreads, o.NumberOfThreads, direction);
}

int vtkSurfaceAtlas::FillOutputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkMultiBlockDataSet");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

vtkTypeBool vtkSurfaceAtlas::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkBeltramiSurface::NewCompositeOutputs(request, outputVector);
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

int vtkSurfaceAtlas::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return vtkBeltramiSurface::RunOnWholeSurface(this, inputVector, outputVector,
    [this](vtkPolyData* input, vtkPolyData* output) { return this->Build(input, output); });
}

int vtkSurfaceAtlas::Build(vtkPolyData* input, vtkPolyData* output)
{
  output->Initialize(); // a defined output: empty
  vtkBeltramiSurface surface;
  const vtkBeltramiSurface::Readiness ready = surface.BuildWhole(this, input, this->NumberOfThreads, "the atlas");
  if (ready != vtkBeltramiSurface::Readiness::Ready)
  {
    return ready == vtkBeltramiSurface::Readiness::Empty ? 1 : 0;
  }
  const std::string split = surface.SplitNonManifold(this->NumberOfThreads);
  if (!split.empty())
  {
    vtkWarningMacro(<< split << ", and the atlas keeps the parts apart.");
  }
  const beltrami::MeshTopology& topology = surface.Topology();
  std::vector<double> storage;
  const double* points = surface.PointsAsDouble(storage);
  beltrami::AtlasOptions options;
  this->CopySettings(options, vtkBeltramiCopy::ToCore);
  if (!this->ReadSeamLabels(surface, options))
  {
    return 0;
  }
  this->UpdateProgress(0.0);
  const beltrami::AtlasResult atlas = beltrami::BuildAtlas(topology, points, options, [this](double fraction) {
    this->UpdateProgress(0.5 * fraction);
    return !this->GetAbortExecute();
  });
  if (!atlas.Completed)
  {
    return 1; // aborted: the output stays empty
  }
  if (!atlas.Error.empty())
  {
    vtkErrorMacro(<< atlas.Error << ". The output is empty.");
    return 0;
  }
  if (!atlas.Warning.empty())
  {
    vtkWarningMacro(<< atlas.Warning << ".");
  }
  std::vector<vtkIdType> triangleCell(topology.NumberOfTriangles());
  for (beltrami::Index t = 0; t < topology.NumberOfTriangles(); ++t)
  {
    triangleCell[t] = surface.TriangleCell(topology.OriginalTriangleIds()[t]);
  }
  this->WriteCutSurface(input, surface, atlas, triangleCell, output);
  this->UpdateProgress(0.5);
  if (this->MapResolution > 0)
  {
    this->WriteMaps(input, surface, points, atlas, triangleCell);
  }
  this->UpdateProgress(1.0);
  return 1;
}

void vtkSurfaceAtlas::WriteCutSurface(vtkPolyData* input, const vtkBeltramiSurface& surface,
  const beltrami::AtlasResult& atlas, const std::vector<vtkIdType>& triangleCell, vtkPolyData* output)
{
  vtkIdType numPoints = 0, numTriangles = 0;
  for (const beltrami::AtlasChart& chart : atlas.Charts)
  {
    numPoints += static_cast<vtkIdType>(chart.Vertices.size());
    numTriangles += static_cast<vtkIdType>(chart.Triangles.size());
  }
  vtkNew<vtkPoints> cutPoints;
  cutPoints->SetDataType(input->GetPoints()->GetDataType() == VTK_FLOAT ? VTK_FLOAT : VTK_DOUBLE);
  cutPoints->SetNumberOfPoints(numPoints);
  vtkNew<vtkDoubleArray> uv, chartUV;
  uv->SetName("UV");
  chartUV->SetName("ChartUV");
  uv->SetNumberOfComponents(2);
  chartUV->SetNumberOfComponents(2);
  uv->SetNumberOfTuples(numPoints);
  chartUV->SetNumberOfTuples(numPoints);
  vtkNew<vtkIdTypeArray> pointIds, cellIds;
  pointIds->SetName("vtkOriginalPointIds");
  cellIds->SetName("vtkOriginalCellIds");
  pointIds->SetNumberOfTuples(numPoints);
  cellIds->SetNumberOfTuples(numTriangles);
  vtkNew<vtkIntArray> chartId;
  chartId->SetName("ChartId");
  chartId->SetNumberOfTuples(numTriangles);
  vtkNew<vtkCellArray> triangles;
  triangles->AllocateExact(numTriangles, 3 * numTriangles);
  vtkIdType first = 0, cell = 0;
  for (std::size_t c = 0; c < atlas.Charts.size(); ++c)
  {
    const beltrami::AtlasChart& chart = atlas.Charts[c];
    for (std::size_t v = 0; v < chart.Vertices.size(); ++v)
    {
      const vtkIdType id = first + static_cast<vtkIdType>(v);
      const vtkIdType point = surface.InputPoint(chart.Vertices[v]);
      cutPoints->SetPoint(id, input->GetPoint(point));
      pointIds->SetValue(id, point);
      double packed[2];
      beltrami::AtlasUV(chart, static_cast<beltrami::Index>(v), packed);
      uv->SetTypedTuple(id, packed);
      chartUV->SetTypedTuple(id, &chart.UV[2 * v]);
    }
    for (std::size_t t = 0; t < chart.Triangles.size(); ++t, ++cell)
    {
      const vtkIdType ids[3] = { first + chart.Corners[3 * t], first + chart.Corners[3 * t + 1],
        first + chart.Corners[3 * t + 2] };
      triangles->InsertNextCell(3, ids);
      chartId->SetValue(cell, static_cast<int>(c));
      cellIds->SetValue(cell, triangleCell[chart.Triangles[t]]);
    }
    first += static_cast<vtkIdType>(chart.Vertices.size());
  }
  output->SetPoints(cutPoints);
  output->SetPolys(triangles);
  output->GetPointData()->CopyAllocate(input->GetPointData(), numPoints);
  for (vtkIdType p = 0; p < numPoints; ++p)
  {
    output->GetPointData()->CopyData(input->GetPointData(), pointIds->GetValue(p), p);
  }
  output->GetCellData()->CopyAllocate(input->GetCellData(), numTriangles);
  for (vtkIdType t = 0; t < numTriangles; ++t)
  {
    output->GetCellData()->CopyData(input->GetCellData(), cellIds->GetValue(t), t);
  }
  output->GetPointData()->AddArray(uv);
  output->GetPointData()->SetTCoords(uv);
  output->GetPointData()->AddArray(chartUV);
  output->GetPointData()->AddArray(pointIds);
  output->GetCellData()->AddArray(chartId);
  output->GetCellData()->AddArray(cellIds);

  vtkNew<vtkDoubleArray> area, angle, areaDistortion;
  area->SetName("AtlasChartArea");
  angle->SetName("AtlasChartAngleDistortion");
  areaDistortion->SetName("AtlasChartAreaDistortion");
  for (const beltrami::AtlasChart& chart : atlas.Charts)
  {
    area->InsertNextValue(chart.Area3D);
    angle->InsertNextValue(chart.MeanAngleDistortion);
    areaDistortion->InsertNextValue(chart.MeanAreaDistortion);
  }
  vtkNew<vtkIntArray> count, splits;
  count->SetName("AtlasCharts");
  count->InsertNextValue(static_cast<int>(atlas.Charts.size()));
  splits->SetName("AtlasSplitsForFlips");
  splits->InsertNextValue(atlas.SplitsForFlips);
  vtkNew<vtkIntArray> cutEdges;
  cutEdges->SetName("AtlasCutEdges");
  cutEdges->InsertNextValue(static_cast<int>(atlas.CutEdges));
  vtkNew<vtkDoubleArray> efficiency;
  efficiency->SetName("AtlasPackingEfficiency");
  efficiency->InsertNextValue(atlas.PackingEfficiency);
  vtkFieldData* fd = output->GetFieldData();
  fd->ShallowCopy(input->GetFieldData());
  for (vtkAbstractArray* a : { static_cast<vtkAbstractArray*>(count), static_cast<vtkAbstractArray*>(area),
         static_cast<vtkAbstractArray*>(angle), static_cast<vtkAbstractArray*>(areaDistortion),
         static_cast<vtkAbstractArray*>(efficiency), static_cast<vtkAbstractArray*>(splits),
         static_cast<vtkAbstractArray*>(cutEdges) })
  {
    fd->AddArray(a);
  }
}

namespace
{

/// A chart's map image: n x n pixel centres of its square.
vtkSmartPointer<vtkImageData> MapImage(int n)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(n, n, 1);
  image->SetSpacing(1.0 / n, 1.0 / n, 1.0);
  image->SetOrigin(0.5 / n, 0.5 / n, 0.0);
  return image;
}

/// A new point array `name` of the image (on LargeBuffer's cached pages:
/// fresh pages for every map cost more than filling them).
double* AddMap(vtkImageData* image, const char* name, int components)
{
  vtkSmartPointer<vtkDataArray> array =
    vtkBeltramiSurface::NewArray(VTK_DOUBLE, name, components, image->GetNumberOfPoints());
  image->GetPointData()->AddArray(array);
  return static_cast<double*>(array->GetVoidPointer(0));
}

/// A per-vertex quantity sampled by the maps.
struct MapField
{
  std::string Name;
  int Components;
  std::vector<double> Values; ///< per surface vertex
};

/// The maps of `chart` (one of the atlas' charts, or the whole packed atlas)
/// at n^2 pixels, rasterised into `raster` (reused).
vtkSmartPointer<vtkImageData> ChartMaps(const beltrami::AtlasChart& chart, int n, const double* points,
  const std::vector<MapField>& fields, const std::vector<vtkIdType>& triangleCell, beltrami::ChartRaster& raster,
  int numThreads)
{
  beltrami::RasterizeChart(chart, n, raster, numThreads);
  vtkSmartPointer<vtkImageData> image = MapImage(n);
  vtkNew<vtkIdTypeArray> faces;
  faces->SetName("FaceId");
  faces->SetNumberOfTuples(image->GetNumberOfPoints());
  for (std::size_t p = 0; p < raster.Face.size(); ++p)
  {
    faces->SetValue(static_cast<vtkIdType>(p), raster.Face[p] < 0 ? -1 : triangleCell[chart.Triangles[raster.Face[p]]]);
  }
  image->GetPointData()->AddArray(faces);
  beltrami::AreaMap(raster, chart, points, AddMap(image, "AreaRatio", 1), numThreads);
  for (const MapField& f : fields)
  {
    beltrami::InterpolateOnRaster(
      raster, chart, f.Values.data(), f.Components, AddMap(image, f.Name.c_str(), f.Components), false, numThreads);
  }
  return image;
}

/// The per-vertex quantities of the maps: the embedding, the curvatures
/// (boundary points from their interior neighbours) and the input's numeric
/// point arrays, as doubles.
std::vector<MapField> MapFields(
  vtkPolyData* input, const vtkBeltramiSurface& surface, const double* points, int numThreads)
{
  const beltrami::MeshTopology& topology = surface.Topology();
  const vtkIdType numPoints = topology.NumberOfVertices(); // (the input's, and split points' copies)
  std::vector<double> meanCurvature(numPoints), gaussianCurvature(numPoints);
  beltrami::CurvatureOptions curvatureOptions;
  curvatureOptions.Boundary = beltrami::BoundaryPolicy::InteriorAverage;
  curvatureOptions.NumberOfThreads = numThreads;
  beltrami::CurvatureOutputs curvatures;
  curvatures.MeanCurvature = meanCurvature.data();
  curvatures.GaussianCurvature = gaussianCurvature.data();
  beltrami::ComputeCurvatures(topology, points, curvatureOptions, curvatures);
  std::vector<MapField> fields = { { "Embedding", 3, std::vector<double>(points, points + 3 * numPoints) },
    { "MeanCurvature", 1, meanCurvature }, { "GaussianCurvature", 1, gaussianCurvature } };
  vtkPointData* pd = input->GetPointData();
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = pd->GetArray(a);
    if (array && array->GetName() && std::string(array->GetName()) != "Embedding")
    {
      MapField f{ array->GetName(), array->GetNumberOfComponents(), {} };
      f.Values.resize(static_cast<std::size_t>(numPoints) * f.Components);
      for (vtkIdType i = 0; i < numPoints; ++i)
      {
        for (int c = 0; c < f.Components; ++c)
        {
          f.Values[i * f.Components + c] = array->GetComponent(surface.InputPoint(i), c);
        }
      }
      fields.push_back(std::move(f));
    }
  }
  return fields;
}

constexpr int MinimumMapResolution = 8;
constexpr double MapBytesPerPixel = 44.0; ///< FaceId and five doubles, at least

} // namespace

int vtkSurfaceAtlas::ChartMapResolution(std::size_t charts, std::int64_t triangles)
{
  // The texels of MapResolution^2 maps for as many charts as the automatic
  // count gives the surface (one per TrianglesPerChart triangles), and at
  // least MinimumFullCharts: more charts (a scan's debris, many small
  // components) share them.  2,000 separate octahedra made 4,000 charts
  // and 11 GB of maps in 53 s.
  constexpr double MinimumFullCharts = 64.0;
  const double full = static_cast<double>(this->MapResolution) * this->MapResolution;
  const double budget =
    std::max(MinimumFullCharts, static_cast<double>(triangles) / beltrami::TrianglesPerChart) * full;
  if (static_cast<double>(charts) * full <= budget)
  {
    return this->MapResolution;
  }
  const int resolution = std::min(this->MapResolution,
    std::max(MinimumMapResolution, static_cast<int>(std::sqrt(budget / static_cast<double>(charts)))));
  vtkWarningMacro(<< charts << " charts' maps of " << this->MapResolution << " x " << this->MapResolution
                  << " pixels would take " << std::ceil(static_cast<double>(charts) * full * MapBytesPerPixel / 1e8) / 10
                  << " GB or more: each chart's maps are "
                  << resolution << " x " << resolution << " instead (as many pixels as "
                  << static_cast<int>(budget / full) << " charts at full size). Set Map Layout to one atlas "
                  << "image for a single " << this->MapResolution << " x " << this->MapResolution
                  << " image of the whole surface.");
  return resolution;
}

void vtkSurfaceAtlas::WriteMaps(vtkPolyData* input, const vtkBeltramiSurface& surface, const double* points,
  const beltrami::AtlasResult& atlas, const std::vector<vtkIdType>& triangleCell)
{
  vtkMultiBlockDataSet* maps = vtkMultiBlockDataSet::SafeDownCast(this->GetOutputDataObject(1));
  if (!maps)
  {
    return;
  }
  const beltrami::MeshTopology& topology = surface.Topology();
  const std::vector<MapField> fields = MapFields(input, surface, points, this->NumberOfThreads);
  beltrami::ChartRaster raster; // one for every chart: its memory is reused
  if (this->MapLayout == ATLAS)
  {
    const beltrami::AtlasChart packed = beltrami::PackedAtlas(atlas);
    vtkSmartPointer<vtkImageData> image =
      ChartMaps(packed, this->MapResolution, points, fields, triangleCell, raster, this->NumberOfThreads);
    vtkNew<vtkIntArray> charts;
    charts->SetName("ChartId");
    charts->SetNumberOfTuples(image->GetNumberOfPoints());
    for (std::size_t p = 0; p < raster.Face.size(); ++p)
    {
      charts->SetValue(static_cast<vtkIdType>(p),
        raster.Face[p] < 0 ? -1 : atlas.ChartOfTriangle[packed.Triangles[raster.Face[p]]]);
    }
    image->GetPointData()->AddArray(charts);
    maps->SetNumberOfBlocks(1);
    maps->SetBlock(0, image);
    maps->GetMetaData(0u)->Set(vtkCompositeDataSet::NAME(), "Atlas");
    return;
  }
  const int resolution = this->ChartMapResolution(atlas.Charts.size(), topology.NumberOfTriangles());
  maps->SetNumberOfBlocks(static_cast<unsigned int>(atlas.Charts.size()));
  for (std::size_t c = 0; c < atlas.Charts.size(); ++c)
  {
    maps->SetBlock(static_cast<unsigned int>(c),
      ChartMaps(atlas.Charts[c], resolution, points, fields, triangleCell, raster, this->NumberOfThreads));
    maps->GetMetaData(static_cast<unsigned int>(c))->Set(vtkCompositeDataSet::NAME(), ("Chart " + std::to_string(c)).c_str());
  }
}

void vtkSurfaceAtlas::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfCharts: " << this->NumberOfCharts << "\n";
  os << indent << "MaximumChartArea: " << this->MaximumChartArea << "\n";
  os << indent << "BalanceAreas: " << this->BalanceAreas << "\n";
  os << indent << "SplitAtFeatures: " << this->SplitAtFeatures << "\n";
  os << indent << "FeatureAngle: " << this->FeatureAngle << "\n";
  os << indent << "ChartBoundary: " << this->ChartBoundary << "\n";
  os << indent << "TextureSize: " << this->TextureSize << "\n";
  os << indent << "MarginTexels: " << this->MarginTexels << "\n";
  os << indent << "MapResolution: " << this->MapResolution << "\n";
  os << indent << "MapLayout: " << this->MapLayout << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
