"""Benchmark (on demand): vtkImplicitFairing with its defaults (the noise
estimate, and where it finds noise the search for the step and the operator,
one order-2 step, exact volume) on the bunny Loop-subdivided four times
(19.3M triangles), clean and with normal noise of 0.075% of the bounding-box
diagonal (2.4 edge lengths): time,
iterations and the peak resident memory of the process that reads the mesh
and smooths it (the subdivision runs in a process of its own first, so its
peak does not count).  Optionally (--multigrid) the same step with hypre's
algebraic multigrid.
Run:  source build/beltrami-env.sh && /usr/bin/python3 Testing/Benchmarks/benchmark_large_fairing.py [levels]
(levels: Loop subdivisions, default 4; needs about 10 GB of memory at 4)."""
import os
import resource
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "Data")


def subdivide(levels, path, noise):
    """The bunny Loop-subdivided `levels` times, with normal noise of `noise`
    times the diagonal (0: clean), written to `path` (binary VTP)."""
    from beltrami.pipelines import noisy_along_normals
    from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
    from beltrami import vtkOFFReader
    reader = vtkOFFReader()
    reader.SetFileName(os.path.join(DATA, "bunny00.off"))
    loop = vtkLoopSubdivisionFilter()
    loop.SetInputConnection(reader.GetOutputPort())
    loop.SetNumberOfSubdivisions(levels)
    loop.Update()
    mesh = loop.GetOutput()
    if noise > 0.0:
        bounds = mesh.GetBounds()
        diagonal = sum((bounds[2 * a + 1] - bounds[2 * a]) ** 2 for a in range(3)) ** 0.5
        mesh = noisy_along_normals(mesh, noise * diagonal, seed=1)
    writer = vtkXMLPolyDataWriter()
    writer.SetInputData(mesh)
    writer.SetFileName(path)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.Write()


def smooth(path, multigrid):
    """Reads `path`, runs one default step; prints triangles, seconds,
    iterations, peak RSS before and after the step (GB)."""
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    from beltrami import vtkImplicitFairing
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    mesh = reader.GetOutput()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    f = vtkImplicitFairing()
    f.SetInputData(mesh)
    f.SetNumberOfThreads(2)
    if multigrid:
        f.SetPreconditioner(vtkImplicitFairing.MULTIGRID)
    t = time.perf_counter()
    f.Update()
    seconds = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    print(mesh.GetNumberOfPolys(), seconds, f.GetIterations(0), before, peak)


if __name__ == "__main__":
    if sys.argv[1:2] == ["--subdivide"]:
        subdivide(int(sys.argv[2]), sys.argv[3], float(sys.argv[4]))
        sys.exit(0)
    if sys.argv[1:2] == ["--smooth"]:
        smooth(sys.argv[2], sys.argv[3] == "1")
        sys.exit(0)
    levels = int(next((a for a in sys.argv[1:] if a.isdigit()), 4))
    solvers = (False, True) if "--multigrid" in sys.argv else (False,)
    print(f"One default fairing step (2 threads) on the bunny Loop-subdivided {levels} times;")
    print("peak RSS of the process that reads the mesh and smooths it (GB): after reading / after the step")
    with tempfile.TemporaryDirectory() as tmp:
        for noise in (0.0, 0.00075):
            path = os.path.join(tmp, "bunny.vtp")
            subprocess.run([sys.executable, __file__, "--subdivide", str(levels), path, repr(noise)], check=True)
            for multigrid in solvers:
                out = subprocess.run([sys.executable, __file__, "--smooth", path, "1" if multigrid else "0"],
                                     check=True, capture_output=True, text=True).stdout.split()
                triangles, seconds, iterations, before, peak = int(out[0]), float(out[1]), int(out[2]), float(out[3]), float(out[4])
                print(f"  {triangles} triangles, noise {100 * noise:.3f}% of the diagonal, "
                      f"{'multigrid' if multigrid else 'Jacobi'}: {seconds:.1f} s, {iterations} iterations, "
                      f"peak {before:.2f} / {peak:.2f} GB")
