"""Benchmark (on demand): one implicit curvature-flow step of vtkImplicitFairing
against vtkWindowedSincPolyDataFilter (20 iterations) on bunny00 Loop-subdivided
to ~300k and ~1.2M triangles, and accuracy on the noisy bunny (Gaussian noise of
0.3% of the bounding-box diagonal along the normals; RMS vertex distance to the
clean mesh) against the windowed-sinc filter at its best pass band.
In the same run, on the same meshes: CGAL 5.5's smooth_shape (implicit mean
curvature flow, one step of the same time) through
build/bin/beltrami-benchmark-cgal-smooth-shape, built when Debian's
libcgal-dev is installed (a peer to compare with, not a dependency).
Run:  source build/beltrami-env.sh && /usr/bin/python3 Testing/Benchmarks/benchmark_fairing.py

With --defaults: instead, the defaults (the step and the operator
chosen from the noise) on every mesh of the shared corpus with Gaussian noise of
0.1%, 0.3% and 1% of the diagonal along the normals, against the filter's own
best step and windowed sinc's best pass band (both chosen with the clean mesh),
error and time per case in one table (also written for the guide's benchmarks page).
With --defaults --isotropic: the same with the noise in every coordinate.
With --defaults --variants: the defaults on shapes no setting was tuned on,
each corpus mesh stretched 6 times, flattened to 0.15 and decimated to a
tenth (inputs.variants_of), clean (how far the defaults move it, in mean
edge lengths) and with the same noise, against the same oracles: printed
only.
With --preconditioners [--big]: the preconditioners of the implicit solves
(Jacobi, hypre's algebraic multigrid, the geometric multigrid on the
surface's hierarchy, and Automatic, the default, which takes one of the
first and last) on bunny00 Loop-subdivided 0-2 times (75k-1.2M
triangles; --big adds 4.8M), clean and with noise of 0.3% of the diagonal:
one order-1 step of 10 h^2 and of 1000 h^2 and one order-2 step of 4 h^4
(OperatorMollification 0: one solve each), time and iterations of each,
and windowed sinc's time, in one table (a preconditioner that took more
than 10 times Jacobi's time and 2 s on a mesh is not run on the next
larger one)."""
import os
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter

import peers
import results
from beltrami import vtkImplicitFairing, vtkOFFReader

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
from test_python import noisy_along_normals  # noqa: E402
import fairing_oracles as oracles  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "Data")
CGAL = os.path.join(HERE, "..", "..", "build", "bin", "beltrami-benchmark-cgal-smooth-shape")


def mean_edge_length(mesh):
    p = vtk_to_numpy(mesh.GetPoints().GetData()).astype(float)
    t = vtk_to_numpy(mesh.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return float(np.mean([np.linalg.norm(p[t[:, a]] - p[t[:, (a + 1) % 3]], axis=1).mean() for a in range(3)]))


def cgal_smooth(mesh, time_step, iterations=1):
    """(seconds, smoothed points) of CGAL's smooth_shape, or None when not built."""
    if not os.path.exists(CGAL):
        return None
    run, out = peers.run_on_off(CGAL, mesh, [repr(time_step), iterations])
    return float(run.stdout.split()[0]), vtk_to_numpy(out.GetPoints().GetData()).astype(float)


def first_and_best(make, repeats=3):
    """(filter of the last run, wall time of the first run, best of `repeats`):
    the first run of a filter in a process also faults in fresh memory."""
    times = []
    for _ in range(repeats):
        f = make()
        t = time.perf_counter()
        f.Update()
        times.append(time.perf_counter() - t)
    return f, times[0], min(times)


def sinc(mesh, passband):
    return oracles.sinc_filter(mesh, passband)


def fairing(mesh, threads, step=10.0, steps=1, order=1, mollification=0.0):
    """Curvature flow of the given order (step in h^2, h^4 for order 2); order
    1 without mollification is the flow CGAL's smooth_shape integrates."""
    f = vtkImplicitFairing()
    f.SetInputData(mesh)
    f.SetOrder(order)
    f.SetOperatorMollification(mollification)
    f.SetTimeStep(step)
    f.SetNumberOfIterations(steps)
    f.SetNumberOfThreads(threads)
    return f


def subdivided(mesh, levels):
    loop = vtkLoopSubdivisionFilter()
    loop.SetInputData(mesh)
    loop.SetNumberOfSubdivisions(levels)
    loop.Update()
    return loop.GetOutput()


def defaults(mesh, threads):
    f = vtkImplicitFairing()
    f.SetInputData(mesh)
    f.SetNumberOfThreads(threads)
    return f


def defaults_table(isotropic=False):
    """The defaults against the oracles over the corpus (fairing_oracles),
    with noise along the normals or, isotropic, in every direction."""
    import inputs
    print(("Isotropic noise. " if isotropic else "") +
          "Fairing defaults: RMS distance to the clean mesh / diagonal; own best: the best step of the curvature flow\n"
          "and of the umbrella; sinc: vtkWindowedSincPolyDataFilter (20 iterations) at its best pass band; noise:\n"
          "the estimate over the added noise; seconds of the defaults and of one sinc run")
    print(f"{'mesh':28s} {'noise':>6s} {'input':>8s} {'defaults':>8s} {'own best':>8s} {'sinc':>8s} {'noise':>6s} "
          f"{'operator':>9s} {'s':>6s} {'sinc s':>6s}")
    rows = []
    for path in sorted(p for p in inputs.corpus_paths() if p.startswith(inputs.SHARED_MESHES)):
        mesh = oracles.read_triangles(path)
        if mesh.GetNumberOfPolys() < 8:
            continue
        for level in (0.001, 0.003, 0.01):
            r = oracles.case(mesh, level, isotropic=isotropic)
            r["mesh"] = os.path.basename(path)
            rows.append(r)
            print(f"{r['mesh']:28s} {100 * level:5.1f}% {r['input']:8.5f} {r['defaults']:8.5f} {r['own best']:8.5f} "
                  f"{r['sinc best']:8.5f} {r['estimated noise'] / level:6.2f} "
                  f"{'umbrella' if r['operator'] == 0 else 'curvature':>9s} {r['seconds']:6.2f} {r['sinc seconds']:6.2f}"
                  f"{'  (found isotropic)' if r['tangential noise'] > 0 else ''}", flush=True)
    noisy = len(rows)
    summary = (f"No further than the input: {sum(r['defaults'] <= r['input'] * (1 + 1e-9) for r in rows)} of {noisy}; "
               f"within 10% of the own best: {sum(r['defaults'] <= 1.1 * r['own best'] for r in rows)}; "
               f"ahead of windowed sinc's best: {sum(r['defaults'] < r['sinc best'] for r in rows)}; "
               f"noise estimate within 15%: {sum(abs(r['estimated noise'] / r['noise'] - 1) <= 0.15 for r in rows)}.")
    if isotropic:
        summary += f" Found isotropic: {sum(r['tangential noise'] > 0 for r in rows)} of {noisy}."
    print(summary)
    results.save("smoothing_defaults_isotropic" if isotropic else "smoothing_defaults", "Smoothing",
                 "The defaults over the corpus" + (", isotropic noise" if isotropic else ""),
                 "the filter's own best step (curvature flow or umbrella) and vtkWindowedSincPolyDataFilter "
                 "(20 iterations) at its best pass band, both chosen with the clean mesh",
                 "every mesh of the corpus with Gaussian noise " +
                 ("in every coordinate" if isotropic else "along the normals") +
                 " of 0.1%, 0.3% and 1% of the bounding-box diagonal",
                 ["mesh", "noise", "input", "defaults", "own best", "windowed sinc best", "estimated / true noise",
                  "operator chosen"] + (["found isotropic"] if isotropic else []) + ["defaults s", "sinc s"],
                 [[r["mesh"], f"{100 * r['noise']:.1f}%", r["input"], r["defaults"], r["own best"],
                   r["sinc best"], r["estimated noise"] / r["noise"],
                   "umbrella" if r["operator"] == 0 else "curvature flow"] +
                  (["yes" if r["tangential noise"] > 0 else "no"] if isotropic else []) +
                  [r["seconds"], r["sinc seconds"]] for r in rows],
                 "Errors: RMS distance to the clean mesh over the bounding-box diagonal. " + summary)


def variants_table():
    """The defaults on the corpus meshes' variants (see the docstring)."""
    import inputs
    print("Fairing defaults on shapes no setting was tuned on: RMS distance to the clean mesh / diagonal (clean: "
          "the move in mean edge lengths h); own best and sinc as --defaults")
    counts = {"cases": 0, "no further": 0, "within 10%": 0, "ahead of sinc": 0, "clean": 0, "clean kept": 0}
    for path in sorted(p for p in inputs.corpus_paths() if p.startswith(inputs.SHARED_MESHES)):
        for name, mesh in inputs.variants_of(os.path.basename(path), oracles.read_triangles(path)):
            if mesh.GetNumberOfPoints() < 50:
                continue
            moved = oracles.case(mesh, 0.0, oracles=False)["moved"] / oracles.mean_edge_length(mesh)
            counts["clean"] += 1
            counts["clean kept"] += moved < 0.1
            print(f"{name:42s} clean: moved {moved:.3f} h{'  (over 0.1 h)' if moved >= 0.1 else ''}", flush=True)
            for level in (0.001, 0.003, 0.01):
                r = oracles.case(mesh, level)
                flags = [("further than the input", r["defaults"] > r["input"] * (1 + 1e-9)),
                         ("beyond 1.1 x own best", r["defaults"] > 1.1 * r["own best"]),
                         ("behind sinc", r["defaults"] >= r["sinc best"])]
                counts["cases"] += 1
                counts["no further"] += not flags[0][1]
                counts["within 10%"] += not flags[1][1]
                counts["ahead of sinc"] += not flags[2][1]
                print(f"{name:42s} {100 * level:5.1f}% {r['input']:8.5f} {r['defaults']:8.5f} {r['own best']:8.5f} "
                      f"{r['sinc best']:8.5f} noise {r['estimated noise'] / level:5.2f}  "
                      + ", ".join(text for text, bad in flags if bad), flush=True)
    print(f"Clean, moved under 0.1 h: {counts['clean kept']} of {counts['clean']}. Noisy: no further than the input "
          f"{counts['no further']} of {counts['cases']}; within 10% of the own best {counts['within 10%']}; ahead "
          f"of windowed sinc's best {counts['ahead of sinc']}.")


def preconditioner_table(levels):
    """Time and iterations of one step per preconditioner (see the docstring)."""
    reader = vtkOFFReader()
    reader.SetFileName(os.path.join(DATA, "bunny00.off"))
    reader.Update()
    names = ("Jacobi", "algebraic multigrid", "geometric multigrid", "Automatic (default)")
    steps = ((1, 10.0, "order 1, 10 h^2"), (1, 1000.0, "order 1, 1000 h^2"), (2, 4.0, "order 2, 4 h^4"))
    rows = []
    slow = {}  # (mesh, step, preconditioner): its time over Jacobi's at the last size
    for level in levels:
        mesh = subdivided(reader.GetOutput(), level) if level else reader.GetOutput()
        pts = vtk_to_numpy(mesh.GetPoints().GetData())
        diagonal = np.linalg.norm(pts.max(0) - pts.min(0))
        noisy = noisy_along_normals(mesh, 0.003 * diagonal, seed=1)
        # Noise of 0.3% of the diagonal is about one edge of bunny00, two and
        # four of its subdivisions: the same crumpling at every size too.
        edge = noisy_along_normals(mesh, 0.003 * diagonal / 2 ** level, seed=1)
        cases = [("clean", mesh), ("noisy 0.3%", noisy)] + ([("noisy, one edge", edge)] if level else [])
        for label, m in cases:
            start = time.perf_counter()
            sinc(m, 0.1).Update()
            t_sinc = time.perf_counter() - start
            for order, step, text in steps:
                row = [m.GetNumberOfPolys(), label, text]
                for preconditioner in range(len(names)):
                    key = (label, text, preconditioner)
                    if slow.get(key, 0.0) > 10.0:
                        row += ["skipped (%.0fx Jacobi's time on the last mesh)" % slow[key], "-"]
                        continue
                    f = fairing(m, 2, step, 1, order, 0.0)
                    f.SetPreconditioner(preconditioner)
                    start = time.perf_counter()
                    f.Update()
                    seconds = time.perf_counter() - start
                    slow[key] = seconds / row[3] if preconditioner and seconds > 2.0 else 1.0
                    row += [round(seconds, 3), f.GetIterations(0)]
                row.append(round(t_sinc, 3))
                rows.append(row)
                print(" | ".join(map(str, row)), flush=True)
    columns = ["triangles", "mesh", "step"]
    for name in names:
        columns += [name + " s", name + " iterations"]
    results.save("smoothing_preconditioners", "Smoothing", "Preconditioners of the implicit steps",
                 "vtkWindowedSincPolyDataFilter (20 iterations), the same mesh",
                 "bunny00 Loop-subdivided, clean and with noise along the normals of 0.3% of the diagonal (about "
                 "one edge of bunny00, 2 and 4 of its subdivisions) and of 0.3% over 2^level (one edge at every "
                 "size)",
                 columns + ["windowed sinc s"], rows,
                 "One step of vtkImplicitFairing (curvature flow, OperatorMollification 0, 2 threads), the whole "
                 "filter's time (the multigrid set-up included). Order 2 with Jacobi or the geometric multigrid: "
                 "COCG on D + i sqrt(t) K; with the algebraic multigrid: CG on the real system. Automatic: the "
                 "geometric multigrid for order-1 steps from about 150 h^2 and order-2 steps from about 100 h^4 "
                 "(and any order-2 step on 1.5M to 4M vertices), else Jacobi.")


if "--preconditioners" in sys.argv:
    preconditioner_table([0, 1, 2, 3] if "--big" in sys.argv else [0, 1, 2])
    sys.exit(0)

if "--defaults" in sys.argv and "--variants" in sys.argv:
    variants_table()
    sys.exit(0)

if "--defaults" in sys.argv:
    defaults_table("--isotropic" in sys.argv)
    sys.exit(0)

reader = vtkOFFReader()
reader.SetFileName(os.path.join(DATA, "bunny00.off"))
reader.Update()
bunny = reader.GetOutput()
print("Accuracy: noisy bunny (sigma = 0.3% of the diagonal), RMS distance / diagonal")
clean = vtk_to_numpy(bunny.GetPoints().GetData()).astype(float)
diag = np.linalg.norm(clean.max(0) - clean.min(0))
noisy = noisy_along_normals(bunny, 0.003 * diag, seed=1)
noisy_points = vtk_to_numpy(noisy.GetPoints().GetData())

accuracy_rows = []


def rms(f):
    f.Update()
    x = vtk_to_numpy(f.GetOutput().GetPoints().GetData())
    return float(np.sqrt(np.mean(np.sum((x - clean) ** 2, 1)))) / diag


def report(text, value):
    print(f"  {text:60s} {value:.5f}")
    accuracy_rows.append([text, value])


report("noisy input", float(np.sqrt(np.mean(np.sum((noisy_points - clean) ** 2, 1)))) / diag)
best = min((rms(sinc(noisy, pb)), pb) for pb in (0.001, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2))
report(f"windowed sinc, best pass band ({best[1]})", best[0])
report("ours, defaults (the step and the operator chosen from the noise)", rms(defaults(noisy, 0)))
report("ours, curvature flow L^2, 1 x 4 h^4, OperatorMollification 1", rms(fairing(noisy, 0, 4.0, 1, 2, 1.0)))
for step, steps in ((0.25, 4), (0.25, 3), (0.5, 2), (2.0, 1)):
    report(f"ours, curvature flow L {steps} x {step} h^2", rms(fairing(noisy, 0, step, steps)))
for step in (10.0, 20.0, 40.0):
    f = fairing(noisy, 0, step, 1, 2)
    f.SetOperator(vtkImplicitFairing.UMBRELLA)
    report(f"ours, umbrella L^2 (3.2.6), 1 x {step:g}", rms(f))
for step in (2.0, 4.0, 8.0):
    for mollification in (0.0, 1.0):
        report(f"ours, curvature flow L^2, OperatorMollification {mollification:g}, 1 x {step:g} h^4",
               rms(fairing(noisy, 0, step, 1, 2, mollification)))
h = mean_edge_length(bunny)
for step, steps in ((0.25, 3), (0.5, 2), (2.0, 1)):
    reference = cgal_smooth(noisy, step * h * h, steps)
    if reference:
        error = float(np.sqrt(np.mean(np.sum((reference[1] - clean) ** 2, 1)))) / diag
        report(f"CGAL smooth_shape {steps} x {step} h^2", error)
results.save("smoothing_accuracy", "Smoothing", "Accuracy on a noisy scan",
             "vtkWindowedSincPolyDataFilter at its best pass band, CGAL 5.5 smooth_shape",
             "bunny00 with Gaussian noise of 0.3% of the bounding-box diagonal along the normals",
             ["method", "RMS distance to the clean mesh / diagonal"], accuracy_rows)


print("\nSpeed: one implicit curvature-flow step of order 1 (lambda*dt = 10 h^2) and the filter's defaults")
print("(on this clean mesh: the noise estimate, which finds none and leaves it as it is; on a copy with noise of")
print("0.3% of the diagonal: the estimate and the risk search of both operators); windowed sinc, 20 iterations;")
print("first run in this process and best of 3 (CGAL: one run in its own process; the noisy defaults: one run)")
speed_rows = []
for level in (1, 2):
    mesh = subdivided(bunny, level)
    pts = vtk_to_numpy(mesh.GetPoints().GetData())
    noisy_mesh = noisy_along_normals(mesh, 0.003 * np.linalg.norm(pts.max(0) - pts.min(0)), seed=1)
    _, first_sinc, t_sinc = first_and_best(lambda: sinc(mesh, 0.1))
    h = mean_edge_length(mesh)
    reference = cgal_smooth(mesh, 10.0 * h * h)
    for threads in (1, 2):
        f, first, best = first_and_best(lambda: fairing(mesh, threads))
        line = (f"  {mesh.GetNumberOfPolys():9d} triangles, {threads} thread(s): ours {first:.3f} / {best:.3f} s "
                f"({f.GetIterations(0)} CG iterations), windowed sinc {first_sinc:.3f} / {t_sinc:.3f} s "
                f"(ratio {t_sinc / best:.1f})")
        if reference:
            line += f", CGAL smooth_shape {reference[0]:.3f} s (ratio {reference[0] / first:.1f} / {reference[0] / best:.1f})"
        print(line)
        step_best = best
        f, first, best = first_and_best(lambda: defaults(mesh, threads))
        noisy_defaults = defaults(noisy_mesh, threads)
        start = time.perf_counter()
        noisy_defaults.Update()
        noisy = time.perf_counter() - start
        speed_rows.append([mesh.GetNumberOfPolys(), threads, step_best, best, round(noisy, 2), t_sinc,
                           t_sinc / step_best, reference[0] if reference else "-"])
        line = (f"  {'':9s}            {threads} thread(s): defaults {first:.3f} / {best:.3f} s "
                f"({f.GetIterations(0)} iterations), on the noisy copy {noisy:.2f} s")
        if reference:
            line += f", CGAL ratio {reference[0] / first:.1f} / {reference[0] / best:.1f}"
        print(line)
    if not reference:
        print("  (CGAL comparison skipped: build/bin/beltrami-benchmark-cgal-smooth-shape not built; "
              "apt install libcgal-dev and rebuild)")
    # Order 2 (L^2, section 3.2.6): one step of 4 h^4, 2 threads, on this mesh
    # and on the noisy copy.
    for name, m in (("clean", mesh), ("noisy", noisy_mesh)):
        for mollification in (0.0, 1.0):
            f, first, best = first_and_best(lambda: fairing(m, 2, 4.0, 1, 2, mollification))
            print(f"  {name}, curvature flow L^2 one step of 4 h^4, OperatorMollification {mollification:g}: "
                  f"{first:.3f} / {best:.3f} s ({f.GetIterations(0)} iterations)")

results.save("smoothing_speed", "Smoothing", "Speed on large meshes",
             "vtkWindowedSincPolyDataFilter (20 iterations), CGAL 5.5 smooth_shape (one step of the same time)",
             "bunny00 Loop-subdivided (clean, and with noise of 0.3% of the diagonal along the normals)",
             ["triangles", "threads", "one step s", "defaults s", "defaults, noisy s", "windowed sinc s",
              "sinc / one step", "CGAL smooth_shape s"], speed_rows,
             "One step: one implicit curvature-flow step of order 1 (10 h^2); defaults: the noise estimate, which "
             "finds none on the clean mesh and leaves it as it is; on the noisy copy the estimate and the step search "
             "of both operators (one run). Best of 3 runs in one process; CGAL one run in its own.")

print("\nPreconditioners: Jacobi (default) against algebraic multigrid (hypre's BoomerAMG,")
print("one V-cycle per CG iteration), 2 threads, first run in this process (multigrid's includes its set-up;")
print("the first multigrid solve of the process also starts MPI, about 0.5 s); distance to a solve")
print("at tolerance 1e-12, largest over the points, relative to the bounding-box diagonal")
for level in (1, 2):
    mesh = subdivided(bunny, level)
    pts = vtk_to_numpy(mesh.GetPoints().GetData())
    diagonal = np.linalg.norm(pts.max(0) - pts.min(0))
    cases = [(f"noisy {s:g}, 4 h^4", noisy_along_normals(mesh, s * diagonal, seed=1), {"TimeStep": 4.0})
             for s in (0.003, 0.00075)]
    cases.append(("clean, order 1, 1000 h^2", mesh, {"Order": 1, "TimeStep": 1000.0, "OperatorMollification": 0.0}))
    for name, m, settings in cases:
        def make(preconditioner, tolerance=1e-4):
            f = defaults(m, 2)
            for key, value in settings.items():
                getattr(f, "Set" + key)(value)
            f.SetPreconditioner(preconditioner)
            f.SetSolverTolerance(tolerance)
            f.SetMaximumSolverIterations(100000)
            return f
        exact = make(vtkImplicitFairing.JACOBI, 1e-12)
        exact.Update()
        reference = vtk_to_numpy(exact.GetOutput().GetPoints().GetData()).astype(float)
        line = f"  {mesh.GetNumberOfPolys():8d} triangles, {name:26s}"
        seconds = []
        for label, preconditioner in (("Jacobi", vtkImplicitFairing.JACOBI), ("multigrid", vtkImplicitFairing.MULTIGRID)):
            f = make(preconditioner)
            t = time.perf_counter()
            f.Update()
            seconds.append(time.perf_counter() - t)
            x = vtk_to_numpy(f.GetOutput().GetPoints().GetData()).astype(float)
            line += (f" {label} {seconds[-1]:6.2f} s ({f.GetIterations(f.GetNumberOfSolves() - 1)} it, "
                     f"off {np.abs(x - reference).max() / diagonal:.1e})")
        print(line + f"; multigrid/Jacobi time {seconds[1] / seconds[0]:.1f}", flush=True)

print("\nSolver iterations, umbrella operator on bunny00 (the thesis' table in section 3.2.8:")
print("7-9 iterations at lambda*dt = 10, 35-39 at 100, stopping at ||A X - b|| < eps ||X||);")
print("ours stop at a reduction of the initial residual (the update), by default 1e-4")
for step in (10.0, 100.0):
    counts = []
    for tolerance in (1e-2, 1e-4):
        f = vtkImplicitFairing()
        f.SetInputData(bunny)
        f.SetOperator(vtkImplicitFairing.UMBRELLA)
        f.SetOrder(1)
        f.SetTimeStep(step)
        f.SetSolverTolerance(tolerance)
        f.Update()
        counts.append(f"{f.GetIterations(0)} at tolerance {tolerance:g}")
    print(f"  lambda*dt = {step:g}: " + ", ".join(counts))
