#include "vtkOpenVDBReader.h"

#include "OpenVDBGrid.h"

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

class vtkOpenVDBReader::vtkInternals
{
public:
  bool Valid = false;
  beltrami::VDBGrid Grid;
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
      beltrami::ReadVDBGrid(this->FileName, this->GridName, this->MaximumNumberOfVoxels, this->Timeout, false);
    this->Internals->Valid = true;
    const beltrami::VDBGrid& g = this->Internals->Grid;
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
    beltrami::VDBGrid g;
    if (this->Internals->Valid)
    {
      g = std::move(this->Internals->Grid);
      this->Internals->Valid = false;
    }
    else
    {
      g = beltrami::ReadVDBGrid(this->FileName, this->GridName, this->MaximumNumberOfVoxels, this->Timeout, false);
    }
    output->SetExtent(const_cast<int*>(g.Extent));
    output->SetOrigin(g.Origin);
    output->SetSpacing(g.Spacing);
    const std::string name = g.Name.empty() ? "values" : g.Name;
    if (output->GetNumberOfPoints() > 0)
    {
      output->GetPointData()->SetScalars(beltrami::NewVDBValueArray(g));
    }
    else
    {
      vtkWarningMacro("The grid '" << name << "' has no active voxels: the image is empty.");
    }
    beltrami::AddVDBFieldData(g, output->GetFieldData());
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
