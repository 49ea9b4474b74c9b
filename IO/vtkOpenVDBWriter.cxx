#include "vtkOpenVDBWriter.h"

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>

#include <openvdb/openvdb.h>

#include <cmath>

vtkStandardNewMacro(vtkOpenVDBWriter);

vtkOpenVDBWriter::vtkOpenVDBWriter()
{
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

vtkOpenVDBWriter::~vtkOpenVDBWriter()
{
  this->SetFileName(nullptr);
}

vtkImageData* vtkOpenVDBWriter::GetInput()
{
  return vtkImageData::SafeDownCast(this->Superclass::GetInput());
}

int vtkOpenVDBWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

namespace
{
template <typename GridT, int NC>
typename GridT::Ptr MakeGrid(vtkImageData* image, vtkDataArray* array, bool sparse, double background)
{
  using V = typename GridT::ValueType;
  V backgroundValue;
  if constexpr (NC == 1)
  {
    backgroundValue = static_cast<V>(background);
  }
  else
  {
    using S = typename V::value_type;
    backgroundValue = V(static_cast<S>(background));
  }
  typename GridT::Ptr grid = GridT::create(backgroundValue);
  auto accessor = grid->getAccessor();
  int ext[6];
  image->GetExtent(ext);
  vtkIdType id = 0;
  for (int k = ext[4]; k <= ext[5]; ++k)
  {
    for (int j = ext[2]; j <= ext[3]; ++j)
    {
      for (int i = ext[0]; i <= ext[1]; ++i, ++id)
      {
        V value;
        if constexpr (NC == 1)
        {
          value = static_cast<V>(array->GetComponent(id, 0));
        }
        else
        {
          using S = typename V::value_type;
          value = V(static_cast<S>(array->GetComponent(id, 0)), static_cast<S>(array->GetComponent(id, 1)),
            static_cast<S>(array->GetComponent(id, 2)));
        }
        if (!sparse || value != backgroundValue)
        {
          accessor.setValueOn(openvdb::Coord(i, j, k), value);
        }
      }
    }
  }
  return grid;
}
} // namespace

void vtkOpenVDBWriter::WriteData()
{
  vtkImageData* input = this->GetInput();
  if (!input || !this->FileName || !*this->FileName)
  {
    vtkErrorMacro("A vtkImageData input and a file name are needed.");
    return;
  }
  vtkDataArray* array = this->GetInputArrayToProcess(0, input);
  if (!array || array->GetNumberOfTuples() != input->GetNumberOfPoints() || input->GetNumberOfPoints() == 0)
  {
    vtkErrorMacro("No point array to write (input array 0), or an empty image.");
    return;
  }
  const int nc = array->GetNumberOfComponents();
  if (nc != 1 && nc != 3)
  {
    vtkErrorMacro("OpenVDB grids hold scalars or 3-vectors; '" << (array->GetName() ? array->GetName() : "")
                                                               << "' has " << nc << " components.");
    return;
  }
  try
  {
    openvdb::initialize();
    const bool dbl = array->GetDataType() == VTK_DOUBLE;
    openvdb::GridBase::Ptr grid;
    if (nc == 1)
    {
      grid = dbl ? openvdb::GridBase::Ptr(MakeGrid<openvdb::DoubleGrid, 1>(input, array, this->SparseOutput, this->BackgroundValue))
                 : openvdb::GridBase::Ptr(MakeGrid<openvdb::FloatGrid, 1>(input, array, this->SparseOutput, this->BackgroundValue));
    }
    else
    {
      grid = dbl ? openvdb::GridBase::Ptr(MakeGrid<openvdb::Vec3DGrid, 3>(input, array, this->SparseOutput, this->BackgroundValue))
                 : openvdb::GridBase::Ptr(MakeGrid<openvdb::Vec3SGrid, 3>(input, array, this->SparseOutput, this->BackgroundValue));
    }
    const double* spacing = input->GetSpacing();
    const double* origin = input->GetOrigin();
    openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(1.0);
    transform->postScale(openvdb::Vec3d(spacing[0], spacing[1], spacing[2]));
    transform->postTranslate(openvdb::Vec3d(origin[0], origin[1], origin[2]));
    grid->setTransform(transform);
    grid->setName(!this->GridName.empty() ? this->GridName : (array->GetName() ? array->GetName() : "values"));
    openvdb::io::File file(this->FileName);
    file.write({ grid });
    file.close();
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro("Writing '" << this->FileName << "' failed: " << e.what());
  }
}

void vtkOpenVDBWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "GridName: " << this->GridName << "\n";
  os << indent << "SparseOutput: " << this->SparseOutput << "\n";
  os << indent << "BackgroundValue: " << this->BackgroundValue << "\n";
}
