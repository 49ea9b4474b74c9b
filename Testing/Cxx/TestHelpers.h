// Helpers for the VTK-level tests.
#pragma once

#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkObject.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <string>
#include <vector>

namespace beltrami
{
namespace test
{

/// Collects the warnings and errors an object emits (instead of printing them).
class MessageCollector : public vtkCommand
{
public:
  static MessageCollector* New() { return new MessageCollector; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    const std::string text = data ? static_cast<const char*>(data) : "";
    (event == vtkCommand::ErrorEvent ? Errors : Warnings).push_back(text);
  }
  void Watch(vtkObject* object)
  {
    object->AddObserver(vtkCommand::WarningEvent, this);
    object->AddObserver(vtkCommand::ErrorEvent, this);
  }
  bool WarnedAbout(const std::string& needle) const
  {
    for (const auto& w : Warnings)
    {
      if (w.find(needle) != std::string::npos)
      {
        return true;
      }
    }
    return false;
  }
  std::vector<std::string> Warnings, Errors;
};

inline double Value(vtkPolyData* pd, const char* name, vtkIdType i, int component = 0)
{
  return pd->GetPointData()->GetArray(name)->GetComponent(i, component);
}

inline std::string DataFile(const std::string& name)
{
  return std::string(BELTRAMI_TEST_DATA_DIR) + "/" + name;
}

} // namespace test
} // namespace beltrami
