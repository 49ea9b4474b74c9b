"""The peers the benchmarks compare with, set up once: VTK's filters, and
the CGAL programs built next to ours (Testing/Benchmarks/CGAL*.cxx)."""
import os
import subprocess
import tempfile

from vtkmodules.vtkImagingGeneral import vtkImageAnisotropicDiffusion2D, vtkImageAnisotropicDiffusion3D

from beltrami import vtkOFFReader, vtkOFFWriter


def run_on_off(program, mesh, arguments, timeout=900):
    """Runs `program in.off *arguments out.off` on `mesh` written as OFF;
    returns (completed process, the mesh read back from out.off, or None when
    the program failed)."""
    with tempfile.TemporaryDirectory() as tmp:
        src, dst = os.path.join(tmp, "in.off"), os.path.join(tmp, "out.off")
        w = vtkOFFWriter()
        w.SetInputData(mesh)
        w.SetFileName(src)
        w.Write()
        run = subprocess.run([program, src] + [str(a) for a in arguments] + [dst], capture_output=True, text=True,
                             timeout=timeout)
        if run.returncode != 0:
            return run, None
        r = vtkOFFReader()
        r.SetFileName(dst)
        r.Update()
        return run, r.GetOutput()


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
