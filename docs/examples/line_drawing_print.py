# A drawing for print: the visible lines only, as SVG and PDF pages.
import os
import tempfile

from beltrami import vtkLineDrawingWriter, vtkOFFReader, vtkSurfaceLineDrawing

reader = vtkOFFReader()
reader.SetFileName("Testing/Data/fandisk.off")
drawing = vtkSurfaceLineDrawing()
drawing.SetInputConnection(reader.GetOutputPort())
drawing.SetCameraPosition(2.0, 1.2, 1.6)
drawing.SetViewDirection(-2.0, -1.2, -1.6)
drawing.SetViewUp(0.0, 1.0, 0.0)
drawing.SetVisibility(vtkSurfaceLineDrawing.VISIBLE_AND_HIDDEN_LINES)

folder = tempfile.mkdtemp()
writer = vtkLineDrawingWriter()
writer.SetInputConnection(drawing.GetOutputPort())
writer.SetDrawHiddenLines(True)  # dashed; off (the default) leaves them out
for name in ("fandisk.svg", "fandisk.pdf"):
    writer.SetFileName(os.path.join(folder, name))
    writer.Write()
print(sorted(os.listdir(folder)))
