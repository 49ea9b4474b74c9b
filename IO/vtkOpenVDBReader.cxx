#include "vtkOpenVDBReader.h"

#include "Core/HelperProcess.h"

#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringArray.h>
#include <vtksys/SystemTools.hxx>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>


vtkStandardNewMacro(vtkOpenVDBReader);

int vtkOpenVDBReader::CanReadFile(const char* fileName)
{
  std::ifstream in(fileName ? fileName : "", std::ios::binary);
  char magic[8] = { 0 };
  // OpenVDB files start with the 64-bit magic number 0x56444220 ("VDB ").
  return in.read(magic, 8) && std::memcmp(magic, "\x20\x42\x44\x56", 4) == 0 ? 1 : 0;
}

namespace
{
/// What beltrami-vdb-read reports (see IO/Tools/beltrami_vdb_read.cxx).
struct GridData
{
  std::vector<std::string> Names;
  std::string Name;
  int Components = 0;
  bool Double = false;
  int Extent[6] = { 0, -1, 0, -1, 0, -1 };
  double Origin[3] = { 0, 0, 0 };
  double Spacing[3] = { 1, 1, 1 };
  std::int64_t Active = 0;
  std::vector<char> Values;
};

/// Runs the helper process on the file: its bytes in, checked.
std::vector<char> RunHelper(const std::vector<std::string>& arguments, double maximumBytes, double timeout)
{
  const std::string helper = beltrami::HelperPathNextTo(
    reinterpret_cast<const void*>(&RunHelper), "beltrami-vdb-read", "BELTRAMI_VDB_READ");
  beltrami::HelperProcessResult run = beltrami::RunHelperProcess(helper, arguments, {}, maximumBytes, timeout);
  if (run.TimedOut)
  {
    throw std::runtime_error("the OpenVDB parser did not finish within the timeout: the file is damaged or too large");
  }
  if (run.Overflow)
  {
    throw std::runtime_error("the OpenVDB helper sent more data than the grid can hold");
  }
  if (run.Signal)
  {
    throw std::runtime_error("the file is damaged: the OpenVDB parser crashed on it (signal " +
      std::to_string(run.Signal) + ")");
  }
  return std::move(run.Output);
}

/// The selected grid's layout and values, every size checked.
GridData ReadGrid(const char* fileName, const std::string& gridName, vtkIdType maximumVoxels, double timeout)
{
  const std::vector<std::string> arguments = { fileName, gridName, std::to_string(maximumVoxels) };
  const double maximumBytes = 1e7 + static_cast<double>(maximumVoxels) * 3 * sizeof(double);
  const std::vector<char> bytes = RunHelper(arguments, maximumBytes, timeout);
  beltrami::ByteReader c(bytes, "OpenVDB helper");
  char magic[5];
  c.Take(magic, 5);
  if (std::memcmp(magic, "BVDB1", 5) != 0)
  {
    throw std::runtime_error("malformed answer of the OpenVDB helper");
  }
  if (c.Get<std::int32_t>() != 0)
  {
    throw std::runtime_error(c.String());
  }
  GridData g;
  const std::uint32_t count = c.Get<std::uint32_t>();
  for (std::uint32_t k = 0; k < count; ++k)
  {
    g.Names.push_back(c.String());
  }
  g.Name = c.String();
  g.Components = c.Get<std::int32_t>();
  g.Double = c.Get<std::int32_t>() != 0;
  for (int a = 0; a < 6; ++a)
  {
    g.Extent[a] = c.Get<std::int32_t>();
  }
  double voxels = 1.0;
  for (int a = 0; a < 3; ++a)
  {
    voxels *= std::max(0.0, static_cast<double>(g.Extent[2 * a + 1]) - g.Extent[2 * a] + 1.0);
  }
  c.Take(g.Origin, sizeof(g.Origin));
  c.Take(g.Spacing, sizeof(g.Spacing));
  g.Active = c.Get<std::int64_t>();
  if ((g.Components != 1 && g.Components != 3) || voxels > static_cast<double>(maximumVoxels))
  {
    throw std::runtime_error("malformed answer of the OpenVDB helper");
  }
  const double expected = voxels * g.Components * (g.Double ? sizeof(double) : sizeof(float));
  if (static_cast<double>(c.Left()) != expected)
  {
    throw std::runtime_error("the OpenVDB helper sent " + std::to_string(c.Left()) + " bytes of values for " +
      std::to_string(static_cast<std::int64_t>(expected)));
  }
  g.Values.assign(bytes.begin() + static_cast<std::ptrdiff_t>(c.Offset()), bytes.end());
  return g;
}
} // namespace

class vtkOpenVDBReader::vtkInternals
{
public:
  bool Valid = false;
  GridData Grid;
};

vtkOpenVDBReader::vtkOpenVDBReader()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(0);
}

vtkOpenVDBReader::~vtkOpenVDBReader()
{
  this->SetFileName(nullptr);
  delete this->Internals;
}

int vtkOpenVDBReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (!this->FileName || !vtksys::SystemTools::FileExists(this->FileName, true))
  {
    vtkErrorMacro("Cannot read '" << (this->FileName ? this->FileName : "") << "': no such file.");
    return 0;
  }
  this->Internals->Valid = false;
  try
  {
    this->Internals->Grid =
      ReadGrid(this->FileName, this->GridName, this->MaximumNumberOfVoxels, this->Timeout);
    this->Internals->Valid = true;
    const GridData& g = this->Internals->Grid;
    outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), g.Extent, 6);
    outInfo->Set(vtkDataObject::ORIGIN(), g.Origin, 3);
    outInfo->Set(vtkDataObject::SPACING(), g.Spacing, 3);
    vtkDataObject::SetPointDataActiveScalarInfo(outInfo, g.Double ? VTK_DOUBLE : VTK_FLOAT, g.Components);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro("Cannot read '" << this->FileName << "': " << e.what() << ".");
    return 0;
  }
  return 1;
}

int vtkOpenVDBReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector);
  output->Initialize();
  try
  {
    // The grid RequestInformation read (or a new read if none is kept).
    GridData g;
    if (this->Internals->Valid)
    {
      g = std::move(this->Internals->Grid);
      this->Internals->Valid = false;
    }
    else
    {
      g = ReadGrid(this->FileName, this->GridName, this->MaximumNumberOfVoxels, this->Timeout);
    }
    output->SetExtent(const_cast<int*>(g.Extent));
    output->SetOrigin(g.Origin);
    output->SetSpacing(g.Spacing);
    const vtkIdType n = output->GetNumberOfPoints();
    const std::string name = g.Name.empty() ? "values" : g.Name;
    if (n > 0)
    {
      vtkSmartPointer<vtkDataArray> a;
      if (g.Double)
      {
        a = vtkSmartPointer<vtkDoubleArray>::New();
      }
      else
      {
        a = vtkSmartPointer<vtkFloatArray>::New();
      }
      a->SetName(name.c_str());
      a->SetNumberOfComponents(g.Components);
      a->SetNumberOfTuples(n);
      std::memcpy(a->GetVoidPointer(0), g.Values.data(), g.Values.size());
      output->GetPointData()->SetScalars(a);
    }
    else
    {
      vtkWarningMacro("The grid '" << name << "' has no active voxels: the image is empty.");
    }
    vtkNew<vtkStringArray> names;
    names->SetName("GridNames");
    for (const std::string& s : g.Names)
    {
      names->InsertNextValue(s);
    }
    output->GetFieldData()->AddArray(names);
    vtkNew<vtkIdTypeArray> active;
    active->SetName("ActiveVoxelCount");
    active->InsertNextValue(static_cast<vtkIdType>(g.Active));
    output->GetFieldData()->AddArray(active);
  }
  catch (const std::exception& e)
  {
    output->Initialize();
    vtkErrorMacro("Cannot read '" << this->FileName << "': " << e.what() << ".");
    return 0;
  }
  return 1;
}

void vtkOpenVDBReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "GridName: " << this->GridName << "\n";
  os << indent << "MaximumNumberOfVoxels: " << this->MaximumNumberOfVoxels << "\n";
  os << indent << "Timeout: " << this->Timeout << "\n";
}
