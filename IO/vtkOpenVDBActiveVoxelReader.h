/**
 * @class   vtkOpenVDBActiveVoxelReader
 * @brief   Reads the active voxels of an OpenVDB (.vdb) grid, without
 *          densifying it, as a vtkUnstructuredGrid of voxels.
 *
 * Sparse grids (fog volumes, narrow-band level sets) hold a few active
 * voxels in a huge index space; vtkOpenVDBReader fills their whole active
 * bounding box.  This reader outputs one point per active voxel (at its
 * world position: origin + index * spacing, as vtkOpenVDBReader) with the
 * grid's values as a point array named as the grid, and one VTK_VOXEL cell
 * per cell of the index grid whose eight corners are all active - so
 * memory follows the active count, the output renders as a volume, and
 * vtkTetrahedralBeltramiDenoising smooths it on its voxels (split into the
 * Kuhn tetrahedra of the 3D image path).  Active tiles (blocks stored as one
 * value) are expanded into their voxels.  Field data: GridNames,
 * ActiveVoxelCount.
 *
 * The file is parsed in the helper process beltrami-vdb-read, as for
 * vtkOpenVDBReader (Timeout, damaged files are errors, never crashes); more
 * than MaximumNumberOfVoxels active voxels (default 2^28) are refused before
 * anything is allocated.
 */
#ifndef vtkOpenVDBActiveVoxelReader_h
#define vtkOpenVDBActiveVoxelReader_h

#include "BeltramiIOModule.h" // export macro
#include "vtkUnstructuredGridAlgorithm.h"

#include <string>

class BELTRAMIIO_EXPORT vtkOpenVDBActiveVoxelReader : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkOpenVDBActiveVoxelReader* New();
  vtkTypeMacro(vtkOpenVDBActiveVoxelReader, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  vtkSetStdStringFromCharMacro(GridName);
  vtkGetCharFromStdStringMacro(GridName);
  vtkSetMacro(MaximumNumberOfVoxels, vtkIdType);
  vtkGetMacro(MaximumNumberOfVoxels, vtkIdType);
  vtkSetClampMacro(Timeout, double, 0.1, VTK_DOUBLE_MAX);
  vtkGetMacro(Timeout, double);

  /// 1 if the file starts with OpenVDB's magic number.
  static int CanReadFile(const char* fileName);

protected:
  vtkOpenVDBActiveVoxelReader();
  ~vtkOpenVDBActiveVoxelReader() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  std::string GridName;
  vtkIdType MaximumNumberOfVoxels = 268435456;
  double Timeout = 300.0;

private:
  vtkOpenVDBActiveVoxelReader(const vtkOpenVDBActiveVoxelReader&) = delete;
  void operator=(const vtkOpenVDBActiveVoxelReader&) = delete;
};

#endif
