/**
 * @class   vtkOpenVDBReader
 * @brief   Reads a grid of an OpenVDB (.vdb) file as vtkImageData.
 *
 * The grid named GridName (default: the first grid) is read densely over its
 * active bounding box: float and double grids give a scalar array, Vec3s and
 * Vec3d grids a 3-component array, named as the grid; inactive voxels inside
 * the box hold the grid's background value.  The grid's transform gives the
 * origin and spacing (axis-aligned scale and translation only; rotated or
 * frustum transforms are an error).  Field data: GridNames (all grids of the
 * file), ActiveVoxelCount.
 *
 * Robustness: OpenVDB's parser can corrupt memory on a damaged file, so it
 * runs in a helper process (beltrami-vdb-read, next to the library; or the
 * program named by BELTRAMI_VDB_READ) that reads the whole file into memory
 * and parses it from a stream that throws at its end (a truncated file is an
 * error, never a hang).  The reader checks every size the helper sends; a
 * crash of the helper, or a run longer than Timeout seconds (default 300), is
 * an error naming the cause, and the output is empty.  A box of more than
 * MaximumNumberOfVoxels voxels (default 2^31 - 1) is refused before anything
 * is allocated.
 */
#ifndef vtkOpenVDBReader_h
#define vtkOpenVDBReader_h

#include "BeltramiIOModule.h" // export macro
#include "vtkImageAlgorithm.h"

#include <string>

class BELTRAMIIO_EXPORT vtkOpenVDBReader : public vtkImageAlgorithm
{
public:
  static vtkOpenVDBReader* New();
  vtkTypeMacro(vtkOpenVDBReader, vtkImageAlgorithm);
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
  vtkOpenVDBReader();
  ~vtkOpenVDBReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  std::string GridName;
  vtkIdType MaximumNumberOfVoxels = 2147483647;
  double Timeout = 300.0;

private:
  // The grid read by RequestInformation, kept for the RequestData that
  // follows (the file is parsed once per update).
  class vtkInternals;
  vtkInternals* Internals;

  vtkOpenVDBReader(const vtkOpenVDBReader&) = delete;
  void operator=(const vtkOpenVDBReader&) = delete;
};

#endif
