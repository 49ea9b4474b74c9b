# Reading and writing OFF meshes and OpenVDB grids.
import os
import tempfile
from beltrami import vtkOFFReader, vtkOFFWriter, vtkOpenVDBReader, vtkOpenVDBWriter
from vtkmodules.vtkImagingCore import vtkRTAnalyticSource

folder = tempfile.mkdtemp()
reader = vtkOFFReader()
reader.SetFileName("Testing/Data/mushroom.off")
writer = vtkOFFWriter()
writer.SetInputConnection(reader.GetOutputPort())
writer.SetFileName(os.path.join(folder, "copy.off"))
writer.Write()

wavelet = vtkRTAnalyticSource()
wavelet.SetWholeExtent(0, 15, 0, 15, 0, 15)
vdb = vtkOpenVDBWriter()
vdb.SetInputConnection(wavelet.GetOutputPort())
vdb.SetFileName(os.path.join(folder, "wavelet.vdb"))
vdb.Write()
back = vtkOpenVDBReader()
back.SetFileName(os.path.join(folder, "wavelet.vdb"))
back.Update()
print("voxels read back:", back.GetOutput().GetNumberOfPoints())
