#include "vtkSurfaceLineDrawing.h"

#include "vtkBeltramiPieces.h"
#include "vtkBeltramiSettings.h"
#include "vtkBeltramiSurface.h"

#include "Solvers/Partition.h"

#include "Drawing/LineDrawing.h"
#include "Drawing/Visibility.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <string>
#include <utility>

BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::CONTOUR, beltrami::LineType::Contour);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::SUGGESTIVE_CONTOUR, beltrami::LineType::SuggestiveContour);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::SUGGESTIVE_HIGHLIGHT, beltrami::LineType::SuggestiveHighlight);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::RIDGE, beltrami::LineType::Ridge);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::VALLEY, beltrami::LineType::Valley);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::BOUNDARY, beltrami::LineType::Boundary);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::CREASE, beltrami::LineType::Crease);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::APPARENT_RIDGE, beltrami::LineType::ApparentRidge);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::ALL_LINES, beltrami::LineVisibility::All);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::VISIBLE_LINES, beltrami::LineVisibility::Visible);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::VISIBLE_AND_HIDDEN_LINES, beltrami::LineVisibility::VisibleAndHidden);

vtkStandardNewMacro(vtkSurfaceLineDrawing);

struct vtkSurfaceLineDrawing::Kept
{
  beltrami::LineDrawingGeometry Geometry;
  /// Its derivatives as the surface output's array, made once (not per view).
  vtkSmartPointer<vtkDoubleArray> Derivatives;
  vtkIdType InputPoints = 0; ///< the input's (a split piece's topology has ghost points after them)
  /// Split runs: the field array LineDrawingDistribution.
  vtkSmartPointer<vtkFieldData> Distribution;
  /// The last view's NdotV, RadialCurvature, RadialCurvatureDerivative: the
  /// next view writes over them when nothing else holds them any more (no
  /// fresh pages for 24 bytes per point at every camera change).
  vtkSmartPointer<vtkDoubleArray> ViewArrays[3];
  const void* Input = nullptr;
  vtkMTimeType InputTime = 0;
  beltrami::FieldSmoothingOptions Smoothing; ///< the settings it was built with
};

vtkSurfaceLineDrawing::vtkSurfaceLineDrawing()
{
  this->SetNumberOfOutputPorts(2);
  // The defaults have one source: the core's LineDrawingOptions.
  beltrami::LineDrawingOptions defaults;
  this->CopySettings(defaults, vtkBeltramiCopy::FromCore);
}

vtkSurfaceLineDrawing::~vtkSurfaceLineDrawing() = default;

void vtkSurfaceLineDrawing::CopySettings(beltrami::LineDrawingOptions& o, vtkBeltramiCopy direction)
{
  bool* draw[beltrami::NumberOfLineTypes] = { &this->Contours, &this->SuggestiveContours,
    &this->SuggestiveHighlights, &this->Ridges, &this->Valleys, &this->Boundaries, &this->Creases,
    &this->ApparentRidges };
  for (int type = 0; type < beltrami::NumberOfLineTypes; ++type)
  {
    BeltramiCopySetting(*draw[type], o.Draw[type], direction);
  }
  BeltramiCopySetting(this->FeatureSize, o.FeatureSize, direction);
  BeltramiCopySetting(this->CurvatureSmoothing, o.CurvatureSmoothing, direction);
  BeltramiCopySetting(this->SuggestiveContourThreshold, o.SuggestiveThreshold, direction);
  BeltramiCopySetting(this->SuggestiveContourAngle, o.SuggestiveAngle, direction);
  BeltramiCopySetting(this->RidgeThreshold, o.RidgeThreshold, direction);
  BeltramiCopySetting(this->ApparentRidgeThreshold, o.ApparentRidgeThreshold, direction);
  BeltramiCopySetting(this->CreaseAngle, o.CreaseAngle, direction);
  BeltramiCopySetting(this->MinimumLineLength, o.MinimumLength, direction);
  BeltramiCopySetting(this->HysteresisRatio, o.HysteresisRatio, direction);
  BeltramiCopySetting(this->DropBackFacing, o.DropBackFacing, direction);
  BeltramiCopySetting(this->AvoidCreases, o.AvoidCreases, direction);
  BeltramiCopySetting(this->Visibility, o.Visibility, direction);
  BeltramiCopySetting(this->NumberOfThreads, o.NumberOfThreads, direction);
}

int vtkSurfaceLineDrawing::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (vtkBeltramiPieces::CanSolveTogether(outputVector->GetInformationObject(0)))
  {
    const int done = this->DrawSplit(inputVector, outputVector);
    if (done >= 0)
    {
      return done;
    }
  }
  return vtkBeltramiSurface::RunOnWholeSurface(this, inputVector, outputVector,
    [this](vtkPolyData* input, vtkPolyData* output) { return this->Draw(input, output); });
}

int vtkSurfaceLineDrawing::DrawSplit(vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* lines = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* surface = vtkPolyData::GetData(outputVector, 1);
  vtkBeltramiPieces ranks;
  ranks.SetCollective(true);
  if (!ranks.AllAgree(lines && surface))
  {
    vtkErrorMacro("Missing poly data outputs on some rank.");
    return 0;
  }
  lines->Initialize(); // a defined output: empty
  if (ranks.AllAgree(this->Cache && this->Cache->Geometry.Split && this->Keeps(input)))
  {
    surface->ShallowCopy(input);
    return this->DrawView(lines, surface); // a new view of the kept pieces
  }
  return vtkBeltramiSurface::ExecuteDistributed(this, input, surface, outputVector->GetInformationObject(0),
    this->NumberOfThreads, [&](vtkBeltramiSurface& pieces) {
      this->KeepGeometry(pieces, input, true);
      return this->DrawView(lines, surface) != 0;
    });
}

namespace
{

vtkSmartPointer<vtkDoubleArray> NewArray(const char* name, int components, vtkIdType tuples)
{
  return vtkDoubleArray::SafeDownCast(vtkBeltramiSurface::NewArray(VTK_DOUBLE, name, components, tuples));
}

template <typename Vector>
vtkSmartPointer<vtkDoubleArray> FromVector(const char* name, int components, const Vector& values)
{
  auto array = NewArray(name, components, static_cast<vtkIdType>(values.size() / components));
  std::copy(values.begin(), values.end(), array->GetPointer(0));
  return array;
}

void WriteLines(const beltrami::LineSet& lines, vtkPolyData* output)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(lines.PointStrength.size()));
  std::copy(lines.Points.begin(), lines.Points.end(),
    vtkDoubleArray::SafeDownCast(points->GetData())->GetPointer(0));
  vtkNew<vtkCellArray> cells;
  for (beltrami::Index l = 0; l < lines.NumberOfLines(); ++l)
  {
    cells->InsertNextCell(lines.Offsets[l + 1] - lines.Offsets[l]);
    for (beltrami::Index k = lines.Offsets[l]; k < lines.Offsets[l + 1]; ++k)
    {
      cells->InsertCellPoint(lines.Connectivity[k]);
    }
  }
  output->SetPoints(points);
  output->SetLines(cells);
  auto normals = FromVector("Normals", 3, lines.Normals);
  output->GetPointData()->SetNormals(normals);
  output->GetPointData()->AddArray(FromVector("Strength", 1, lines.PointStrength));
  vtkNew<vtkUnsignedCharArray> type;
  type->SetName("LineType");
  type->SetNumberOfValues(lines.NumberOfLines());
  std::copy(lines.Type.begin(), lines.Type.end(), type->GetPointer(0));
  output->GetCellData()->AddArray(type);
  output->GetCellData()->AddArray(FromVector("Strength", 1, lines.Strength));
  output->GetCellData()->SetActiveScalars("LineType");
  if (!lines.Hidden.empty())
  {
    vtkNew<vtkUnsignedCharArray> hidden;
    hidden->SetName("Hidden");
    hidden->SetNumberOfValues(lines.NumberOfLines());
    std::copy(lines.Hidden.begin(), lines.Hidden.end(), hidden->GetPointer(0));
    output->GetCellData()->AddArray(hidden);
  }
}

/// The view on the lines' field data, for writers that project them
/// (vtkLineDrawingWriter): CameraPosition, ViewDirection, ViewUp,
/// ParallelProjection, Visibility.
void WriteView(vtkPolyData* output, const double position[3], const double direction[3], const double up[3],
  bool parallel, int visibility)
{
  vtkFieldData* fd = output->GetFieldData();
  const std::pair<const char*, const double*> vectors[3] = { { "CameraPosition", position },
    { "ViewDirection", direction }, { "ViewUp", up } };
  for (const auto& v : vectors)
  {
    auto array = NewArray(v.first, 3, 1);
    std::copy(v.second, v.second + 3, array->GetPointer(0));
    fd->AddArray(array);
  }
  const std::pair<const char*, int> flags[2] = { { "ParallelProjection", parallel ? 1 : 0 },
    { "Visibility", visibility } };
  for (const auto& f : flags)
  {
    vtkNew<vtkIntArray> array;
    array->SetName(f.first);
    array->InsertNextValue(f.second);
    fd->AddArray(array);
  }
}

} // namespace

namespace
{

/// When `input` (its cells or its points) last changed.
vtkMTimeType ChangeTime(vtkPolyData* input)
{
  return input ? std::max(input->GetMTime(), input->GetPoints() ? input->GetPoints()->GetMTime() : 0) : 0;
}

} // namespace

beltrami::FieldSmoothingOptions vtkSurfaceLineDrawing::Smoothing() const
{
  beltrami::FieldSmoothingOptions smoothing;
  smoothing.Amount = this->CurvatureSmoothing;
  smoothing.FeatureSize = this->CurvatureSmoothing > 0.0 ? this->FeatureSize : 0.0;
  return smoothing;
}

bool vtkSurfaceLineDrawing::Keeps(vtkPolyData* input) const
{
  const beltrami::FieldSmoothingOptions smoothing = this->Smoothing();
  return this->Cache && this->Cache->Input == input && this->Cache->InputTime == ChangeTime(input) &&
    this->Cache->Smoothing.Amount == smoothing.Amount && this->Cache->Smoothing.FeatureSize == smoothing.FeatureSize;
}

int vtkSurfaceLineDrawing::UpdateGeometry(vtkPolyData* input, bool& ready)
{
  ready = true;
  if (this->Keeps(input) && !this->Cache->Geometry.Split)
  {
    return 1;
  }
  this->Cache.reset();
  vtkBeltramiSurface surface;
  const vtkBeltramiSurface::Readiness readiness =
    surface.BuildWhole(this, input, this->NumberOfThreads, "the line drawing");
  if (readiness != vtkBeltramiSurface::Readiness::Ready)
  {
    ready = false;
    return readiness == vtkBeltramiSurface::Readiness::Empty ? 1 : 0;
  }
  this->KeepGeometry(surface, input, false);
  return 1;
}

void vtkSurfaceLineDrawing::KeepGeometry(const vtkBeltramiSurface& surface, vtkPolyData* input, bool split)
{
  this->Cache.reset();
  auto kept = std::make_unique<Kept>();
  const auto partition = split ? surface.SplitPieces().SharedSplit() : nullptr;
  kept->Smoothing = this->Smoothing();
  surface.Dispatch([&](const auto* points) {
    kept->Geometry.Build(surface.Topology(), points, this->NumberOfThreads, partition, kept->Smoothing);
  });
  if (!kept->Geometry.SmoothingWarning.empty() && (!partition || partition->Rank() == 0))
  {
    vtkWarningMacro("Curvature Smoothing could not smooth the surface (" << kept->Geometry.SmoothingWarning
                                                                          << "): the lines are found on the surface itself.");
  }
  kept->InputPoints = input ? input->GetNumberOfPoints() : 0;
  const auto& derivatives = kept->Geometry.Derivatives;
  kept->Derivatives = NewArray("CurvatureDerivative", 4, kept->InputPoints);
  std::copy(derivatives.begin(), derivatives.begin() + 4 * kept->InputPoints, kept->Derivatives->GetPointer(0));
  if (partition)
  {
    kept->Distribution = vtkSmartPointer<vtkFieldData>::New();
    surface.SplitPieces().AddDistribution(kept->Distribution, "LineDrawingDistribution");
  }
  kept->Input = input;
  kept->InputTime = ChangeTime(input);
  ++this->GeometryBuilds;
  const beltrami::Index undefined = kept->Geometry.UndefinedVertices; // (over all ranks)
  if (undefined > 0 && (!partition || partition->Rank() == 0))
  {
    // (A split piece's topology has cut stars at the edge of its ring: not
    // a defect of the user's surface.)
    const std::string defects = partition ? std::string() : surface.TopologyWarning();
    vtkWarningMacro(<< undefined << " points have no curvature (boundary, non-manifold, NaN or degenerate 1-rings"
                    << (defects.empty() ? std::string() : ": " + defects)
                    << "): suggestive contours, highlights, ridges and valleys stop at their triangles.");
  }
  this->Cache = std::move(kept);
}

int vtkSurfaceLineDrawing::Draw(vtkPolyData* input, vtkPolyData* output)
{
  output->Initialize(); // a defined output: empty
  vtkPolyData* surface = vtkPolyData::SafeDownCast(this->GetOutputDataObject(1));
  surface->ShallowCopy(input);
  bool ready = false;
  if (!this->UpdateGeometry(input, ready))
  {
    return 0; // error reported
  }
  return ready ? this->DrawView(output, surface) : 1; // (not ready: nothing to draw, warned)
}

int vtkSurfaceLineDrawing::DrawView(vtkPolyData* output, vtkPolyData* surface)
{
  const beltrami::LineDrawingGeometry& geometry = this->Cache->Geometry;
  beltrami::LineDrawingOptions options;
  this->CopySettings(options, vtkBeltramiCopy::ToCore);
  beltrami::LineView view;
  view.Perspective = !this->ParallelProjection;
  view.Position = beltrami::Vec3(this->CameraPosition[0], this->CameraPosition[1], this->CameraPosition[2]);
  view.Direction = beltrami::Vec3(this->ViewDirection[0], this->ViewDirection[1], this->ViewDirection[2]);
  if (!view.Perspective && !(view.Direction.norm() > 0.0))
  {
    vtkErrorMacro("ViewDirection is zero: no view. The output is empty."); // (on every rank alike)
    return 0;
  }
  const vtkIdType n = geometry.NumberOfVertices();
  const char* names[3] = { "NdotV", "RadialCurvature", "RadialCurvatureDerivative" };
  double* values[3];
  for (int k = 0; k < 3; ++k)
  {
    vtkSmartPointer<vtkDoubleArray>& array = this->Cache->ViewArrays[k];
    if (!array || array->GetReferenceCount() > 1) // (held downstream: a new one)
    {
      array = NewArray(names[k], 1, n);
    }
    array->SetNumberOfTuples(n); // (every value is written)
    array->Modified();
    values[k] = array->GetPointer(0);
  }
  beltrami::LineSet lines = beltrami::DrawLines(geometry, view, options, { values[0], values[1], values[2] });
  if (options.Visibility != beltrami::LineVisibility::All) // (split: collective)
  {
    beltrami::VisibilityOptions visibility;
    visibility.KeepHidden = options.Visibility == beltrami::LineVisibility::VisibleAndHidden;
    visibility.NumberOfThreads = this->NumberOfThreads;
    visibility.MinimumLength = options.MinimumLength *
      (options.FeatureSize > 0.0 ? options.FeatureSize : geometry.AutomaticFeatureSize());
    lines = beltrami::SplitByVisibility(lines, geometry, view, visibility);
  }
  WriteLines(lines, output);
  if (!geometry.Split || geometry.Split->Rank() == 0)
  {
    WriteView(output, this->CameraPosition, this->ViewDirection, this->ViewUp, this->ParallelProjection,
      this->Visibility);
  }
  vtkPointData* pd = surface->GetPointData();
  pd->AddArray(this->Cache->Derivatives);
  for (vtkDoubleArray* array : this->Cache->ViewArrays)
  {
    array->SetNumberOfTuples(this->Cache->InputPoints); // (split: drops the ghost points' values)
    pd->AddArray(array);
  }
  if (this->Cache->Distribution)
  {
    surface->GetFieldData()->AddArray(this->Cache->Distribution->GetAbstractArray(0));
  }
  return 1;
}

void vtkSurfaceLineDrawing::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "CameraPosition: " << this->CameraPosition[0] << " " << this->CameraPosition[1] << " "
     << this->CameraPosition[2] << "\n"
     << indent << "ViewDirection: " << this->ViewDirection[0] << " " << this->ViewDirection[1] << " "
     << this->ViewDirection[2] << "\n"
     << indent << "ViewUp: " << this->ViewUp[0] << " " << this->ViewUp[1] << " " << this->ViewUp[2] << "\n"
     << indent << "ParallelProjection: " << this->ParallelProjection << "\n"
     << indent << "Visibility: " << this->Visibility << "\n"
     << indent << "CurvatureSmoothing: " << this->CurvatureSmoothing << "\n"
     << indent << "Contours: " << this->Contours << "\n"
     << indent << "SuggestiveContours: " << this->SuggestiveContours << "\n"
     << indent << "SuggestiveHighlights: " << this->SuggestiveHighlights << "\n"
     << indent << "Ridges: " << this->Ridges << "\n"
     << indent << "Valleys: " << this->Valleys << "\n"
     << indent << "Boundaries: " << this->Boundaries << "\n"
     << indent << "Creases: " << this->Creases << "\n"
     << indent << "ApparentRidges: " << this->ApparentRidges << "\n"
     << indent << "ApparentRidgeThreshold: " << this->ApparentRidgeThreshold << "\n"
     << indent << "FeatureSize: " << this->FeatureSize << "\n"
     << indent << "SuggestiveContourThreshold: " << this->SuggestiveContourThreshold << "\n"
     << indent << "SuggestiveContourAngle: " << this->SuggestiveContourAngle << "\n"
     << indent << "RidgeThreshold: " << this->RidgeThreshold << "\n"
     << indent << "MinimumLineLength: " << this->MinimumLineLength << "\n"
     << indent << "HysteresisRatio: " << this->HysteresisRatio << "\n"
     << indent << "CreaseAngle: " << this->CreaseAngle << "\n"
     << indent << "DropBackFacing: " << this->DropBackFacing << "\n"
     << indent << "AvoidCreases: " << this->AvoidCreases << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n"
     << indent << "GeometryBuilds: " << this->GeometryBuilds << "\n";
}
