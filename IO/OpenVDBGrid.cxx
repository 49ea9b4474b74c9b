#include "OpenVDBGrid.h"

#include "Support/HelperProcess.h"

#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkStringArray.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace beltrami
{

namespace
{

/// Runs the helper process on the file: its bytes in, checked.
std::vector<char> RunHelper(const std::vector<std::string>& arguments, double maximumBytes, double timeout)
{
  const std::string helper = HelperPathNextTo(
    reinterpret_cast<const void*>(&RunHelper), "beltrami-vdb-read", "BELTRAMI_VDB_READ");
  HelperProcessResult run = RunHelperProcess(helper, arguments, {}, maximumBytes, timeout);
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
} // namespace

VDBGrid ReadVDBGrid(const char* fileName, const std::string& gridName, std::int64_t maximumVoxels,
  double timeout, bool activeOnly)
{
  std::vector<std::string> arguments = { fileName, gridName, std::to_string(maximumVoxels) };
  if (activeOnly)
  {
    arguments.emplace_back("active");
  }
  // Values (at most 3 doubles) and, for active voxels, 3 int32 coordinates.
  const double maximumBytes = 1e7 + static_cast<double>(maximumVoxels) * (3 * sizeof(double) + 12);
  const std::vector<char> bytes = RunHelper(arguments, maximumBytes, timeout);
  ByteReader c(bytes, "OpenVDB helper");
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
  VDBGrid g;
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
  if ((g.Components != 1 && g.Components != 3) || (!activeOnly && voxels > static_cast<double>(maximumVoxels)))
  {
    throw std::runtime_error("malformed answer of the OpenVDB helper");
  }
  const std::size_t valueSize = static_cast<std::size_t>(g.Components) * (g.Double ? sizeof(double) : sizeof(float));
  if (activeOnly)
  {
    const std::int64_t n = c.Get<std::int64_t>();
    if (n < 0 || n > maximumVoxels ||
      static_cast<double>(c.Left()) != static_cast<double>(n) * (12.0 + static_cast<double>(valueSize)))
    {
      throw std::runtime_error("malformed answer of the OpenVDB helper");
    }
    g.Coordinates.resize(3 * static_cast<std::size_t>(n));
    c.Take(g.Coordinates.data(), g.Coordinates.size() * sizeof(std::int32_t));
    g.Values.resize(static_cast<std::size_t>(n) * valueSize);
    c.Take(g.Values.data(), g.Values.size());
    return g;
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

vtkSmartPointer<vtkDataArray> NewVDBValueArray(const VDBGrid& grid)
{
  const std::size_t valueSize = static_cast<std::size_t>(grid.Components) * (grid.Double ? sizeof(double) : sizeof(float));
  if (grid.Values.empty() || valueSize == 0)
  {
    return nullptr;
  }
  vtkSmartPointer<vtkDataArray> a;
  if (grid.Double)
  {
    a = vtkSmartPointer<vtkDoubleArray>::New();
  }
  else
  {
    a = vtkSmartPointer<vtkFloatArray>::New();
  }
  a->SetName(grid.Name.empty() ? "values" : grid.Name.c_str());
  a->SetNumberOfComponents(grid.Components);
  a->SetNumberOfTuples(static_cast<vtkIdType>(grid.Values.size() / valueSize));
  std::memcpy(a->GetVoidPointer(0), grid.Values.data(), grid.Values.size());
  return a;
}

void AddVDBFieldData(const VDBGrid& grid, vtkFieldData* fieldData)
{
  vtkNew<vtkStringArray> names;
  names->SetName("GridNames");
  for (const std::string& s : grid.Names)
  {
    names->InsertNextValue(s);
  }
  fieldData->AddArray(names);
  vtkNew<vtkIdTypeArray> active;
  active->SetName("ActiveVoxelCount");
  active->InsertNextValue(static_cast<vtkIdType>(grid.Active));
  fieldData->AddArray(active);
}

} // namespace beltrami
