#!/usr/bin/python3
"""Benchmark (on demand, not a test): vtkIntrinsicParameterization on
Loop-subdivided disk meshes of about 10k and 150k-180k vertices.

    source build/beltrami-env.sh
    /usr/bin/python3 Testing/Benchmarks/benchmark_parameterization.py [threads...]

CGAL is not a Debian dependency of this project; the CGAL 5.5 times printed
for reference are the issue's measurements on a 207k-vertex disk (DCP 11.1 s,
DAP 32.4 s, LSCM 14.2 s), not measured in this run.
"""
import os
import sys
import time

from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter

from beltrami import vtkIntrinsicParameterization, vtkOFFReader

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "Data")
CGAL_207K = {"DCP": 11.1, "DAP": 32.4, "natural": 14.2}


def mesh(name, levels):
    reader = vtkOFFReader()
    reader.SetFileName(os.path.join(DATA, name))
    loop = vtkLoopSubdivisionFilter()
    loop.SetInputConnection(reader.GetOutputPort())
    loop.SetNumberOfSubdivisions(levels)
    loop.Update()
    return loop.GetOutput()


def run(data, conformal, authalic, boundary, threads):
    f = vtkIntrinsicParameterization()
    f.SetInputData(data)
    f.SetConformalWeight(conformal)
    f.SetAuthalicWeight(authalic)
    f.SetBoundary(boundary)
    f.SetNumberOfThreads(threads)
    start = time.perf_counter()
    f.Update()
    return time.perf_counter() - start, f


def main(argv):
    thread_counts = [int(a) for a in argv[1:]] or [1, 2]
    cases = (("DCP", 1.0, 0.0, vtkIntrinsicParameterization.CIRCLE),
             ("DAP", 0.0, 1.0, vtkIntrinsicParameterization.CIRCLE),
             ("natural", 1.0, 0.0, vtkIntrinsicParameterization.NATURAL))
    for name, levels in (("mushroom.off", 1), ("patch-01.off", 4)):
        data = mesh(name, levels)
        n = data.GetNumberOfPoints()
        print("%s, %d Loop levels: %d vertices, %d triangles" % (name, levels, n, data.GetNumberOfCells()))
        for label, conformal, authalic, boundary in cases:
            for threads in thread_counts:
                elapsed, f = run(data, conformal, authalic, boundary, threads)
                line = ("  %-8s %d thread%s %7.3f s   mean angle distortion %6.3f deg, flipped %d"
                        % (label, threads, " " if threads == 1 else "s", elapsed,
                           f.GetMeanAngleDistortion(), f.GetNumberOfFlippedTriangles()))
                if n > 100000:
                    # Scaled to 207k vertices with the n^1.5 cost of a sparse factorization.
                    scaled = elapsed * (207000.0 / n) ** 1.5
                    line += "   ~%.2f s at 207k: CGAL 5.5 (issue) %.1f s = %.1fx" % (
                        scaled, CGAL_207K[label], CGAL_207K[label] / scaled)
                print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
