/**
 * @class   vtkLineDrawingWriter
 * @brief   Writes a line drawing (vtkSurfaceLineDrawing's lines) as an SVG
 *          or PDF page for papers and print.
 *
 * The lines are projected with the camera the drawing was made for (its
 * field arrays CameraPosition, ViewDirection, ViewUp and
 * ParallelProjection), the drawing's longer side filling Page Size less the
 * margins; polylines whose ends meet are joined, each is simplified to
 * Tolerance (points on the page) and stroked per line type (cell array
 * LineType) with the widths of LineWidths and the colours of LineColors;
 * with TaperByStrength the suggestive contours and highlights, ridges,
 * valleys and apparent ridges thin where their point array Strength is weak (below twice its
 * median, down to a fifth of the width).  Lines marked hidden (cell array
 * Hidden, the drawing's Visibility set to visible and hidden lines) are
 * drawn dashed in grey with DrawHiddenLines, else left out.  The drawing
 * should be made with Visibility on: its lines are otherwise all written,
 * hidden or not (with a warning).  FileFormat AUTOMATIC takes the format
 * from the file name's extension (.pdf: PDF, else SVG).  PDF goes through
 * Cairo.  In a distributed run (ParaView sets Piece and NumberOfPieces on
 * each rank) rank 0, which holds the drawing's lines, writes the file.
 */
#ifndef vtkLineDrawingWriter_h
#define vtkLineDrawingWriter_h

#include "BeltramiIOModule.h" // export macro
#include "vtkWriter.h"

class vtkPolyData;

class BELTRAMIIO_EXPORT vtkLineDrawingWriter : public vtkWriter
{
public:
  static vtkLineDrawingWriter* New();
  vtkTypeMacro(vtkLineDrawingWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Formats
  {
    AUTOMATIC = 0,
    SVG = 1,
    PDF = 2
  };

  /// Name of the file to write.
  vtkSetFilePathMacro(FileName);
  vtkGetFilePathMacro(FileName);
  /// The format: from the file name's extension (.pdf: PDF, else SVG), SVG or PDF. Values: 0 From
  /// the extension, 1 SVG, 2 PDF. Default: From the extension.
  vtkSetClampMacro(FileFormat, int, AUTOMATIC, PDF);
  vtkGetMacro(FileFormat, int);
  /// The page's longer side in points (1/72 inch). Default: 504.
  vtkSetClampMacro(PageSize, double, 1.0, 1e5);
  vtkGetMacro(PageSize, double);
  /// The page's margin in points. Default: 18.
  vtkSetClampMacro(Margin, double, 0.0, 1e5);
  vtkGetMacro(Margin, double);
  /// Lines are simplified to, and ends joined within, this distance in points. Default: 0.05.
  vtkSetClampMacro(Tolerance, double, 0.0, 100.0);
  vtkGetMacro(Tolerance, double);
  /// Stroke widths in points per line type: contour, suggestive contour, suggestive highlight,
  /// ridge, valley, boundary, crease, apparent ridge, and hidden lines. Default: 1.2 0.7 0.7 0.6
  /// 0.6 1.2 0.9 0.7 0.5.
  vtkSetVectorMacro(LineWidths, double, 9);
  vtkGetVectorMacro(LineWidths, double, 9);
  /// One of Line Widths (index: the line type, 8 for hidden lines), as ParaView sets them.
  void SetLineWidths(int index, double width);
  /// Stroke colours (RGB in [0, 1]) per line type, in the order of Line Widths. Default: 0 0 0 0 0
  /// 0 0.55 0.55 0.55 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0.55 0.55 0.55.
  vtkSetVectorMacro(LineColors, double, 27);
  vtkGetVectorMacro(LineColors, double, 27);
  /// One value of Line Colors (index: 3 times the line type plus the channel), as ParaView sets them.
  void SetLineColors(int index, double value);
  /// Draw the lines marked hidden, dashed (Hidden Dash), instead of leaving them out. Default: off.
  vtkSetMacro(DrawHiddenLines, bool);
  vtkGetMacro(DrawHiddenLines, bool);
  vtkBooleanMacro(DrawHiddenLines, bool);
  /// Dash and gap length of hidden lines in points. Default: 2.5.
  vtkSetClampMacro(HiddenDash, double, 0.0, 1e3);
  vtkGetMacro(HiddenDash, double);
  /// Thin suggestive contours and highlights, ridges, valleys and apparent ridges where they are
  /// weak: width times Strength over twice its median, in [0.2, 1]. Default: off.
  vtkSetMacro(TaperByStrength, bool);
  vtkGetMacro(TaperByStrength, bool);
  vtkBooleanMacro(TaperByStrength, bool);

  /// The piece this process asks its input for, of NumberOfPieces: ParaView sets them on each rank
  /// (its writers' convention), so that a drawing split over the ranks is drawn together and
  /// written by piece 0. Default: 0 of 1 (the whole data).
  vtkSetClampMacro(Piece, int, 0, VTK_INT_MAX);
  vtkGetMacro(Piece, int);
  vtkSetClampMacro(NumberOfPieces, int, 1, VTK_INT_MAX);
  vtkGetMacro(NumberOfPieces, int);

  vtkPolyData* GetInput();

protected:
  vtkLineDrawingWriter();
  ~vtkLineDrawingWriter() override;

  void WriteData() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  vtkTypeBool ProcessRequest(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  char* FileName = nullptr;
  int FileFormat = AUTOMATIC;
  double PageSize = 0.0;
  double Margin = 0.0;
  double Tolerance = 0.0;
  double LineWidths[9];
  double LineColors[27];
  bool DrawHiddenLines = false;
  double HiddenDash = 0.0;
  bool TaperByStrength = false;
  int Piece = 0;
  int NumberOfPieces = 1;

private:
  vtkLineDrawingWriter(const vtkLineDrawingWriter&) = delete;
  void operator=(const vtkLineDrawingWriter&) = delete;
};

#endif
