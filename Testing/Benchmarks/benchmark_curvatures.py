"""Benchmark (on demand): vtkDiscreteCurvatures against VTK's vtkCurvatures,
speed on the bunny scan and on it Loop-subdivided twice, accuracy on
octahedral unit spheres.  Runs build/bin/beltrami-benchmark-curvatures (the
C++ side, which prints the figures) and writes its tables for the guide's
benchmarks page (results.py).
Run:  source build/beltrami-env.sh && /usr/bin/python3 Testing/Benchmarks/benchmark_curvatures.py"""
import os
import re
import subprocess
import sys

import results

HERE = os.path.dirname(os.path.abspath(__file__))
BINARY = os.path.join(HERE, "..", "..", "build", "bin", "beltrami-benchmark-curvatures")


def seconds(text, label):
    return float(re.search(re.escape(label) + r"\s+([0-9.]+) s", text).group(1))


def main():
    out = subprocess.run([BINARY], check=True, capture_output=True, text=True).stdout
    print(out)
    speed, accuracy = [], []
    for block in re.split(r"\n(?=\S.*: \d+ points)", out)[1:]:
        header = re.match(r"(.*): (\d+) points, (\d+) triangles", block)
        if not header:
            continue
        if "Accuracy" in block:
            block = block.split("\nAccuracy")[0]
        vtk = {kind: seconds(block, "vtkCurvatures " + kind) for kind in ("Mean", "Gaussian", "Maximum")}
        ours1 = seconds(block, "all outputs, 1 thread")
        ours2 = seconds(block, "all outputs, 2 threads")
        speed.append([header.group(1), int(header.group(3)), vtk["Mean"], vtk["Gaussian"], vtk["Maximum"], ours1, ours2,
                      sum(vtk.values()) / ours2])
    for line in out.split("Accuracy", 1)[1].splitlines():
        numbers = re.findall(r"[0-9.]+", line)
        if "|" in line and len(numbers) == 7:
            accuracy.append([int(numbers[0])] + [float(x) for x in numbers[1:]])
    if not speed or not accuracy:
        print("FAILED: could not read the benchmark's output")
        return 1
    results.save("curvatures_speed", "Curvatures", "Speed", "VTK's vtkCurvatures (one run per curvature type)",
                 "bunny00 and bunny00 Loop-subdivided twice",
                 ["mesh", "triangles", "vtkCurvatures mean s", "Gaussian s", "maximum s", "ours, all outputs, 1 thread s",
                  "ours, 2 threads s", "VTK's three / ours 2 threads"], speed,
                 "Medians of repeated runs. Ours computes every output (mean, Gaussian, principal curvatures and "
                 "directions, normals, mixed areas) in one run.")
    results.save("curvatures_accuracy", "Curvatures", "Accuracy on spheres", "VTK's vtkCurvatures",
                 "octahedral unit spheres (subdivided octahedra projected on the sphere)",
                 ["vertices", "ours (Meyer 2003) kappa_H %", "kappa_G %", "ours (Taubin 1995) kappa_H %", "kappa_G %",
                  "vtkCurvatures kappa_H %", "kappa_G %"], accuracy,
                 "Mean relative error against the exact curvatures (1 and 1), in percent.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
