#include "vtkSurfaceRemeshingInternals.h"

#include "Maps/Atlas.h"
#include "Mesh/MeshMeasures.h"
#include "Remeshing/RemeshMetric.h"
#include "Remeshing/SurfaceRemeshing.h"
#include "Mesh/SurfaceDistance.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSurfaceRemeshing);

vtkSurfaceRemeshing::vtkSurfaceRemeshing()
{
  this->SetNumberOfOutputPorts(2);
  // Input array 0: the importance of POINT_ARRAY (a point array); 1: the
  // metric of TENSOR_ARRAY.
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, static_cast<const char*>(nullptr));
  this->SetInputArrayToProcess(1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, static_cast<const char*>(nullptr));
}

vtkSurfaceRemeshing::~vtkSurfaceRemeshing() = default;

int vtkSurfaceRemeshing::FillOutputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkMultiBlockDataSet");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

vtkTypeBool vtkSurfaceRemeshing::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkBeltramiSurface::NewCompositeOutputs(request, outputVector);
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

int vtkSurfaceRemeshing::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return vtkBeltramiSurface::RunOnWholeSurface(this, inputVector, outputVector,
    [this](vtkPolyData* input, vtkPolyData* output) { return this->Build(input, output); });
}

int vtkSurfaceRemeshing::KeepSurface(vtkPolyData* input)
{
  const vtkMTimeType time = std::max(input->GetMTime(), input->GetPoints() ? input->GetPoints()->GetMTime() : 0);
  if (this->Cache && this->Cache->Input == input && this->Cache->InputTime == time)
  {
    return 1;
  }
  this->Cache.reset();
  auto kept = std::make_unique<Kept>();
  const vtkBeltramiSurface::Readiness ready =
    kept->Surface.BuildWhole(this, input, this->NumberOfThreads, "the remesh");
  if (ready != vtkBeltramiSurface::Readiness::Ready)
  {
    return ready == vtkBeltramiSurface::Readiness::Empty ? -1 : 0;
  }
  const std::string split = kept->Surface.SplitNonManifold(this->NumberOfThreads);
  if (!split.empty())
  {
    vtkWarningMacro(<< split << ", and the remesh keeps the parts apart.");
  }
  kept->Points = kept->Surface.PointsAsDouble(kept->Storage);
  kept->Layouts[0].Points = kept->Points;
  kept->Input = input;
  kept->InputTime = time;
  this->Cache = std::move(kept);
  return 1;
}

const beltrami::AtlasResult& vtkSurfaceRemeshing::Atlas()
{
  Kept& surface = *this->Cache;
  Layout& kept = surface.Laid();
  // With sharp edges kept, their fragments shorter than the spacing of the
  // requested count are dropped (the error-driven mode's count is not known
  // yet: all are kept there).
  const double spacing = this->SplitsAtFeatures() && this->MaximumDeviation <= 0.0 && this->NumberOfVertices > 0
    ? beltrami::UniformSpacing(
        beltrami::SurfaceArea(surface.Surface.Topology(), kept.Points, this->NumberOfThreads), this->NumberOfVertices)
    : 0.0;
  if (!kept.Atlas || kept.SplitAtFeatures != this->SplitsAtFeatures() || kept.FeatureAngle != this->FeatureAngle ||
    kept.FeatureSpacing != spacing)
  {
    beltrami::AtlasOptions options = beltrami::RemeshingAtlasOptions(spacing);
    options.SplitAtFeatures = this->SplitsAtFeatures();
    options.FeatureAngle = this->FeatureAngle;
    options.NumberOfThreads = this->NumberOfThreads;
    kept.Atlas = std::make_unique<beltrami::AtlasResult>(
      beltrami::BuildAtlas(surface.Surface.Topology(), kept.Points, options));
    kept.Remeshing.Clear();
    kept.SplitAtFeatures = this->SplitsAtFeatures();
    kept.FeatureAngle = this->FeatureAngle;
    kept.FeatureSpacing = spacing;
    ++this->AtlasBuilds;
  }
  return *kept.Atlas;
}

namespace
{

void AddField(vtkPolyData* output, const char* name, std::initializer_list<double> values)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  for (double v : values)
  {
    array->InsertNextValue(v);
  }
  output->GetFieldData()->AddArray(array);
}

/// The input's cell arrays on the remesh `output`: each triangle takes the
/// values of the input cell nearest its centre (labels stay labels);
/// nothing where the input has none.
void CopyCellData(vtkPolyData* input, const vtkBeltramiSurface& surface, const double* points,
  const beltrami::RemeshResult& r, vtkPolyData* output)
{
  vtkCellData* in = input->GetCellData();
  const beltrami::MeshTopology& topology = surface.Topology();
  if (in->GetNumberOfArrays() == 0 || r.Triangles.empty())
  {
    return;
  }
  const beltrami::IndexArray& triangles = topology.TriangleList();
  const beltrami::TriangleGrid grid(points, triangles.data(), triangles.size() / 3);
  vtkCellData* out = output->GetCellData();
  const vtkIdType count = static_cast<vtkIdType>(r.Triangles.size() / 3);
  out->CopyAllocate(in, count);
  for (vtkIdType t = 0; t < count; ++t)
  {
    const beltrami::Index* c = r.Triangles.data() + 3 * t;
    const beltrami::Vec3 centre = (beltrami::Point(r.Points.data(), c[0]) + beltrami::Point(r.Points.data(), c[1]) +
                                    beltrami::Point(r.Points.data(), c[2])) / 3.0;
    double distance = 0.0;
    const beltrami::Index nearest = grid.Nearest(centre, distance);
    const vtkIdType cell = nearest < 0 ? -1 : surface.TriangleCell(topology.OriginalTriangleIds()[nearest]);
    if (cell >= 0)
    {
      out->CopyData(in, cell, t);
    }
    else
    {
      out->NullData(t);
    }
  }
}

/// The remesh into `output`: points, triangles, the input's point data
/// interpolated, the kind of every vertex and the quality figures.
void WriteRemesh(vtkPolyData* input, const vtkBeltramiSurface& surface, const beltrami::RemeshResult& r,
  std::size_t charts, vtkPolyData* output)
{
  const vtkIdType n = static_cast<vtkIdType>(r.Points.size() / 3);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  for (vtkIdType v = 0; v < n; ++v)
  {
    points->SetPoint(v, &r.Points[3 * v]);
  }
  vtkNew<vtkCellArray> polys;
  for (std::size_t t = 0; t < r.Triangles.size(); t += 3)
  {
    const vtkIdType ids[3] = { r.Triangles[t], r.Triangles[t + 1], r.Triangles[t + 2] };
    polys->InsertNextCell(3, ids);
  }
  output->SetPoints(points);
  output->SetPolys(polys);
  vtkPointData* in = input->GetPointData();
  vtkPointData* out = output->GetPointData();
  out->InterpolateAllocate(in, n);
  vtkNew<vtkIdList> corners;
  corners->SetNumberOfIds(3);
  for (vtkIdType v = 0; v < n; ++v)
  {
    for (int k = 0; k < 3; ++k)
    {
      corners->SetId(k, surface.InputPoint(surface.Topology().CornerVertex(3 * r.SourceTriangle[v] + k)));
    }
    out->InterpolatePoint(in, v, corners, const_cast<double*>(&r.SourceBarycentric[3 * v]));
  }
  vtkNew<vtkUnsignedCharArray> kind;
  kind->SetName("SampleKind");
  kind->SetNumberOfValues(n);
  for (vtkIdType v = 0; v < n; ++v)
  {
    kind->SetValue(v, static_cast<unsigned char>(r.Samples.Kind[v]));
  }
  out->AddArray(kind);
  const beltrami::MeshTopology remesh(static_cast<beltrami::Index>(n), beltrami::IndexArray(r.Triangles.begin(), r.Triangles.end()));
  const beltrami::TriangleQuality q = beltrami::MeasureTriangleQuality(remesh, r.Points.data());
  AddField(output, "RemeshMeanMinimumAngle", { q.MeanMinimumAngle });
  AddField(output, "RemeshMinimumAngle", { q.MinimumAngle });
  AddField(output, "RemeshFractionBelow30", { q.FractionBelow30 });
  AddField(output, "RemeshFractionValence6", { q.FractionValence6 });
  AddField(output, "RemeshEdgeLengthVariation", { q.EdgeLengthVariation });
  AddField(output, "RemeshCharts", { static_cast<double>(charts) });
  AddField(output, "RemeshDeviation", { r.DeviationToInput, r.DeviationFromInput });
  AddField(output, "RemeshSeconds",
    { r.SamplingSeconds, r.TriangulationSeconds, r.OptimizationSeconds, r.FidelitySeconds });
}

/// The control map and the halftone as one image (output 1).
void WriteControlMap(const beltrami::SurfaceSamples& samples, vtkMultiBlockDataSet* maps)
{
  const int n = samples.Resolution;
  vtkNew<vtkImageData> image;
  image->SetDimensions(n, n, 1);
  image->SetSpacing(1.0 / n, 1.0 / n, 1.0);
  image->SetOrigin(0.5 / n, 0.5 / n, 0.0);
  vtkNew<vtkDoubleArray> map;
  map->SetName("ControlMap");
  map->SetNumberOfValues(static_cast<vtkIdType>(n) * n);
  vtkNew<vtkUnsignedCharArray> halftone;
  halftone->SetName("Halftone");
  halftone->SetNumberOfValues(static_cast<vtkIdType>(n) * n);
  for (vtkIdType p = 0; p < static_cast<vtkIdType>(n) * n; ++p)
  {
    map->SetValue(p, samples.ControlMap[p]);
    halftone->SetValue(p, samples.Halftone.empty() ? 0 : samples.Halftone[p]);
  }
  image->GetPointData()->AddArray(map);
  image->GetPointData()->AddArray(halftone);
  maps->SetNumberOfBlocks(1);
  maps->SetBlock(0, image);
  maps->GetMetaData(0u)->Set(vtkMultiBlockDataSet::NAME(), "ControlMap");
}

} // namespace

void vtkSurfaceRemeshing::AddTransferFunctionPoint(double x, double importance)
{
  this->TransferFunction.push_back(x);
  this->TransferFunction.push_back(importance);
  this->Modified();
}

void vtkSurfaceRemeshing::RemoveAllTransferFunctionPoints()
{
  if (!this->TransferFunction.empty())
  {
    this->TransferFunction.clear();
    this->Modified();
  }
}

bool vtkSurfaceRemeshing::BuildMetric(const std::uint8_t* featureEdges, std::vector<double>& metric)
{
  const beltrami::MeshTopology& topology = this->Cache->Surface.Topology();
  const double* points = this->Cache->Laid().Points;
  if (this->Anisotropy == TENSOR_ARRAY)
  {
    std::string error;
    vtkDataArray* array = this->Cache->Surface.SelectedPointArray(this, 1, 6, "metric", error);
    if (!array)
    {
      vtkErrorMacro(<< (error.empty() ? std::string("Anisotropy TENSOR_ARRAY needs a 6-component point array (input "
                                                    "array 1).")
                                      : error)
                    << " The output is empty.");
      return false;
    }
    metric.resize(6 * static_cast<std::size_t>(topology.NumberOfVertices()));
    for (beltrami::Index v = 0; v < topology.NumberOfVertices(); ++v)
    {
      for (int c = 0; c < 6; ++c)
      {
        metric[6 * v + c] = array->GetComponent(this->Cache->Surface.InputPoint(v), c);
      }
      if (!(beltrami::MetricDensity(&metric[6 * v]) > 0.0) || !std::isfinite(beltrami::MetricDensity(&metric[6 * v])))
      {
        vtkErrorMacro(<< "Anisotropy TENSOR_ARRAY: the tensor of point " << v << " is not positive definite in its "
                      << "tangent plane. The output is empty.");
        return false;
      }
    }
    return true;
  }
  // (Kept while the surface, its feature lines and these settings stay: a
  // new count re-runs the sampling only.)
  const std::array<double, 4> key = { this->MaximumAnisotropy, this->MinimumImportance, this->Gradation,
    static_cast<double>(this->AtlasBuilds) };
  Layout& kept = this->Cache->Laid();
  if (!kept.Metric.empty() && kept.MetricKey == key)
  {
    metric = kept.Metric;
    return true;
  }
  beltrami::MetricOptions options;
  options.MaximumAnisotropy = this->MaximumAnisotropy;
  options.Minimum = this->MinimumImportance;
  options.Gradation = this->Gradation; // (0: the remesher grades it over its spacing, RemeshOptions::MetricGradation)
  options.FeatureEdges = featureEdges;
  options.NumberOfThreads = this->NumberOfThreads;
  beltrami::MetricResult result = beltrami::CurvatureMetric(topology, points, options);
  if (!result.Warning.empty())
  {
    vtkWarningMacro(<< "Anisotropy: " << result.Warning << ".");
  }
  metric = std::move(result.Metric);
  kept.Metric = metric;
  kept.MetricKey = key;
  return true;
}

bool vtkSurfaceRemeshing::BuildImportance(std::vector<double>& importance)
{
  vtkBeltramiSurface& surface = this->Cache->Surface;
  const beltrami::MeshTopology& topology = surface.Topology();
  Layout& kept = this->Cache->Laid();
  std::vector<double> values;
  if (this->Importance == POINT_ARRAY)
  {
    std::string error;
    vtkDataArray* array = surface.SelectedPointArray(this, 0, 1, "importance", error);
    if (!array)
    {
      vtkErrorMacro(<< (error.empty() ? std::string("Importance POINT_ARRAY needs a point array (input array 0).") : error)
                    << " The output is empty.");
      return false;
    }
    values.resize(topology.NumberOfVertices());
    beltrami::Index nonFinite = 0;
    for (beltrami::Index v = 0; v < topology.NumberOfVertices(); ++v)
    {
      values[v] = array->GetComponent(surface.InputPoint(v), 0);
      nonFinite += std::isfinite(values[v]) ? 0 : 1;
    }
    if (nonFinite > 0)
    {
      vtkWarningMacro(<< nonFinite << " importance values are NaN or infinite: those points take the mean "
                      << "importance.");
    }
  }
  else if (this->Importance != UNIFORM)
  {
    if (kept.CurvatureImportance != this->Importance)
    {
      kept.Curvatures = beltrami::CurvatureValues(
        topology, kept.Points, static_cast<beltrami::CurvatureMeasure>(this->Importance), this->NumberOfThreads);
      kept.CurvatureImportance = this->Importance;
    }
    values = kept.Curvatures;
  }
  if (!values.empty())
  {
    beltrami::ImportanceOptions transfer;
    transfer.Gamma = this->Gamma;
    transfer.TransferFunction = this->TransferFunction;
    transfer.Gradation = this->Gradation;
    transfer.Minimum = this->MinimumImportance;
    beltrami::ImportanceResult result =
      beltrami::ImportanceFromValues(topology, kept.Points, values, transfer, this->NumberOfThreads);
    if (!result.Warning.empty())
    {
      vtkWarningMacro(<< "Importance: " << result.Warning << ".");
    }
    importance = std::move(result.Importance);
  }
  return true;
}

bool vtkSurfaceRemeshing::RemeshLayout(Run& run, bool sparserSeams)
{
  const beltrami::MeshTopology& topology = this->Cache->Surface.Topology();
  const double* points = this->Cache->Laid().Points;
  if (!this->BuildImportance(run.Importance))
  {
    return false;
  }
  const beltrami::AtlasResult& atlas = this->Atlas();
  if (!atlas.Error.empty())
  {
    vtkErrorMacro(<< "No atlas: " << atlas.Error << ". The output is empty.");
    return false;
  }
  if (this->Anisotropy != ISOTROPIC &&
    !this->BuildMetric(atlas.FeatureEdges.empty() ? nullptr : atlas.FeatureEdges.data(), run.Metric))
  {
    return false;
  }
  beltrami::RemeshOptions& options = run.Options;
  options.NumberOfVertices = this->NumberOfVertices;
  options.Metric = run.Metric.empty() ? nullptr : run.Metric.data();
  options.MetricGradation = this->Gradation > 0.0 ? 0.0 : 1.0;
  if (this->Gradation > 0.0)
  {
    options.ImportanceGradation = 0.0; // (ImportanceFromValues graded it)
  }
  // The first fifth of the rounds in the charts' planes, the rest stitching
  // across the seams on the surface (beltrami::RemeshOptimization).
  options.Iterations = this->Iterations / 5;
  options.StitchingIterations = this->Iterations - options.Iterations;
  options.FeatureAngle = this->SplitsAtFeatures() ? this->FeatureAngle : 0.0;
  options.MaximumLineSag = this->MaximumLineSag;
  options.SparserSeams = sparserSeams;
  options.MaximumSurfaceSag = this->MaximumSurfaceSag;
  options.FarPinRounds = this->FidelityRounds;
  options.NumberOfThreads = this->NumberOfThreads;
  options.Cache = &this->Cache->Laid().Remeshing;
  if (this->Cache->Active > 0) // a smoothed copy: the remesh is moved onto the input and shaped there
  {
    options.FinalSurface = this->Cache->Points;
    options.FinalCache = &this->Cache->Layouts[0].Remeshing;
  }
  if (this->MaximumDeviation > 0.0)
  {
    run.Driven = beltrami::RemeshToDeviation(
      topology, points, atlas, run.Weights(), options, this->MaximumDeviation, this->MaximumDeviationRounds);
  }
  else
  {
    run.Driven.Remesh = beltrami::RemeshSurface(topology, points, atlas, run.Weights(), options);
  }
  return true;
}

int vtkSurfaceRemeshing::Build(vtkPolyData* input, vtkPolyData* output)
{
  output->Initialize(); // a defined output: empty
  this->KeepingSharpEdges = this->SharpEdgesTried = false;
  const int surfaceKept = this->KeepSurface(input);
  if (surfaceKept <= 0)
  {
    return surfaceKept < 0 ? 1 : 0; // nothing to remesh (warned), or an error
  }
  if (this->MaximumDeviation <= 0.0 && this->NumberOfVertices < 3)
  {
    vtkErrorMacro(<< "NumberOfVertices " << this->NumberOfVertices << ": a remesh needs at least 3 vertices, or a "
                  << "MaximumDeviation to choose the count. The output is empty.");
    return 0;
  }
  Kept& kept = *this->Cache;
  kept.Active = 0;
  kept.DenoisedRun.reset();
  kept.DenoisedCopy = -1;
  Run run;
  if (this->LayOutFoldedInputOnCopyFirst(run))
  {
    return this->Report(input, run, output);
  }
  if (!this->RemeshLayout(run))
  {
    return 0;
  }
  this->LayOutNoisyInputOnCopy(run);
  this->LayOutWithSparserSeams(run);
  this->KeepSharpEdgesWhereMissed(run);
  return this->Report(input, run, output);
}

int vtkSurfaceRemeshing::Report(vtkPolyData* input, const Run& run, vtkPolyData* output)
{
  const beltrami::MeshTopology& topology = this->Cache->Surface.Topology();
  const double* points = this->Cache->Laid().Points;
  const beltrami::AtlasResult& atlas = *this->Cache->Laid().Atlas;
  const beltrami::DeviationRemeshResult& driven = run.Driven;
  const beltrami::RemeshResult& remesh = driven.Remesh;
  const std::int64_t count = driven.Counts.empty() ? this->NumberOfVertices : driven.Counts.back();
  // Where the count cannot keep the input (a thin part, a component), the
  // message names one that does (with the count given, not the error-driven mode's).
  const bool far =
    (run.LaidDistance >= 0.0 ? run.LaidDistance : remesh.DeviationFromInput * remesh.Diagonal) > remesh.Spacing;
  const bool missing = this->MaximumDeviation <= 0.0 && (!remesh.Error.empty() || far);
  beltrami::RemeshOptions asked = run.Options;
  asked.NumberOfVertices = count;
  // A folding input (noise as large as its edges) remeshed with at least
  // as many vertices as it has: its far points are its noise, which more
  // vertices do not reach (bunny00 with noise of 0.3% of its diagonal, 11.7%
  // of its edges folded, at 50,000 vertices: 1.24 spacings away, and 1.47,
  // 1.09 and 1.72 at 2, 4 and 8 times the count, 32 s of remeshes to say so).
  const double folded = missing && remesh.Error.empty() && count >= topology.NumberOfVertices()
    ? this->Cache->FoldedShare() : 0.0;
  const beltrami::CountAdvice counts = missing && folded < beltrami::CrumpledShare
    ? beltrami::AdviseCounts(topology, points, atlas, run.Weights(), asked, remesh) : beltrami::CountAdvice();
  const std::int64_t keeping = counts.Keeps, remeshing = counts.Remeshes;
  const std::string succeeds = remeshing > 0 && (keeping == 0 || remeshing < keeping)
    ? " A remesh with " + std::to_string(remeshing) + " vertices succeeds." : std::string();
  std::ostringstream noisy;
  if (folded >= beltrami::CrumpledShare)
  {
    noisy << " The input folds (" << 100.0 * folded << "% of its neighbouring triangles face more than 90 degrees "
          << "apart) and has no more vertices than the remesh: its far points are its noise, which more vertices "
          << "do not reach; smooth it first (vtkImplicitFairing).";
  }
  const std::string advice = !missing ? std::string()
    : folded >= beltrami::CrumpledShare ? noisy.str()
    : succeeds + (keeping > 0 ? " A remesh with " + std::to_string(keeping) +
                     " vertices keeps every part of the input within its spacing."
                              : " No remesh with up to 8 times the count (at most 64 per input vertex) keeps every "
                                "part of the input within its spacing.");
  if (!remesh.Error.empty())
  {
    vtkErrorMacro(<< "Cannot remesh with " << count << " vertices: " << remesh.Error << "." << advice
                  << " The output is empty.");
    return 0;
  }
  const double diagonal = remesh.Diagonal;
  const double deviation = std::max(remesh.DeviationFromInput, remesh.DeviationToInput);
  if (this->MaximumDeviation > 0.0 && !driven.Met)
  {
    // Why it stopped, and where sharp edges were rounded off (a cylinder of
    // 128 vertices: 0.75% of its diagonal at 8,192 vertices; with its
    // edges kept 0.46% at 228), how to keep them.
    const std::int64_t most = beltrami::MostVerticesPerInputVertex * static_cast<std::int64_t>(topology.NumberOfVertices());
    const std::vector<std::uint8_t> sharp =
      this->SplitsAtFeatures() || this->SharpEdgesTried ? std::vector<std::uint8_t>()
                                                        : beltrami::SharpEdges(topology, points, this->FeatureAngle);
    vtkWarningMacro(<< "The remesh with " << count << " vertices is " << 100.0 * deviation
                    << "% of the diagonal from the input after " << driven.Rounds << " remeshes, more than the "
                    << "MaximumDeviation of " << 100.0 * this->MaximumDeviation << "% ("
                    << (count >= most ? std::to_string(beltrami::MostVerticesPerInputVertex) +
                            " vertices per input vertex, beyond what the input's resolution can use"
                                      : "MaximumDeviationRounds " + std::to_string(this->MaximumDeviationRounds))
                    << ")."
                    << (std::find(sharp.begin(), sharp.end(), 1) != sharp.end()
                           ? " The input has edges sharper than FeatureAngle, which the remesh rounds off: "
                             "SplitAtFeatures keeps them."
                           : ""));
  }
  else if (this->MaximumDeviation <= 0.0 && far)
  {
    const beltrami::Vec3& p = remesh.FarthestInputPoint;
    vtkWarningMacro(<< "The remesh with " << count << " vertices leaves parts of the input "
                    << "farther from it than its spacing (" << remesh.Spacing << "): the input point ("
                    << p[0] << ", " << p[1] << ", " << p[2] << ") is " << remesh.DeviationFromInput * diagonal
                    << " away (" << 100.0 * remesh.DeviationFromInput
                    << "% of the diagonal; field array RemeshDeviation)." << advice);
  }
  if (this->MaximumDeviation <= 0.0 && run.LaidDistance < 0.0 && remesh.DeviationToInput * diagonal > remesh.Spacing)
  {
    // (Triangles that bridge a gap or a fold of the input: the diamond
    // surface cut by a box had them, 2.6% of its diagonal off it, unsaid.)
    vtkWarningMacro(<< "The remesh with " << count << " vertices has triangles farther from the input than its "
                    << "spacing (" << remesh.Spacing << "): " << remesh.DeviationToInput * diagonal << " ("
                    << 100.0 * remesh.DeviationToInput << "% of the diagonal; field array RemeshDeviation): they "
                    << "bridge a gap or a fold of the input that the count cannot follow. More vertices, or a "
                    << "MaximumDeviation, follow it.");
  }
  WriteRemesh(input, this->Cache->Surface, remesh, atlas.Charts.size(), output);
  CopyCellData(input, this->Cache->Surface, this->Cache->Points, remesh, output);
  const double smallest = output->GetFieldData()->GetArray("RemeshMinimumAngle")->GetTuple1(0);
  if (smallest < 1.0)
  {
    // (A plate's rim thinner than the spacing with its sharp edges kept:
    // the thin plate at 1,000 vertices, 0.93 degrees.  Also in the
    // anisotropic mode, whose triangles stretched sixfold have angles of
    // 10 degrees and more: a sphere with 100 needles one input vertex wide,
    // at 2,000 vertices, had five of 0 degrees, three seam samples in a
    // line along a needle's ridge from its tip.)
    vtkWarningMacro(<< "The remesh with " << count << " vertices has a triangle with an angle of " << smallest
                    << " degrees (field array RemeshMinimumAngle): a part of the input thinner than its spacing "
                    << "(a needle, a plate's rim) or sharp edges meeting at a small angle leave no room for a "
                    << "rounder one. More vertices give them room.");
  }
  if (!run.Metric.empty())
  {
    const beltrami::MetricQuality q = beltrami::MeasureInMetric(topology, points,
      remesh.GradedMetric.empty() ? run.Metric.data() : remesh.GradedMetric.data(), remesh.Points,
      remesh.Triangles, remesh.SourceTriangle, remesh.SourceBarycentric);
    vtkNew<vtkDoubleArray> figures;
    figures->SetName("RemeshMetricQuality");
    for (const double value : { q.MedianEdgeLength, q.EdgesWithin20Percent, q.MinimumAngle, q.MeanMinimumAngle,
           q.TrianglesBelow30 })
    {
      figures->InsertNextValue(value);
    }
    output->GetFieldData()->AddArray(figures);
    vtkNew<vtkDoubleArray> pointMetric;
    pointMetric->SetName("Metric");
    pointMetric->SetNumberOfComponents(6);
    pointMetric->SetNumberOfTuples(static_cast<vtkIdType>(q.PointMetric.size() / 6));
    std::copy(q.PointMetric.begin(), q.PointMetric.end(), pointMetric->GetPointer(0));
    output->GetPointData()->AddArray(pointMetric);
  }
  WriteControlMap(remesh.Samples, vtkMultiBlockDataSet::SafeDownCast(this->GetOutputDataObject(1)));
  if (!driven.Counts.empty())
  {
    vtkNew<vtkIdTypeArray> rounds;
    rounds->SetName("RemeshRounds");
    for (const std::int64_t c : driven.Counts)
    {
      rounds->InsertNextValue(static_cast<vtkIdType>(c));
    }
    output->GetFieldData()->AddArray(rounds);
  }
  return 1;
}

void vtkSurfaceRemeshing::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfVertices: " << this->NumberOfVertices << "\n"
     << indent << "MaximumDeviation: " << this->MaximumDeviation << "\n"
     << indent << "MaximumDeviationRounds: " << this->MaximumDeviationRounds << "\n"
     << indent << "Importance: " << this->Importance << "\n"
     << indent << "Anisotropy: " << this->Anisotropy << "\n"
     << indent << "MaximumAnisotropy: " << this->MaximumAnisotropy << "\n"
     << indent << "Gamma: " << this->Gamma << "\n"
     << indent << "MinimumImportance: " << this->MinimumImportance << "\n"
     << indent << "Gradation: " << this->Gradation << "\n"
     << indent << "TransferFunctionPoints: " << this->GetNumberOfTransferFunctionPoints() << "\n"
     << indent << "SplitAtFeatures: " << this->SplitAtFeatures << "\n"
     << indent << "FeatureAngle: " << this->FeatureAngle << "\n"
     << indent << "MaximumLineSag: " << this->MaximumLineSag << "\n"
     << indent << "MaximumSurfaceSag: " << this->MaximumSurfaceSag << "\n"
     << indent << "FidelityRounds: " << this->FidelityRounds << "\n"
     << indent << "Iterations: " << this->Iterations << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
