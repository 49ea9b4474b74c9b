import os
import tempfile

from paraview.simple import *

drawing = SurfaceLineDrawing(Input=OpenDataFile("Testing/Data/fandisk.off"))
drawing.CameraPosition = [2.0, 1.2, 1.6]
drawing.ViewDirection = [-2.0, -1.2, -1.6]
drawing.Visibility = "Visible lines"
folder = tempfile.mkdtemp()
SaveData(os.path.join(folder, "fandisk.svg"), proxy=drawing)  # the Line Drawing Writer
SaveData(os.path.join(folder, "fandisk.pdf"), proxy=drawing, TaperByStrength=1)
print(sorted(os.listdir(folder)))
