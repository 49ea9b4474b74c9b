import os
import tempfile
from paraview.simple import *

mesh = OpenDataFile("Testing/Data/mushroom.off")  # the OFF reader, by extension
SaveData(os.path.join(tempfile.mkdtemp(), "copy.off"), proxy=mesh)
