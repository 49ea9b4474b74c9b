#include "vtkOpenVDBActiveVoxelReader.h"

#include "OpenVDBGrid.h"
#include "vtkOpenVDBReader.h"

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtksys/SystemTools.hxx>

#include <cstring>
#include <functional>
#include <stdexcept>
#include <unordered_map>

vtkStandardNewMacro(vtkOpenVDBActiveVoxelReader);

namespace
{
/// (i, j, k) of an index grid as a hash key.
struct Coordinate
{
  std::int32_t I, J, K;
  bool operator==(const Coordinate& o) const { return I == o.I && J == o.J && K == o.K; }
};
struct CoordinateHash
{
  std::size_t operator()(const Coordinate& c) const
  {
    std::uint64_t h = static_cast<std::uint32_t>(c.I);
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint32_t>(c.J);
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint32_t>(c.K);
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
} // namespace

int vtkOpenVDBActiveVoxelReader::CanReadFile(const char* fileName)
{
  return vtkOpenVDBReader::CanReadFile(fileName);
}

vtkOpenVDBActiveVoxelReader::vtkOpenVDBActiveVoxelReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkOpenVDBActiveVoxelReader::~vtkOpenVDBActiveVoxelReader()
{
  this->SetFileName(nullptr);
}

int vtkOpenVDBActiveVoxelReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  output->Initialize();
  if (!this->FileName || !vtksys::SystemTools::FileExists(this->FileName, true))
  {
    vtkErrorMacro("Cannot read '" << (this->FileName ? this->FileName : "") << "': no such file.");
    return 0;
  }
  beltrami::VDBGrid g;
  try
  {
    g = beltrami::ReadVDBGrid(this->FileName, this->GridName, this->MaximumNumberOfVoxels, this->Timeout, true);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro("Cannot read '" << this->FileName << "': " << e.what() << ".");
    return 0;
  }
  const vtkIdType n = static_cast<vtkIdType>(g.Coordinates.size() / 3);
  const std::string name = g.Name.empty() ? "values" : g.Name;

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  std::unordered_map<Coordinate, vtkIdType, CoordinateHash> ids;
  ids.reserve(static_cast<std::size_t>(n));
  for (vtkIdType p = 0; p < n; ++p)
  {
    const std::int32_t* c = &g.Coordinates[3 * p];
    points->SetPoint(p, g.Origin[0] + c[0] * g.Spacing[0], g.Origin[1] + c[1] * g.Spacing[1],
      g.Origin[2] + c[2] * g.Spacing[2]);
    ids.emplace(Coordinate{ c[0], c[1], c[2] }, p);
  }
  output->SetPoints(points);

  // A VTK_VOXEL (corners numbered x + 2y + 4z) wherever all eight are active.
  vtkNew<vtkCellArray> cells;
  for (vtkIdType p = 0; p < n; ++p)
  {
    const std::int32_t* c = &g.Coordinates[3 * p];
    vtkIdType corner[8];
    bool complete = true;
    for (int k = 0; k < 8 && complete; ++k)
    {
      const auto it = ids.find(Coordinate{ c[0] + (k & 1), c[1] + ((k >> 1) & 1), c[2] + ((k >> 2) & 1) });
      complete = it != ids.end();
      corner[k] = complete ? it->second : -1;
    }
    if (complete)
    {
      cells->InsertNextCell(8, corner);
    }
  }
  output->SetCells(VTK_VOXEL, cells);

  if (auto values = beltrami::NewVDBValueArray(g))
  {
    output->GetPointData()->SetScalars(values);
  }
  else
  {
    vtkWarningMacro("The grid '" << name << "' has no active voxels: the output is empty.");
  }
  beltrami::AddVDBFieldData(g, output->GetFieldData());
  return 1;
}

void vtkOpenVDBActiveVoxelReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "GridName: " << this->GridName << "\n";
  os << indent << "MaximumNumberOfVoxels: " << this->MaximumNumberOfVoxels << "\n";
  os << indent << "Timeout: " << this->Timeout << "\n";
}
