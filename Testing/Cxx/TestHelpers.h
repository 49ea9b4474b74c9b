// Helpers for the VTK-level tests.
#pragma once

#include "vtkOFFReader.h"

#include <vtkCellArray.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkObject.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <vtkCellArrayIterator.h>
#include <vtkDataSet.h>
#include <vtkDoubleArray.h>
#include <vtkMath.h>

#include <cmath>
#include <functional>
#include <random>
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

/// Runs `filter` on `input` (its messages to `messages` when given) and
/// returns a shallow copy of its output.
template <typename Output = vtkPolyData, typename Filter>
vtkSmartPointer<Output> RunOn(Filter* filter, vtkDataObject* input, MessageCollector* messages = nullptr)
{
  if (messages)
  {
    messages->Watch(filter);
  }
  filter->SetInputData(input);
  filter->Update();
  auto out = vtkSmartPointer<Output>::New();
  out->ShallowCopy(filter->GetOutput());
  return out;
}

/// A point array `name` added to `data`: f(x) at every point x, plus Gaussian
/// noise of standard deviation `sigma` (seeded: the same values every run).
inline vtkSmartPointer<vtkDoubleArray> AddPointField(vtkDataSet* data, const char* name,
  const std::function<double(const double* x)>& f, double sigma = 0.0, unsigned seed = 1)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfTuples(data->GetNumberOfPoints());
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma > 0.0 ? sigma : 1.0);
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
  {
    array->SetValue(i, f(data->GetPoint(i)) + (sigma > 0.0 ? noise(rng) : 0.0));
  }
  data->GetPointData()->AddArray(array);
  return array;
}

/// A mesh of Testing/Data read by vtkOFFReader.
inline vtkSmartPointer<vtkPolyData> ReadOFF(const std::string& name)
{
  vtkSmartPointer<vtkOFFReader> reader = vtkSmartPointer<vtkOFFReader>::New();
  reader->SetFileName(DataFile(name).c_str());
  reader->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(reader->GetOutput());
  return out;
}

/// The mean length of the edges of the triangles (each interior edge twice).
inline double MeanEdgeLength(vtkPolyData* pd)
{
  double sum = 0.0;
  vtkIdType count = 0;
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  auto it = vtkSmartPointer<vtkCellArrayIterator>::Take(pd->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    it->GetCurrentCell(n, ids);
    for (vtkIdType k = 0; k < n; ++k)
    {
      double a[3], b[3];
      pd->GetPoint(ids[k], a);
      pd->GetPoint(ids[(k + 1) % n], b);
      sum += std::sqrt(vtkMath::Distance2BetweenPoints(a, b));
      ++count;
    }
  }
  return count ? sum / count : 0.0;
}

} // namespace test
} // namespace beltrami
