"""ImplicitFairing on surfaces split over the ranks of pvbatch:
each rank smooths its own piece, every solve runs over all ranks, and the
results equal the serial ones (plain VTK on the whole surface) to the solver
tolerance.  Run by ctest with 1, 2, 3 and 4 ranks (mpirun --oversubscribe).

Checked: the real bunny cut anywhere by RedistributeDataSet (points where
three or more pieces meet from 3 ranks on), with the default options (order
2 curvature flow, operator mollification, exact volume) at a tight and at the
default tolerance; fixed points and smoothing weights; order 1 with the
area invariant; an open surface (boundary fixed); explicit and Taubin steps,
anisotropy, the sampling regularisation, boundaries smoothed as curves, the
height-field and revolution volumes, axis and plane constraints, the
feature curves of anisotropic smoothing on fandisk (each run where the
pieces are); a rank with an empty piece;
a piece that owns no point; a NaN point in one piece; a fan where Jacobi
stops short of the tolerance (Automatic goes on with the algebraic multigrid
over the ranks); a noisy scan (within
1e-4 of the diagonal), its step chosen over the ranks and on a sample; the
algebraic multigrid over the ranks (the serial iteration counts) and the
geometric one (each rank's hierarchy, joined by a coarse level); and the
counts each rank reports: with 4 ranks no rank holds more
than a third of the points or triangles."""
import builtins  # (ParaView's programmable filters put numpy_interface's all, max, sum... in __main__)
import os
import sys

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from configure import (DISJOINT_SPHERES, FANNED_DISK, check, empty_rank_partitions, lone_triangle_source,  # noqa: E402
                       lone_triangle_whole, moved_points, piecewise_source, rank_rows, with_point_arrays)

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data")


LoadPlugin(os.environ["BELTRAMI_PLUGIN"], ns=globals())
from beltrami import vtkImplicitFairing  # noqa: E402

ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
bunny = OpenDataFile(os.path.join(DATA, "bunny00.off"))
whole_bunny = servermanager.Fetch(bunny)


def points(polydata):
    return vtk_to_numpy(polydata.GetPoints().GetData()).astype(float)


ARRAYS = {"FixedPointsArray": (0, "UseFixedPointsArray"), "SmoothingWeightsArray": (1, "UseSmoothingWeightsArray"),
          "AxisDirectionsArray": (2, "UseAxisDirectionsArray"), "PlaneNormalsArray": (3, "UsePlaneNormalsArray")}


def serial(polydata, **settings):
    """The filter on the whole surface in plain VTK (a serial run)."""
    f = vtkImplicitFairing()
    f.SetInputData(polydata)
    for name, value in settings.items():
        if name in ARRAYS:
            f.SetInputArrayToProcess(ARRAYS[name][0], 0, 0, 0, value[1])
        else:
            getattr(f, "Set" + name)(value)
    f.Update()
    return f.GetOutput()


def matched(pieces, whole):
    """For every point of the fetched pieces, the id of the whole surface's
    point at the same coordinates (the pieces' copies of common points map to
    one point); checks that they cover the whole surface."""
    index = {tuple(x): i for i, x in enumerate(points(whole))}
    ids = np.array([index.get(tuple(x), -1) for x in points(pieces)])
    check(ids.min() >= 0 and len(set(ids)) == whole.GetNumberOfPoints(), "the pieces cover the surface")
    return ids


SERIAL_RUNS = {}


def serial_of(source, prepare, settings):
    """(the whole surface, `prepare`d, and the serial run on it), made once
    for each source, preparation and settings (the runs over other
    partitions compare with the same one)."""
    key = (source.GetGlobalIDAsString(), prepare, repr(sorted(settings.items())))
    if key not in SERIAL_RUNS:
        whole = servermanager.Fetch(prepare(source)) if prepare else servermanager.Fetch(source)
        SERIAL_RUNS[key] = (whole, serial(whole, **settings))
    return SERIAL_RUNS[key]


def split_run(source, label, tolerance, relative, prepare=None, partitions=0, mode=None, **settings):
    """The filter on `source` redistributed over the ranks against the serial
    run; the largest difference must be below `tolerance` times `relative`
    (the serial move, or the size of the surface).  Returns the fetched
    pieces' result and the serial one.  The time step is 4 h^4 unless given
    (TimeStep 0: chosen from the noise, which leaves the clean bunny as it is)."""
    settings.setdefault("TimeStep", 4.0)
    redistributed = RedistributeDataSet(Input=source)
    redistributed.NumberOfPartitions = partitions
    if mode:
        redistributed.BoundaryMode = mode
    unprepared = split = ExtractSurface(Input=redistributed)
    if prepare:
        split = prepare(split)
    faired = ImplicitFairing(Input=split, **settings)
    faired.UpdatePipeline()
    # (Points matched before `prepare`, which may make some NaN.)
    ids = matched(servermanager.Fetch(unprepared), servermanager.Fetch(source))
    result = servermanager.Fetch(faired)
    whole, reference = serial_of(source, prepare, settings)
    ours, theirs = points(result), points(reference)[ids]
    finite = np.isfinite(theirs).all(axis=1)
    check((np.isnan(ours) == np.isnan(theirs)).all(), "%s: NaN exactly where the serial run has it" % label)
    kept = np.isfinite(points(reference)).all(axis=1)
    scale = relative(points(whole)[kept], points(reference)[kept])
    difference = np.abs(ours[finite] - theirs[finite]).max()
    shared = int((np.bincount(ids) >= 3).sum())
    check(difference <= tolerance * scale,
          "%s over %d rank(s) equals the serial result: difference %.3g <= %.0e x %.3g (%d points in 3+ pieces)"
          % (label, ranks, difference, tolerance, scale, shared))
    return faired, result, reference, shared


def iterations(polydata):
    a = polydata.GetFieldData().GetArray("FairingIterations")
    return [int(a.GetValue(k)) for k in range(a.GetNumberOfTuples())]


def extent_of(before, after):
    return np.abs(before).max()


def move_of(before, after):
    return np.abs(after - before).max()


# The default step at a tight tolerance: the serial numbers up to round-off
# of the solves; at the default tolerance within 1e-4 of the move (the same
# solvers run over the ranks; the options on the matrix-free path 1e-3).
faired, result, reference, shared = split_run(bunny, "bunny, defaults, tolerance 1e-10", 1e-9, extent_of,
                                               SolverTolerance=1e-10)
check(ranks < 3 or shared > 0, "bunny: points where three pieces meet")
split_run(bunny, "bunny, defaults", 1e-4, move_of)
# Pieces that overlap: RedistributeDataSet's "Assign to all regions" copies
# the cells on a cut to every piece they touch, unmarked (from 3 ranks on,
# also twice into a rank that holds two of its regions); each is kept once.
split_run(bunny, "bunny, overlapping pieces", 1e-9, extent_of, mode="Assign to all regions", SolverTolerance=1e-10)


# A noisy scan (uniform noise of up to 0.3% of the diagonal): points of tiny
# area make the order-2 system ill-conditioned; a solver that meets the
# residual tolerance can still leave them off by more than the noise (a
# plain CG on the order-2 operator did: 5e-3 of the diagonal on the noisy
# bunny). The distributed complex-shift solve must stay as close as the
# serial one.
def noisy_scan(source):
    # The noise of each point from its coordinates: the same on every rank and in the serial run.
    amplitude = 0.003 * float(np.linalg.norm(points(whole_bunny).max(0) - points(whole_bunny).min(0)))
    return moved_points(source, "h = np.sin(p @ np.array([12.9898e3, 78.233e3, 37.719e3])) * 43758.5453; "
                                "p += %r * (2.0 * (h - np.floor(h)) - 1.0)[:, None] * 0.577" % amplitude)


def diagonal_of(before, after):
    return np.linalg.norm(before.max(0) - before.min(0))


split_run(bunny, "noisy bunny, a step of 4 h^4", 1e-4, diagonal_of, prepare=noisy_scan)
# The step and the operator chosen from the noise (the defaults), on noise in
# all three directions (up to 0.3% of the diagonal in each, from the
# coordinates): the same noise estimate, risks and choice on every rank as
# in the serial run, so the serial points.
def isotropic_noisy_scan(source):
    amplitude = 0.003 * float(np.linalg.norm(points(whole_bunny).max(0) - points(whole_bunny).min(0)))
    return moved_points(source, "h = np.sin(p @ np.array([[12.9898e3, 78.233e3, 37.719e3], [39.3468e3, 11.135e3, "
                                "83.155e3], [73.156e3, 52.235e3, 9.151e3]]).T) * 43758.5453; "
                                "p += %r * (2.0 * (h - np.floor(h)) - 1.0)" % amplitude)


# The noise estimate counts a point where its whole ring is on its owner, so
# it may differ from the serial one by a little (this noise crumples the
# bunny: measured again on 12-rings, which leave out more of the pieces'
# borders, 3% apart on 2 ranks and 5% on 4), and where two steps are nearly
# as good the choice by one step of sqrt 2; the distributed run must then
# give the serial numbers of the step and operator it chose.
noisy_split = isotropic_noisy_scan(ExtractSurface(Input=RedistributeDataSet(Input=bunny)))
chosen = ImplicitFairing(Input=noisy_split)
chosen.UpdatePipeline()
noise, step, operator = rank_rows(chosen, "FairingNoise", ("value",))[0], \
    rank_rows(chosen, "FairingTimeStep", ("value",))[0], rank_rows(chosen, "FairingOperator", ("value",))[0]
whole_noisy = servermanager.Fetch(isotropic_noisy_scan(bunny))
chosen_serial = serial(whole_noisy, TimeStep=0.0)
serial_values = [chosen_serial.GetFieldData().GetArray(name).GetValue(0)
                 for name in ("FairingNoise", "FairingTimeStep", "FairingOperator")]
held = noise >= 0  # (ranks with a piece)
check(np.allclose(noise[held], noise[held][0]) and np.allclose(step[held], step[held][0])
      and (operator[held] == operator[held][0]).all(), "every rank chose the same step %s" % step)
check(abs(noise[held][0] / serial_values[0] - 1) < 0.1 and serial_values[1] > 0.0
      and 0.7 < step[held][0] / serial_values[1] < 1.42 and operator[held][0] == serial_values[2],
      "noise %.5g, step %.3g, operator %d over the ranks; serial %.5g, %.3g, %d"
      % (noise[held][0], step[held][0], operator[held][0], *serial_values))
split_run(bunny, "noisy bunny, the step chosen over the ranks", 1e-4, diagonal_of, prepare=isotropic_noisy_scan,
          TimeStep=float(step[held][0]), Operator=int(operator[held][0]))
# The step chosen on a sample of the surface (StepSearchPoints: here 4,096
# of the bunny's 37,706 points, by default 131,072 of surfaces of more than
# four times that): the sample is gathered on the first rank, so the noise,
# the step and the operator are the serial ones, and the points the serial
# ones to the solver tolerance.
SAMPLED = ("FairingNoise", "FairingTimeStep", "FairingOperator", "FairingSampledPoints")
on_sample = ImplicitFairing(Input=noisy_split, StepSearchPoints=4096)
on_sample.UpdatePipeline()
over_ranks = [rank_rows(on_sample, name, ("value",))[0] for name in SAMPLED]
on_sample_serial = serial(whole_noisy, TimeStep=0.0, StepSearchPoints=4096)
serial_sampled = [on_sample_serial.GetFieldData().GetArray(name).GetValue(0) for name in SAMPLED]
held = over_ranks[0] >= 0
check(serial_sampled[3] > 3800 and builtins.all(np.allclose(v[held], s, rtol=1e-9, atol=0) for v, s in zip(over_ranks, serial_sampled)),
      "on a sample of %d points: noise %s, step %s, operator %s over the ranks; serial %.6g, %.4g, %d"
      % (serial_sampled[3], over_ranks[0][held], over_ranks[1][held], over_ranks[2][held], *serial_sampled[:3]))
split_run(bunny, "noisy bunny, the step chosen on a sample", 1e-4, diagonal_of, prepare=isotropic_noisy_scan,
          TimeStep=0.0, StepSearchPoints=4096)


def enclosed_volume(polydata):
    p = points(polydata)
    t = vtk_to_numpy(polydata.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return float(np.sum(np.einsum("ij,ij->i", p[t[:, 0]], np.cross(p[t[:, 1]], p[t[:, 2]])))) / 6


check(abs(enclosed_volume(reference) / enclosed_volume(whole_bunny) - 1) < 1e-9, "serial volume kept")
# (The fetched pieces are the surface with its common points repeated: its volume is the surface's.)
check(abs(enclosed_volume(result) / enclosed_volume(whole_bunny) - 1) < 1e-9,
      "distributed volume kept exactly (%.3g)" % (enclosed_volume(result) / enclosed_volume(whole_bunny) - 1))

# Algebraic multigrid over the ranks (one BoomerAMG hierarchy spanning them):
# the serial result and the serial iteration counts, an empty rank included.
for partitions in ([0, empty_rank_partitions(ranks)] if ranks > 1 else [0]):
    _, result, reference, _ = split_run(bunny, "bunny, multigrid, %d partitions" % (partitions or ranks), 1e-9, extent_of,
                                        partitions=partitions, Preconditioner=1, SolverTolerance=1e-10)
    ours, theirs = iterations(result), iterations(reference)
    check(len(ours) == len(theirs) and builtins.all(builtins.abs(a - b) <= 2 for a, b in zip(ours, theirs)),
          "multigrid iterations over the ranks %s, serial %s" % (ours, theirs))

# Geometric multigrid over the ranks: each rank cycles on its own points'
# hierarchy, joined by a coarse level made of one level of every rank's: the
# serial result, in iterations that stay within 3.5 times the serial count
# on the complex systems of order 2, where the ranks join their coarsest
# levels (1.9-2 times measured on 2 to 4 ranks), and within 1.5 times on the
# real ones of order 1, where they join finer levels (1-1.25 times; 2.4-2.6
# times on their coarsest levels, and each rank's cycles alone, without the
# joining level, 8-10 times), an empty rank included.
for partitions in ([0, empty_rank_partitions(ranks)] if ranks > 1 else [0]):
    for settings, most in ((dict(), 3.5), (dict(Order=1, TimeStep=4000.0), 1.5)):
        _, result, reference, _ = split_run(bunny, "bunny, geometric multigrid %s, %d partitions"
                                            % (settings, partitions or ranks), 1e-9, extent_of, partitions=partitions,
                                            Preconditioner=2, SolverTolerance=1e-10, **settings)
        ours, theirs = iterations(result), iterations(reference)
        check(len(ours) == len(theirs) and builtins.all(a <= most * b for a, b in zip(ours, theirs)),
              "geometric multigrid iterations over the ranks %s, serial %s" % (ours, theirs))

# A fan where Jacobi stops short of the tolerance (the order-2 step's 1,000
# iterations run out): Automatic goes on with the algebraic multigrid over
# the ranks, to the serial result.
_, result, reference, _ = split_run(piecewise_source(FANNED_DISK), "fanned disk, Automatic", 1e-4, move_of)
ours, theirs = iterations(result), iterations(reference)
check(builtins.min(ours + theirs) > 1000 and builtins.max(ours + theirs) < 1100,
      "fanned disk: Jacobi's 1,000 iterations, then the algebraic multigrid's, over the ranks %s, serial %s"
      % (ours, theirs))

# What each rank holds: its own points, the ghost points of the rings, its
# triangles (field data FairingDistribution, one row per rank).
owned, ghosts, triangles = rank_rows(faired, "FairingDistribution", ("Owned", "Ghosts", "Triangles"))
if ranks > 1:
    check((owned >= 0).all() and owned.sum() == whole_bunny.GetNumberOfPoints(),
          "each point owned by one rank (%s)" % owned)
    check(ranks != 4 or ((owned + ghosts).max() <= whole_bunny.GetNumberOfPoints() / 3
                         and triangles.max() <= whole_bunny.GetNumberOfCells() / 3),
          "no rank holds more than a third: points %s of %d, triangles %s of %d"
          % (owned + ghosts, whole_bunny.GetNumberOfPoints(), triangles, whole_bunny.GetNumberOfCells()))

# Options that keep working distributed: fixed points and smoothing weights
# (point arrays), order 1 with the area invariant.
def with_masks(source):
    return with_point_arrays(source, {"fixed": "(p[:, 1] > 0.15).astype(np.uint8)",
                                      "weight": "np.clip(10.0 * (p[:, 0] + 0.05), 0.0, 1.0)"})


split_run(bunny, "bunny with fixed points and weights", 1e-3, move_of, prepare=with_masks, NumberOfIterations=2,
          UseFixedPointsArray=1, FixedPointsArray=["POINTS", "fixed"],
          UseSmoothingWeightsArray=1, SmoothingWeightsArray=["POINTS", "weight"])
split_run(bunny, "bunny, order 1, area kept", 1e-3, move_of, Order=1, Invariant=3, TimeStep=2.0)

# An open surface: its boundary fixed, no invariant.
mushroom = OpenDataFile(os.path.join(DATA, "mushroom.off"))
split_run(mushroom, "mushroom (open)", 1e-3, move_of)


# Every option but virtual vertices (one vertex joined to a whole boundary
# loop) runs over the ranks: explicit and Taubin steps (a ghost update after
# each power of the operator), anisotropic weights and feature curves (each
# point's by its owner), the sampling regularisation, boundaries smoothed as curves
# (the boundary edges at owned points), the height-field and revolution
# volumes (summed over the ranks), axis and plane constraints (the projected
# solve over the ranks).  The serial numbers up to round-off and the solver
# tolerance, and no gathering: every rank reports its own piece.
def distributed_option(source, label, relative=extent_of, prepare=None, partitions=0, **settings):
    if ranks == 1:
        return  # (one rank runs the serial path: nothing split to compare)
    faired = split_run(source, label, 1e-9, relative, prepare=prepare, partitions=partitions, **settings)[0]
    owned, = rank_rows(faired, "FairingDistribution", ("Owned",))
    # (One partition over several ranks: one rank holds the whole surface and runs it as in serial.)
    check(ranks == 1 or partitions == 1 or (owned >= 0).all(),
          "%s: run where the pieces are (owned points %s)" % (label, owned))


def with_directions(source):
    return with_point_arrays(source, {
        "axis": "np.where((p[:, 1] > 0.15)[:, None], np.array([[0.0, 0.3, 1.0]]), 0.0)",
        "normal": "np.where((p[:, 0] < -0.03)[:, None], np.array([[1.0, 0.2, 0.0]]), 0.0)"})


distributed_option(bunny, "bunny, explicit umbrella", Integration=1, Operator=0, TimeStep=0.5, NumberOfIterations=3)
distributed_option(bunny, "bunny, explicit umbrella squared", Integration=1, Operator=0, TimeStep=0.1,
                   NumberOfIterations=2)
distributed_option(bunny, "bunny, Taubin", Integration=2, Operator=0, NumberOfIterations=4)
distributed_option(bunny, "bunny, anisotropic", Anisotropic=1, SolverTolerance=1e-12)
fandisk = OpenDataFile(os.path.join(DATA, "fandisk.off"))
distributed_option(fandisk, "fandisk, anisotropic with feature curves", Anisotropic=1, SmoothFeatureCurves=1,
                   SolverTolerance=1e-12)
distributed_option(bunny, "bunny, sampling regularisation", Operator=3, Order=1, SolverTolerance=1e-12)
distributed_option(bunny, "bunny, volume of revolution", Invariant=5, ReferencePlaneNormal=[0.0, 1.0, 0.0],
                   SolverTolerance=1e-12)
distributed_option(mushroom, "mushroom, boundary smoothed as a curve", BoundaryHandling=1, SolverTolerance=1e-12)
distributed_option(mushroom, "mushroom, height-field volume", Invariant=4, SolverTolerance=1e-12)
if ranks > 1:  # the same with a rank that holds nothing (no hang: it takes part in every collective step)
    distributed_option(mushroom, "mushroom on %d of %d ranks, curve boundary, anisotropic, explicit"
                       % (empty_rank_partitions(ranks), ranks), partitions=empty_rank_partitions(ranks),
                       BoundaryHandling=1, Anisotropic=1,
                       Integration=1, Operator=0, TimeStep=0.3, NumberOfIterations=2, SolverTolerance=1e-12)
distributed_option(bunny, "bunny, axis and plane constraints", prepare=with_directions, NumberOfIterations=2,
                   SolverTolerance=1e-12, UseAxisDirectionsArray=1, AxisDirectionsArray=["POINTS", "axis"],
                   UsePlaneNormalsArray=1, PlaneNormalsArray=["POINTS", "normal"])

# A rank with an empty piece (fewer partitions than ranks).
if ranks > 1:
    parts = empty_rank_partitions(ranks)
    emptied = split_run(bunny, "bunny on %d of %d ranks" % (parts, ranks), 1e-4, move_of, partitions=parts)[0]
    owned, = rank_rows(emptied, "FairingDistribution", ("Owned",))
    # (One partition: one rank holds the whole surface and runs it as in serial, no rows.)
    check(parts == 1 or (owned == 0).any(), "bunny on %d of %d ranks: a rank holds nothing (owned %s)"
          % (parts, ranks, owned))


# A NaN point (in whichever piece holds it): kept as it is, the rest smoothed as in serial.
def with_nan(source):
    return moved_points(source, "p[(p == np.array(%r)).all(axis=1)] = np.nan" % (points(whole_bunny)[1000].tolist(),))


split_run(bunny, "bunny with a NaN point", 1e-4, move_of, prepare=with_nan)
split_run(bunny, "bunny with a NaN point, geometric multigrid", 1e-4, move_of, prepare=with_nan, Preconditioner=2)
# A piece that owns no point (configure.lone_triangle_source); the serial
# run smooths the whole field (a step of 4 h^4: the chosen step leaves this
# clean field as it is, and would check nothing). Pieces that touch nowhere (a sphere per
# rank): no ring to exchange, each sphere smoothed as in the serial run of
# them all (before: an assertion in VTK's bounding box aborted pvbatch).
# Both also with the geometric multigrid (a rank whose rows are all ghosts;
# a joining level without borders).
for preconditioner in (3, 2):
    if ranks == 1:
        break
    lone_source = lone_triangle_source()
    lone = ImplicitFairing(Input=lone_source, TimeStep=4.0, Preconditioner=preconditioner)
    lone.UpdatePipeline()
    pieces, result = servermanager.Fetch(lone_source), servermanager.Fetch(lone)
    whole_field = lone_triangle_whole()
    reference = serial(whole_field, TimeStep=4.0)
    ids = matched(pieces, whole_field)
    difference = np.abs(points(result) - points(reference)[ids]).max()
    moved = np.abs(points(reference) - points(whole_field)).max()
    owned, = rank_rows(lone, "FairingDistribution", ("Owned",))
    check(owned[builtins.min(2, ranks - 1)] == 0 and moved > 0 and difference <= 1e-3 * moved,
          "preconditioner %d: a rank that owns no point (owned %s): the serial result (difference %.3g, move %.3g)"
          % (preconditioner, owned, difference, moved))
    spheres = ImplicitFairing(Input=piecewise_source(DISJOINT_SPHERES), TimeStep=4.0, Preconditioner=preconditioner)
    spheres.UpdatePipeline()
    result = servermanager.Fetch(spheres)
    from vtkmodules.vtkFiltersCore import vtkAppendPolyData
    namespace = {}
    exec(DISJOINT_SPHERES, namespace)
    append = vtkAppendPolyData()
    for piece in range(ranks):
        append.AddInputData(namespace["make"](piece, ranks))
    append.Update()
    reference = serial(append.GetOutput(), TimeStep=4.0)
    difference = np.abs(points(result) - points(reference)).max()
    moved = np.abs(points(reference) - points(append.GetOutput())).max()
    check(moved > 0 and difference <= 1e-4 * moved,
          "preconditioner %d: pieces that touch nowhere: the serial result (difference %.3g, move %.3g)"
          % (preconditioner, difference, moved))
print("distributed fairing test passed")
