#include "vtkOFFReader.h"

#include "OFFFormat.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <fstream>

vtkStandardNewMacro(vtkOFFReader);

vtkOFFReader::vtkOFFReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkOFFReader::~vtkOFFReader()
{
  this->SetFileName(nullptr);
}

int vtkOFFReader::CanReadFile(const char* fileName)
{
  if (!fileName)
  {
    return 0;
  }
  // The first line that is neither blank nor a comment (CGAL's files start
  // with "# Output of a CGAL tool" lines) names the format: OFF, COFF,
  // NOFF, STOFF, 4OFF...  (Within the first 64 lines.)
  std::ifstream in(fileName, std::ios::binary);
  std::string line;
  for (int k = 0; k < 64 && std::getline(in, line); ++k)
  {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#')
    {
      continue;
    }
    const std::size_t pos = line.find("OFF", first);
    return pos != std::string::npos && pos < first + 16 ? 1 : 0;
  }
  return 0;
}

namespace
{

vtkSmartPointer<vtkDataArray> MakeDoubleArray(
  const std::vector<double>& values, int components, const char* name)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size() / components));
  std::copy(values.begin(), values.end(), array->GetPointer(0));
  return array;
}

vtkSmartPointer<vtkDataArray> MakeColorArray(const std::vector<std::uint8_t>& rgba, bool alpha)
{
  const int components = alpha ? 4 : 3;
  auto array = vtkSmartPointer<vtkUnsignedCharArray>::New();
  array->SetName("Colors");
  array->SetNumberOfComponents(components);
  const vtkIdType n = static_cast<vtkIdType>(rgba.size() / 4);
  array->SetNumberOfTuples(n);
  unsigned char* out = array->GetPointer(0);
  for (vtkIdType i = 0; i < n; ++i)
  {
    std::copy_n(&rgba[4 * i], components, out + components * i);
  }
  return array;
}

} // namespace

int vtkOFFReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize();
  this->LastError.clear();
  if (!this->FileName || !*this->FileName)
  {
    this->LastError = "no file name";
    vtkErrorMacro("A FileName must be specified.");
    this->SetErrorCode(vtkErrorCode::NoFileNameError);
    return 0;
  }
  beltrami::OFFMesh mesh;
  if (!beltrami::ReadOFFFile(this->FileName, mesh, this->LastError))
  {
    vtkErrorMacro("Cannot read OFF file '" << this->FileName << "': " << this->LastError);
    this->SetErrorCode(vtkErrorCode::FileFormatError);
    return 0;
  }
  this->SetErrorCode(vtkErrorCode::NoError);

  vtkNew<vtkPoints> points;
  points->SetData(MakeDoubleArray(mesh.Points, 3, "Points"));
  output->SetPoints(points);

  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(static_cast<vtkIdType>(mesh.FaceOffsets.size()));
  std::copy(mesh.FaceOffsets.begin(), mesh.FaceOffsets.end(), offsets->GetPointer(0));
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(static_cast<vtkIdType>(mesh.FaceIndices.size()));
  std::copy(mesh.FaceIndices.begin(), mesh.FaceIndices.end(), connectivity->GetPointer(0));
  vtkNew<vtkCellArray> polys;
  if (mesh.FaceOffsets.empty())
  {
    offsets->SetNumberOfTuples(1);
    offsets->SetValue(0, 0);
  }
  polys->SetData(offsets, connectivity);
  output->SetPolys(polys);

  if (!mesh.Normals.empty())
  {
    output->GetPointData()->SetNormals(MakeDoubleArray(mesh.Normals, 3, "Normals"));
  }
  if (!mesh.TextureCoords.empty())
  {
    output->GetPointData()->SetTCoords(MakeDoubleArray(mesh.TextureCoords, 2, "TCoords"));
  }
  if (!mesh.PointColors.empty())
  {
    output->GetPointData()->SetScalars(MakeColorArray(mesh.PointColors, mesh.HasPointAlpha));
  }
  if (!mesh.FaceColors.empty())
  {
    output->GetCellData()->SetScalars(MakeColorArray(mesh.FaceColors, mesh.HasFaceAlpha));
  }
  return 1;
}

void vtkOFFReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
}
