// Beltrami IO (private): one grid of an OpenVDB file, as parsed by the
// helper process beltrami-vdb-read (IO/Tools/beltrami_vdb_read.cxx), every
// size it answers checked.  Shared by vtkOpenVDBReader (dense over the
// active bounding box) and vtkOpenVDBActiveVoxelReader (active voxels only).
#pragma once

#include <vtkSmartPointer.h>
#include <vtkType.h>

#include <cstdint>
#include <string>
#include <vector>

class vtkDataArray;
class vtkFieldData;

namespace beltrami
{

struct VDBGrid
{
  std::vector<std::string> Names; ///< all grids of the file
  std::string Name;               ///< the grid read
  int Components = 0;             ///< 1 or 3
  bool Double = false;            ///< double (else float) values
  int Extent[6] = { 0, -1, 0, -1, 0, -1 }; ///< the active bounding box (index space)
  double Origin[3] = { 0, 0, 0 };
  double Spacing[3] = { 1, 1, 1 };
  std::int64_t Active = 0;        ///< active voxel count
  std::vector<char> Values;       ///< dense: over Extent, x fastest; active: per voxel of Coordinates
  std::vector<std::int32_t> Coordinates; ///< active only: (i, j, k) per active voxel
};

/// Reads grid `gridName` (empty: the first) of the file in the helper.
/// activeOnly: the active voxels and their coordinates, never densified (at
/// most maximumVoxels of them); else the values densely over the active
/// bounding box (at most maximumVoxels).  Throws std::runtime_error with a
/// message for the user.
VDBGrid ReadVDBGrid(const char* fileName, const std::string& gridName, std::int64_t maximumVoxels,
  double timeout, bool activeOnly);

/// The grid's values as a VTK array named as the grid (float or double,
/// Components per tuple); nullptr when it has none.
vtkSmartPointer<vtkDataArray> NewVDBValueArray(const VDBGrid& grid);

/// Field data of both readers: GridNames and ActiveVoxelCount.
void AddVDBFieldData(const VDBGrid& grid, vtkFieldData* fieldData);

} // namespace beltrami
