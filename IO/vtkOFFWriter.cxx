#include "vtkOFFWriter.h"

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkErrorCode.h>
#include <vtkInformation.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <cstdio>
#include <memory>

vtkStandardNewMacro(vtkOFFWriter);

vtkOFFWriter::vtkOFFWriter()
{
  this->SetColorArrayName("Colors");
}

vtkOFFWriter::~vtkOFFWriter()
{
  this->SetFileName(nullptr);
  this->SetColorArrayName(nullptr);
}

vtkPolyData* vtkOFFWriter::GetInput()
{
  return vtkPolyData::SafeDownCast(this->Superclass::GetInput());
}

int vtkOFFWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

void vtkOFFWriter::WriteData()
{
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
  if (input->GetNumberOfVerts() + input->GetNumberOfLines() > 0)
  {
    vtkWarningMacro("OFF stores polygons only: " << input->GetNumberOfVerts() << " vertex and "
                                                 << input->GetNumberOfLines()
                                                 << " line cells are not written.");
  }
  vtkUnsignedCharArray* colors = nullptr;
  if (this->WriteColors && this->ColorArrayName)
  {
    colors = vtkUnsignedCharArray::SafeDownCast(
      input->GetPointData()->GetArray(this->ColorArrayName));
    if (colors && colors->GetNumberOfComponents() != 3 && colors->GetNumberOfComponents() != 4)
    {
      colors = nullptr;
    }
  }

  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(this->FileName, "wb"), &std::fclose);
  if (!file)
  {
    vtkErrorMacro("Cannot open '" << this->FileName << "' for writing.");
    this->SetErrorCode(vtkErrorCode::CannotOpenFileError);
    return;
  }
  FILE* f = file.get();
  const vtkIdType numPoints = input->GetNumberOfPoints();
  vtkIdType numFaces = input->GetNumberOfPolys();
  {
    auto strips = vtk::TakeSmartPointer(input->GetStrips()->NewIterator());
    for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell())
    {
      vtkIdType n;
      const vtkIdType* ids;
      strips->GetCurrentCell(n, ids);
      numFaces += n > 2 ? n - 2 : 0;
    }
  }
  std::fprintf(f, "%s\n%lld %lld 0\n", colors ? "COFF" : "OFF", static_cast<long long>(numPoints),
    static_cast<long long>(numFaces));
  double p[3];
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    input->GetPoint(i, p);
    std::fprintf(f, "%.17g %.17g %.17g", p[0], p[1], p[2]);
    if (colors)
    {
      const int nc = colors->GetNumberOfComponents();
      for (int c = 0; c < nc; ++c)
      {
        std::fprintf(f, " %d", static_cast<int>(colors->GetValue(nc * i + c)));
      }
    }
    std::fputc('\n', f);
  }
  auto polys = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
  for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    polys->GetCurrentCell(n, ids);
    std::fprintf(f, "%lld", static_cast<long long>(n));
    for (vtkIdType k = 0; k < n; ++k)
    {
      std::fprintf(f, " %lld", static_cast<long long>(ids[k]));
    }
    std::fputc('\n', f);
  }
  auto strips = vtk::TakeSmartPointer(input->GetStrips()->NewIterator());
  for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    strips->GetCurrentCell(n, ids);
    for (vtkIdType k = 0; k + 2 < n; ++k)
    {
      const bool even = k % 2 == 0;
      std::fprintf(f, "3 %lld %lld %lld\n", static_cast<long long>(ids[even ? k : k + 1]),
        static_cast<long long>(ids[even ? k + 1 : k]), static_cast<long long>(ids[k + 2]));
    }
  }
  if (std::ferror(f))
  {
    vtkErrorMacro("Error while writing '" << this->FileName << "'.");
    this->SetErrorCode(vtkErrorCode::OutOfDiskSpaceError);
  }
}

void vtkOFFWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "WriteColors: " << this->WriteColors << "\n";
  os << indent << "ColorArrayName: " << (this->ColorArrayName ? this->ColorArrayName : "(none)")
     << "\n";
}
