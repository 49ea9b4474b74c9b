/**
 * @class   vtkOFFReader
 * @brief   Reads OFF meshes (Geomview Object File Format) into vtkPolyData.
 *
 * Reads OFF, COFF, NOFF, CNOFF and STOFF variants: polygons of any size,
 * '#' comments, per-vertex normals ("Normals"), colours ("Colors", unsigned
 * char RGB or RGBA) and texture coordinates ("TCoords"), per-face colours
 * (cell array "Colors").  Points are double precision.  Every count and
 * index in the file is validated before use; a truncated, malformed or
 * hostile file produces an error and an empty output.
 */
#ifndef vtkOFFReader_h
#define vtkOFFReader_h

#include "BeltramiIOModule.h" // export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for LastError

class BELTRAMIIO_EXPORT vtkOFFReader : public vtkPolyDataAlgorithm
{
public:
  static vtkOFFReader* New();
  vtkTypeMacro(vtkOFFReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Name of the file to read.
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  /// Returns 1 if the file starts like an OFF file.
  static int CanReadFile(const char* fileName);

  /// The message of the last failed read (empty after a success).
  const char* GetLastErrorMessage() const { return this->LastError.c_str(); }

protected:
  vtkOFFReader();
  ~vtkOFFReader() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  std::string LastError;

private:
  vtkOFFReader(const vtkOFFReader&) = delete;
  void operator=(const vtkOFFReader&) = delete;
};

#endif
