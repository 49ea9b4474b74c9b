// vtkBeltramiSurface, arrays: the point arrays a filter selects (input
// arrays to process, masks) and the output arrays it creates.
#include "vtkBeltramiSurface.h"

#include "Support/LargeBuffer.h"

#include <vtkAlgorithm.h>
#include <vtkAOSDataArrayTemplate.h>
#include <vtkCellData.h>
#include <vtkInformation.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

using beltrami::Index;

vtkDataArray* vtkBeltramiSurface::SelectedPointArray(
  vtkAlgorithm* owner, int idx, int components, const char* what, std::string& error) const
{
  return SelectedPointArray(owner, InputData, idx, components, what, error);
}

namespace
{

/// The point or cell array selected as input array `idx` of `owner` (see
/// SelectedPointArray).
vtkDataArray* SelectedArray(vtkAlgorithm* owner, vtkDataSet* input, int idx, bool cells, int components,
  const char* what, std::string& error)
{
  vtkInformation* info = owner->GetInputArrayInformation(idx);
  const char* name =
    info && info->Has(vtkDataObject::FIELD_NAME()) ? info->Get(vtkDataObject::FIELD_NAME()) : nullptr;
  if (!name || !*name || !input)
  {
    return nullptr;
  }
  vtkFieldData* own = cells ? static_cast<vtkFieldData*>(input->GetCellData()) : input->GetPointData();
  vtkFieldData* other = cells ? static_cast<vtkFieldData*>(input->GetPointData()) : input->GetCellData();
  const char* kind = cells ? " cell array '" : " point array '";
  vtkDataArray* a = own->GetArray(name);
  if (!a && std::string(name) == "None") // ParaView's none_string of an array selection
  {
    return nullptr;
  }
  if (!a)
  {
    // A warning, not an error: these arrays are optional, and pvpython's
    // Filter(Input=x) chooses defaults from the active source before x is set,
    // so a stale name can reach the filter.
    vtkWarningWithObjectMacro(owner, << "The " << what << kind << name << "' does not exist in the input"
                                     << (other->GetAbstractArray(name)
                                            ? (cells ? " (it is a point array; cell data are needed)"
                                                     : " (it is a cell array; point data are needed)")
                                            : "")
                                     << "; it is ignored.");
    return nullptr;
  }
  if (components > 0 && a->GetNumberOfComponents() != components)
  {
    error = std::string("The ") + what + kind + name + "' needs " + std::to_string(components) +
      (components == 1 ? " component." : " components.");
    return nullptr;
  }
  return a;
}

} // namespace

vtkDataArray* vtkBeltramiSurface::SelectedPointArray(vtkAlgorithm* owner, vtkDataSet* input, int idx,
  int components, const char* what, std::string& error)
{
  return SelectedArray(owner, input, idx, false, components, what, error);
}

vtkDataArray* vtkBeltramiSurface::SelectedCellArray(vtkAlgorithm* owner, vtkDataSet* input, int idx,
  int components, const char* what, std::string& error)
{
  return SelectedArray(owner, input, idx, true, components, what, error);
}

std::vector<std::uint8_t> vtkBeltramiSurface::SelectedPointMask(
  vtkAlgorithm* owner, vtkDataSet* input, int idx, const char* what, std::string& error)
{
  std::vector<std::uint8_t> mask;
  if (vtkDataArray* a = SelectedPointArray(owner, input, idx, 1, what, error))
  {
    mask.resize(static_cast<std::size_t>(a->GetNumberOfTuples()));
    vtkIdType nan = 0;
    for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
    {
      const double value = a->GetComponent(i, 0);
      mask[i] = value != 0.0;
      nan += std::isnan(value) ? 1 : 0;
    }
    if (nan > 0)
    {
      vtkWarningWithObjectMacro(owner, << nan << " values of the " << what << " array are NaN: taken as marked "
                                       << "(not zero).");
    }
  }
  return mask;
}

namespace
{
template <typename T>
void AllocateLarge(vtkDataArray* array, vtkIdType values)
{
  auto* aos = vtkAOSDataArrayTemplate<T>::SafeDownCast(array);
  T* memory = aos ? beltrami::LargeBufferAllocator<T>().allocate(static_cast<std::size_t>(values)) : nullptr;
  if (!memory)
  {
    array->SetNumberOfValues(values);
    return;
  }
  aos->SetArray(memory, values, /*save=*/0, vtkAbstractArray::VTK_DATA_ARRAY_USER_DEFINED);
  aos->SetArrayFreeFunction(&beltrami::FreeLargeBlock); // back to the block cache
}
} // namespace

vtkSmartPointer<vtkDataArray> vtkBeltramiSurface::NewArray(
  int dataType, const char* name, int components, vtkIdType tuples)
{
  auto array = vtk::TakeSmartPointer(vtkDataArray::CreateDataArray(dataType));
  array->SetName(name);
  array->SetNumberOfComponents(components);
  const vtkIdType values = static_cast<vtkIdType>(components) * std::max<vtkIdType>(tuples, 0);
  if (values * array->GetDataTypeSize() < static_cast<vtkIdType>(beltrami::LargeBufferAllocator<char>::HugePage))
  {
    array->SetNumberOfTuples(tuples);
    return array;
  }
  switch (dataType)
  {
    vtkTemplateMacro(AllocateLarge<VTK_TT>(array, values));
    default:
      array->SetNumberOfTuples(tuples);
  }
  return array;
}

