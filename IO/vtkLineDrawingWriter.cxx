#include "vtkLineDrawingWriter.h"

#include "LineDrawingFormat.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

vtkStandardNewMacro(vtkLineDrawingWriter);

namespace
{

/// Copies the writer's style settings to the page options, or back (the
/// defaults have one source: LineDrawingPageOptions).
void CopyStyles(double* widths, double* colors, double& dash, beltrami::LineDrawingPageOptions& o, bool toPage)
{
  for (int s = 0; s < beltrami::NumberOfDrawingStyles; ++s)
  {
    beltrami::LineStyle& style = o.Styles[s];
    if (toPage)
    {
      style.Width = widths[s];
      std::copy(colors + 3 * s, colors + 3 * s + 3, style.Color);
    }
    else
    {
      widths[s] = style.Width;
      std::copy(style.Color, style.Color + 3, colors + 3 * s);
    }
  }
  if (toPage)
  {
    o.Styles[beltrami::HiddenStyle].Dash = dash;
  }
  else
  {
    dash = o.Styles[beltrami::HiddenStyle].Dash;
  }
}

/// The first `n` values of field array `name`, false when it is missing or short.
bool FieldValues(vtkPolyData* input, const char* name, int n, double* values)
{
  vtkDataArray* array = vtkArrayDownCast<vtkDataArray>(input->GetFieldData()->GetAbstractArray(name));
  if (!array || array->GetNumberOfTuples() * array->GetNumberOfComponents() < n)
  {
    return false;
  }
  for (int k = 0; k < n; ++k)
  {
    values[k] = array->GetComponent(k / array->GetNumberOfComponents(), k % array->GetNumberOfComponents());
  }
  return true;
}

} // namespace

vtkLineDrawingWriter::vtkLineDrawingWriter()
{
  const beltrami::LineDrawingPageOptions defaults;
  this->PageSize = defaults.PageSize;
  this->Margin = defaults.Margin;
  this->Tolerance = defaults.Tolerance;
  this->DrawHiddenLines = defaults.DrawHidden;
  this->TaperByStrength = defaults.TaperByStrength;
  beltrami::LineDrawingPageOptions copy = defaults;
  CopyStyles(this->LineWidths, this->LineColors, this->HiddenDash, copy, false);
}

vtkLineDrawingWriter::~vtkLineDrawingWriter()
{
  this->SetFileName(nullptr);
}

void vtkLineDrawingWriter::SetLineWidths(int index, double width)
{
  if (index >= 0 && index < beltrami::NumberOfDrawingStyles && this->LineWidths[index] != width)
  {
    this->LineWidths[index] = width;
    this->Modified();
  }
}

void vtkLineDrawingWriter::SetLineColors(int index, double value)
{
  if (index >= 0 && index < 3 * beltrami::NumberOfDrawingStyles && this->LineColors[index] != value)
  {
    this->LineColors[index] = value;
    this->Modified();
  }
}

vtkPolyData* vtkLineDrawingWriter::GetInput()
{
  return vtkPolyData::SafeDownCast(this->Superclass::GetInput());
}

vtkTypeBool vtkLineDrawingWriter::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (request->Has(vtkStreamingDemandDrivenPipeline::REQUEST_UPDATE_EXTENT()) && this->NumberOfPieces > 1)
  {
    // Each rank asks for its own piece, as ParaView's views do, so that a
    // distributed drawing runs together over the ranks (the whole data on
    // every rank, what a plain writer asks for, would draw each rank's
    // piece alone).
    vtkInformation* in = inputVector[0]->GetInformationObject(0);
    in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), this->Piece);
    in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), this->NumberOfPieces);
    return 1;
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

int vtkLineDrawingWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

void vtkLineDrawingWriter::WriteData()
{
  if (this->Piece > 0)
  {
    return; // (rank 0 holds the drawing's lines and writes them)
  }
  vtkPolyData* input = this->GetInput();
  if (!input)
  {
    vtkErrorMacro("No vtkPolyData input.");
    return;
  }
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("A FileName must be specified.");
    this->SetErrorCode(vtkErrorCode::NoFileNameError);
    return;
  }
  beltrami::LineDrawingCamera camera;
  double parallel = 0.0, visibility = 0.0;
  if (!FieldValues(input, "CameraPosition", 3, camera.Position) ||
    !FieldValues(input, "ViewDirection", 3, camera.Direction) || !FieldValues(input, "ViewUp", 3, camera.Up) ||
    !FieldValues(input, "ParallelProjection", 1, &parallel))
  {
    vtkErrorMacro("The input has no camera (field arrays CameraPosition, ViewDirection, ViewUp, ParallelProjection): "
                  "write the lines of a Surface Line Drawing. Nothing written.");
    return;
  }
  camera.Parallel = parallel != 0.0;
  if (!FieldValues(input, "Visibility", 1, &visibility) || visibility == 0.0)
  {
    vtkWarningMacro("The lines were not tested for visibility (the drawing's Visibility is All lines): the parts "
                    "hidden behind the surface are written too. Set Visibility to Visible lines for print.");
  }
  vtkDataArray* types = input->GetCellData()->GetArray("LineType");
  if (input->GetNumberOfLines() > 0 && (!types || types->GetNumberOfTuples() != input->GetNumberOfCells() ||
                                         input->GetNumberOfCells() != input->GetNumberOfLines()))
  {
    vtkErrorMacro("The input's cells must be the lines of a Surface Line Drawing, with cell array LineType. "
                  "Nothing written.");
    return;
  }
  vtkNew<vtkDoubleArray> points; // (the points in double precision)
  points->SetNumberOfComponents(3);
  if (input->GetPoints())
  {
    points->DeepCopy(input->GetPoints()->GetData());
  }
  beltrami::LineDrawingInput lines;
  lines.Points = points->GetPointer(0);
  vtkDataArray* hidden = input->GetCellData()->GetArray("Hidden");
  vtkDataArray* strength = input->GetPointData()->GetArray("Strength");
  vtkNew<vtkDoubleArray> strengths;
  if (strength && strength->GetNumberOfComponents() == 1)
  {
    strengths->DeepCopy(strength);
    lines.PointStrength = strengths->GetPointer(0);
  }
  vtkCellArray* cells = input->GetLines();
  for (vtkIdType c = 0; c < cells->GetNumberOfCells(); ++c)
  {
    vtkIdType n;
    const vtkIdType* ids;
    cells->GetCellAtId(c, n, ids);
    lines.Connectivity.insert(lines.Connectivity.end(), ids, ids + n);
    lines.Offsets.push_back(static_cast<std::int64_t>(lines.Connectivity.size()));
    const double type = types->GetComponent(c, 0);
    lines.Types.push_back(static_cast<std::uint8_t>(type >= 0 && type < beltrami::HiddenStyle ? type : 0));
    lines.Hidden.push_back(hidden && hidden->GetComponent(c, 0) != 0.0);
  }
  beltrami::LineDrawingPageOptions options;
  options.PageSize = this->PageSize;
  options.Margin = this->Margin;
  options.Tolerance = this->Tolerance;
  options.DrawHidden = this->DrawHiddenLines;
  options.TaperByStrength = this->TaperByStrength;
  CopyStyles(this->LineWidths, this->LineColors, this->HiddenDash, options, true);
  const beltrami::LineDrawingPage page = beltrami::LayOutLineDrawing(lines, camera, options);
  const std::string name = this->FileName;
  const bool pdf = this->FileFormat == PDF ||
    (this->FileFormat == AUTOMATIC && name.size() >= 4 &&
      (name.compare(name.size() - 4, 4, ".pdf") == 0 || name.compare(name.size() - 4, 4, ".PDF") == 0));
  std::string error;
  if (pdf)
  {
    if (!beltrami::WriteLineDrawingPdf(page, options, name, error))
    {
      vtkErrorMacro("Cannot write '" << name << "': " << error);
      this->SetErrorCode(vtkErrorCode::CannotOpenFileError);
    }
    return;
  }
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(name.c_str(), "wb"), &std::fclose);
  const std::string svg = beltrami::LineDrawingSvg(page, options);
  if (!file || std::fwrite(svg.data(), 1, svg.size(), file.get()) != svg.size())
  {
    vtkErrorMacro("Cannot write '" << name << "'.");
    this->SetErrorCode(vtkErrorCode::CannotOpenFileError);
  }
}

void vtkLineDrawingWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n"
     << indent << "FileFormat: " << this->FileFormat << "\n"
     << indent << "PageSize: " << this->PageSize << "\n"
     << indent << "Margin: " << this->Margin << "\n"
     << indent << "Tolerance: " << this->Tolerance << "\n"
     << indent << "LineWidths:";
  for (const double w : this->LineWidths)
  {
    os << " " << w;
  }
  os << "\n" << indent << "LineColors:";
  for (const double c : this->LineColors)
  {
    os << " " << c;
  }
  os << "\n"
     << indent << "DrawHiddenLines: " << this->DrawHiddenLines << "\n"
     << indent << "HiddenDash: " << this->HiddenDash << "\n"
     << indent << "TaperByStrength: " << this->TaperByStrength << "\n"
     << indent << "Piece: " << this->Piece << " of " << this->NumberOfPieces << "\n";
}
