#include "vtkSurfaceLineDrawing.h"

#include "vtkBeltramiSettings.h"
#include "vtkBeltramiSurface.h"

#include "Drawing/LineDrawing.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
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

BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::CONTOUR, beltrami::LineType::Contour);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::SUGGESTIVE_CONTOUR, beltrami::LineType::SuggestiveContour);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::SUGGESTIVE_HIGHLIGHT, beltrami::LineType::SuggestiveHighlight);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::RIDGE, beltrami::LineType::Ridge);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::VALLEY, beltrami::LineType::Valley);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::BOUNDARY, beltrami::LineType::Boundary);
BELTRAMI_SAME_ENUM(vtkSurfaceLineDrawing::CREASE, beltrami::LineType::Crease);

vtkStandardNewMacro(vtkSurfaceLineDrawing);

struct vtkSurfaceLineDrawing::Kept
{
  beltrami::LineDrawingGeometry Geometry;
  /// Its derivatives as the surface output's array, made once (not per view).
  vtkSmartPointer<vtkDoubleArray> Derivatives;
  const void* Input = nullptr;
  vtkMTimeType InputTime = 0;
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
    &this->SuggestiveHighlights, &this->Ridges, &this->Valleys, &this->Boundaries, &this->Creases };
  for (int type = 0; type < beltrami::NumberOfLineTypes; ++type)
  {
    BeltramiCopySetting(*draw[type], o.Draw[type], direction);
  }
  BeltramiCopySetting(this->FeatureSize, o.FeatureSize, direction);
  BeltramiCopySetting(this->SuggestiveContourThreshold, o.SuggestiveThreshold, direction);
  BeltramiCopySetting(this->SuggestiveContourAngle, o.SuggestiveAngle, direction);
  BeltramiCopySetting(this->RidgeThreshold, o.RidgeThreshold, direction);
  BeltramiCopySetting(this->CreaseAngle, o.CreaseAngle, direction);
  BeltramiCopySetting(this->MinimumLineLength, o.MinimumLength, direction);
  BeltramiCopySetting(this->HysteresisRatio, o.HysteresisRatio, direction);
  BeltramiCopySetting(this->DropBackFacing, o.DropBackFacing, direction);
  BeltramiCopySetting(this->AvoidCreases, o.AvoidCreases, direction);
  BeltramiCopySetting(this->NumberOfThreads, o.NumberOfThreads, direction);
}

int vtkSurfaceLineDrawing::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return vtkBeltramiSurface::RunOnWholeSurface(this, inputVector, outputVector,
    [this](vtkPolyData* input, vtkPolyData* output) { return this->Draw(input, output); });
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
}

} // namespace

int vtkSurfaceLineDrawing::UpdateGeometry(vtkPolyData* input, bool& ready)
{
  const vtkMTimeType time = std::max(input->GetMTime(), input->GetPoints() ? input->GetPoints()->GetMTime() : 0);
  ready = true;
  if (this->Cache && this->Cache->Input == input && this->Cache->InputTime == time)
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
  auto kept = std::make_unique<Kept>();
  surface.Dispatch([&](const auto* points) { kept->Geometry.Build(surface.Topology(), points, this->NumberOfThreads); });
  kept->Derivatives = FromVector("CurvatureDerivative", 4, kept->Geometry.Derivatives);
  kept->Input = input;
  kept->InputTime = time;
  ++this->GeometryBuilds;
  if (kept->Geometry.UndefinedVertices > 0)
  {
    const std::string defects = surface.TopologyWarning();
    vtkWarningMacro(<< kept->Geometry.UndefinedVertices
                    << " points have no curvature (boundary, non-manifold, NaN or degenerate 1-rings"
                    << (defects.empty() ? std::string() : ": " + defects)
                    << "): suggestive contours, highlights, ridges and valleys stop at their triangles.");
  }
  this->Cache = std::move(kept);
  return 1;
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
  if (!ready)
  {
    return 1; // nothing to draw (warned)
  }
  const beltrami::LineDrawingGeometry& geometry = this->Cache->Geometry;
  beltrami::LineDrawingOptions options;
  this->CopySettings(options, vtkBeltramiCopy::ToCore);
  beltrami::LineView view;
  view.Perspective = !this->ParallelProjection;
  view.Position = beltrami::Vec3(this->CameraPosition[0], this->CameraPosition[1], this->CameraPosition[2]);
  view.Direction = beltrami::Vec3(this->ViewDirection[0], this->ViewDirection[1], this->ViewDirection[2]);
  if (!view.Perspective && !(view.Direction.norm() > 0.0))
  {
    vtkErrorMacro("ViewDirection is zero: no view. The output is empty.");
    return 0;
  }
  const vtkIdType n = geometry.NumberOfVertices();
  auto ndotv = NewArray("NdotV", 1, n);
  auto kr = NewArray("RadialCurvature", 1, n);
  auto drkr = NewArray("RadialCurvatureDerivative", 1, n);
  const beltrami::ViewFields fields{ ndotv->GetPointer(0), kr->GetPointer(0), drkr->GetPointer(0) };
  WriteLines(beltrami::DrawLines(geometry, view, options, fields), output);
  vtkPointData* pd = surface->GetPointData();
  pd->AddArray(this->Cache->Derivatives);
  pd->AddArray(ndotv);
  pd->AddArray(kr);
  pd->AddArray(drkr);
  return 1;
}

void vtkSurfaceLineDrawing::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "CameraPosition: " << this->CameraPosition[0] << " " << this->CameraPosition[1] << " "
     << this->CameraPosition[2] << "\n"
     << indent << "ViewDirection: " << this->ViewDirection[0] << " " << this->ViewDirection[1] << " "
     << this->ViewDirection[2] << "\n"
     << indent << "ParallelProjection: " << this->ParallelProjection << "\n"
     << indent << "Contours: " << this->Contours << "\n"
     << indent << "SuggestiveContours: " << this->SuggestiveContours << "\n"
     << indent << "SuggestiveHighlights: " << this->SuggestiveHighlights << "\n"
     << indent << "Ridges: " << this->Ridges << "\n"
     << indent << "Valleys: " << this->Valleys << "\n"
     << indent << "Boundaries: " << this->Boundaries << "\n"
     << indent << "Creases: " << this->Creases << "\n"
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
