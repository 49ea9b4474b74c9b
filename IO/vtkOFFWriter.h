/**
 * @class   vtkOFFWriter
 * @brief   Writes vtkPolyData as an OFF mesh (Geomview Object File Format).
 *
 * Polygons are written as they are, triangle strips as triangles; vertices
 * and lines are not representable in OFF and are skipped with a warning.
 * Coordinates are written with 17 significant digits so that a write/read
 * round trip is exact.  When WriteColors is on and the point data has an
 * unsigned char array named ColorArrayName with 3 or 4 components, a COFF
 * file with per-vertex colours is written.
 */
#ifndef vtkOFFWriter_h
#define vtkOFFWriter_h

#include "BeltramiIOModule.h" // export macro
#include "vtkWriter.h"

class vtkPolyData;

class BELTRAMIIO_EXPORT vtkOFFWriter : public vtkWriter
{
public:
  static vtkOFFWriter* New();
  vtkTypeMacro(vtkOFFWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Name of the file to write.
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  ///@}

  ///@{
  /// Write per-vertex colours (COFF) when the colour array exists. Default on.
  vtkSetMacro(WriteColors, bool);
  vtkGetMacro(WriteColors, bool);
  vtkBooleanMacro(WriteColors, bool);
  ///@}

  ///@{
  /// Name of the point colour array. Default "Colors".
  vtkSetStringMacro(ColorArrayName);
  vtkGetStringMacro(ColorArrayName);
  ///@}

  vtkPolyData* GetInput();

protected:
  vtkOFFWriter();
  ~vtkOFFWriter() override;

  void WriteData() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;

  char* FileName = nullptr;
  char* ColorArrayName = nullptr;
  bool WriteColors = true;

private:
  vtkOFFWriter(const vtkOFFWriter&) = delete;
  void operator=(const vtkOFFWriter&) = delete;
};

#endif
