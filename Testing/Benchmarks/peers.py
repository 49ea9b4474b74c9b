"""The peers' filters the denoising benchmarks compare with, set up once."""
from vtkmodules.vtkImagingGeneral import vtkImageAnisotropicDiffusion2D, vtkImageAnisotropicDiffusion3D


def vtk_anisotropic_diffusion(k, iterations, volume=False):
    """VTK's anisotropic diffusion (3D for volumes): threshold k, factor 1,
    faces, edges and corners; the input is left to the caller."""
    f = vtkImageAnisotropicDiffusion3D() if volume else vtkImageAnisotropicDiffusion2D()
    f.SetDiffusionThreshold(k)
    f.SetDiffusionFactor(1.0)
    f.SetNumberOfIterations(iterations)
    f.FacesOn()
    f.EdgesOn()
    f.CornersOn()
    return f
