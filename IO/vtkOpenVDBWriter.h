/**
 * @class   vtkOpenVDBWriter
 * @brief   Writes a point array of a vtkImageData as an OpenVDB (.vdb) grid.
 *
 * The array selected as input array 0 (default: the active scalars; 1 or 3
 * components; float and double kept, other numeric types written as float)
 * becomes a FloatGrid, DoubleGrid, Vec3SGrid or Vec3DGrid named as the array
 * (or GridName), with a scale-and-translate transform from the image's
 * spacing and origin.  By default every voxel of the extent is active:
 * vtkOpenVDBReader gives back the same extent, spacing, origin and values,
 * bit for bit.  With SparseOutput on, voxels whose components all equal
 * BackgroundValue (the grid's background) stay inactive: a sparse grid, as
 * OpenVDB users expect of fog volumes (read back densely with
 * vtkOpenVDBReader, or its active voxels alone with
 * vtkOpenVDBActiveVoxelReader).
 */
#ifndef vtkOpenVDBWriter_h
#define vtkOpenVDBWriter_h

#include "BeltramiIOModule.h" // export macro
#include "vtkWriter.h"

#include <string>

class vtkImageData;

class BELTRAMIIO_EXPORT vtkOpenVDBWriter : public vtkWriter
{
public:
  static vtkOpenVDBWriter* New();
  vtkTypeMacro(vtkOpenVDBWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  /// The grid's name (default: the array's name).
  vtkSetStdStringFromCharMacro(GridName);
  vtkGetCharFromStdStringMacro(GridName);

  /// Leave the voxels whose components all equal the background value inactive. Default: off.
  vtkSetMacro(SparseOutput, bool);
  vtkGetMacro(SparseOutput, bool);
  vtkBooleanMacro(SparseOutput, bool);
  /// The grid's background value (every component). Default: 0.
  vtkSetMacro(BackgroundValue, double);
  vtkGetMacro(BackgroundValue, double);

  vtkImageData* GetInput();

protected:
  vtkOpenVDBWriter();
  ~vtkOpenVDBWriter() override;

  void WriteData() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;

  char* FileName = nullptr;
  std::string GridName;
  bool SparseOutput = false;
  double BackgroundValue = 0.0;

private:
  vtkOpenVDBWriter(const vtkOpenVDBWriter&) = delete;
  void operator=(const vtkOpenVDBWriter&) = delete;
};

#endif
