// vtkSurfaceRemeshing's fallbacks: the remesh laid out on a smoothed copy
// of a noisy input, with sparser seams where the input's chart boundaries
// take more than the count, and with sharp edges kept where the
// error-driven mode misses its bound without them.
#include "vtkSurfaceRemeshingInternals.h"

#include "Mesh/MeshMeasures.h"

#include <algorithm>
#include <string>
#include <vector>

bool vtkSurfaceRemeshing::LayOutOnDenoisedCopy(int k)
{
  Kept& kept = *this->Cache;
  if (!kept.DenoisedTried[k])
  {
    kept.DenoisedTried[k] = true;
    kept.Denoised[k] = beltrami::DenoisedLayout(
      kept.Surface.Topology(), kept.Points, beltrami::DenoisedLayoutSteps[k], this->NumberOfThreads);
    kept.Layouts[1 + k].Points = kept.Denoised[k].data();
  }
  kept.Active = kept.Denoised[k].empty() ? 0 : 1 + k;
  return kept.Active > 0;
}

bool vtkSurfaceRemeshing::RemeshDenoised(Run& run)
{
  // The first copy that remeshes; where its remesh is poor, the next ones
  // too, the better kept (isotropic noise of 0.6% of the diagonal on
  // bunny00: the first copy's remesh at 2,000 vertices has 3.2% of its
  // triangles below 30 degrees, the second's 0.3%).
  Kept& cache = *this->Cache;
  if (!cache.DenoisedRun)
  {
    cache.DenoisedRun = std::make_unique<Run>();
    Run& best = *cache.DenoisedRun;
    for (int k = 0; k < Kept::Copies &&
         (cache.DenoisedCopy < 0 || beltrami::PoorRemesh(best.Driven.Remesh, this->NumberOfThreads));
         ++k)
    {
      Run denoised;
      if (!this->LayOutOnDenoisedCopy(k) || !this->Atlas().Error.empty() || !this->RemeshLayout(denoised) ||
        !denoised.Driven.Remesh.Error.empty())
      {
        continue;
      }
      beltrami::RemeshResult& remesh = denoised.Driven.Remesh;
      denoised.LaidDistance = remesh.DeviationFromInput * remesh.Diagonal;
      beltrami::CheckFidelity(this->Cache->Surface.Topology(), this->Cache->Points, denoised.Options, remesh);
      if (cache.DenoisedCopy < 0 || beltrami::KeepCopysRemesh(remesh, best.Driven.Remesh, this->NumberOfThreads))
      {
        best = std::move(denoised);
        cache.DenoisedCopy = k;
      }
    }
  }
  if (cache.DenoisedCopy < 0)
  {
    return false;
  }
  run = *cache.DenoisedRun;
  return this->LayOutOnDenoisedCopy(cache.DenoisedCopy);
}

namespace
{

/// The end of both warnings that a remesh was laid out on a smoothed copy.
const char* const OnCopy = "the remesh was laid out on a smoothed copy of the input and moved onto it, its triangles "
                           "then shaped on the input: its vertices lie on the input and follow its noise";
const char* const SmoothFirst = ". For a remesh of the smoothed surface, smooth the input first (vtkImplicitFairing).";

} // namespace

bool vtkSurfaceRemeshing::LayOutFoldedInputOnCopyFirst(Run& run)
{
  // (Not with sharp edges kept: their folds are the shape's.  A noisy
  // cube's edges at 90 degrees fold half the time, and its smoothed copies
  // remesh poorly: 0.2 -> 1.2 s at 10,000 vertices for the same remesh.)
  Kept& kept = *this->Cache;
  const double folded = this->MaximumDeviation > 0.0 || this->SplitsAtFeatures()
    ? 0.0 : kept.FoldedShare();
  if (folded < beltrami::HeavilyFoldedShare || !this->RemeshDenoised(run) ||
    beltrami::PoorRemesh(run.Driven.Remesh, this->NumberOfThreads))
  {
    kept.Active = 0;
    run = Run();
    return false;
  }
  vtkWarningMacro(<< "The input folds (" << 100.0 * folded << "% of its neighbouring triangles face more than 90 "
                  << "degrees apart: noise larger than its edges, on which its own charts fail or remesh poorly): "
                  << OnCopy << SmoothFirst);
  return true;
}

void vtkSurfaceRemeshing::LayOutNoisyInputOnCopy(Run& run)
{
  // Where the input's own charts fail (a scan whose noise is as large as its
  // edges), the remesh is laid out on a smoothed copy and moved onto the
  // input; not where the rims of its holes alone take more samples than the
  // count (a scan with many holes), which every copy keeps.  Where they
  // remesh, but poorly, on a crumpled input, the copy's is kept where it is
  // better.
  Kept& kept = *this->Cache;
  const std::string inputError = run.Driven.Remesh.Error;
  const std::int64_t tried = run.Driven.Counts.empty() ? this->NumberOfVertices : run.Driven.Counts.back();
  if (!inputError.empty() && run.Driven.Remesh.Samples.RimSamples <= tried)
  {
    const std::int64_t needed = run.Driven.Remesh.Samples.BoundarySamples;
    if (this->RemeshDenoised(run))
    {
      // On an input that does not fold (not noisy), a copy's remesh that
      // leaves it farther than its spacing has lost parts the smoothing
      // rounded off (the thin hairs of a sphere, a flattened CAD part's
      // edges): the input's own charts with sparser seams are kept where
      // they come closer.
      const beltrami::RemeshResult& laid = run.Driven.Remesh;
      if (beltrami::WorstDeviation(laid) * laid.Diagonal > laid.Spacing &&
        kept.FoldedShare() < beltrami::CrumpledShare)
      {
        const int copy = kept.Active;
        kept.Active = 0;
        if (this->RemeshWithSparserSeams(run, needed, &laid))
        {
          return;
        }
        kept.Active = copy;
      }
      vtkWarningMacro(<< "The input's own charts cannot be remeshed with " << tried << " vertices (" << inputError
                      << "): " << OnCopy
                      << (this->MaximumDeviation > 0.0 ? " (MaximumDeviation holds on the smoothed copy; "
                                                         "RemeshDeviation is measured on the input, noise included)"
                                                       : "")
                      << SmoothFirst);
    }
    else
    {
      kept.Active = 0; // the input's error stands
    }
    return;
  }
  if (!inputError.empty() || this->MaximumDeviation > 0.0 || !beltrami::PoorRemesh(run.Driven.Remesh, this->NumberOfThreads))
  {
    return;
  }
  const double folded = kept.FoldedShare();
  Run denoised;
  if (folded >= beltrami::CrumpledShare && this->RemeshDenoised(denoised) &&
    beltrami::KeepCopysRemesh(denoised.Driven.Remesh, run.Driven.Remesh, this->NumberOfThreads))
  {
    run = std::move(denoised);
    vtkWarningMacro(<< "The input folds (" << 100.0 * folded << "% of its neighbouring triangles face more than 90 "
                    << "degrees apart: noise, or knife edges, which SplitAtFeatures keeps) and the remesh of its own "
                    << "charts was poor: " << OnCopy << SmoothFirst);
  }
  else
  {
    kept.Active = 0; // the input's own remesh stands
  }
}

void vtkSurfaceRemeshing::LayOutWithSparserSeams(Run& run)
{
  // Last, so that a noisy scan whose own charts fail is laid out on a
  // smoothed copy first (its remesh there is better).
  const beltrami::SurfaceSamples& samples = run.Driven.Remesh.Samples;
  if (run.Driven.Remesh.Error.empty() || this->Cache->Active != 0 || samples.BoundarySamples <= this->NumberOfVertices)
  {
    return;
  }
  this->RemeshWithSparserSeams(run, samples.BoundarySamples, nullptr); // (else the first error stands)
}

bool vtkSurfaceRemeshing::RemeshWithSparserSeams(Run& run, std::int64_t needed, const beltrami::RemeshResult* rival)
{
  Run sparser;
  if (this->MaximumDeviation > 0.0 || !this->RemeshLayout(sparser, true) || !sparser.Driven.Remesh.Error.empty() ||
    (rival && !(beltrami::WorstDeviation(sparser.Driven.Remesh) < beltrami::WorstDeviation(*rival))))
  {
    return false;
  }
  const beltrami::SurfaceSamples& sparse = sparser.Driven.Remesh.Samples;
  vtkWarningMacro(<< "The chart boundaries of the input need " << needed << " samples at the spacing of "
                  << this->NumberOfVertices << " vertices (" << this->Atlas().Charts.size()
                  << " charts), more than the count: the seams between its charts were "
                  << "sampled " << sparse.SeamSpacing << " times as sparsely (" << sparse.BoundarySamples
                  << " samples) and the remesh evened across them. More vertices give its triangles more room."
                  << (rival ? " (Laid out on a smoothed copy of the input instead, the remesh was farther from it.)"
                            : ""));
  run = std::move(sparser);
  return true;
}

void vtkSurfaceRemeshing::KeepSharpEdgesWhereMissed(Run& run)
{
  // (As MMG's Hausdorff mode keeps ridges.)  Where the remesh with them
  // rounded off missed the bound, or met it only with more vertices than
  // the input has (rounding a polyhedron's creases finely): rounded off,
  // the sharp rims of a cylinder of 64 segments took 16,384 vertices, 64
  // per input vertex, the most the mode makes, to come within 0.5% of the
  // diagonal (0.40%); kept, 228 meet 0.5%.  A remesh that met the bound
  // gives way only to one that meets it with fewer vertices and triangles
  // as good (the kept edges of a coarse scan make slivers: the cow at 0.5%,
  // 4,431 vertices rounded, 2,988 kept with an angle of 4.4 degrees).
  const beltrami::DeviationRemeshResult& driven = run.Driven;
  const std::int64_t before = driven.Counts.empty() ? 0 : driven.Counts.back();
  const bool finer = before > this->Cache->Surface.Topology().NumberOfVertices();
  if (this->MaximumDeviation <= 0.0 || this->SplitAtFeatures || (driven.Met && !finer) ||
    !driven.Remesh.Error.empty() || this->Cache->Active != 0)
  {
    return;
  }
  const std::vector<std::uint8_t> sharp =
    beltrami::SharpEdges(this->Cache->Surface.Topology(), this->Cache->Points, this->FeatureAngle);
  if (std::find(sharp.begin(), sharp.end(), 1) == sharp.end())
  {
    return;
  }
  this->KeepingSharpEdges = true;
  Run kept;
  if (this->RemeshLayout(kept) && kept.Driven.Remesh.Error.empty() &&
    (driven.Met ? kept.Driven.Met && kept.Driven.Counts.back() < before &&
          beltrami::AsGoodTriangles(kept.Driven.Remesh, driven.Remesh)
                : kept.Driven.Met ||
         beltrami::WorstDeviation(kept.Driven.Remesh) < beltrami::WorstDeviation(driven.Remesh)))
  {
    vtkWarningMacro(<< "The remesh with the input's edges sharper than FeatureAngle rounded off was "
                    << 100.0 * beltrami::WorstDeviation(driven.Remesh) << "% of the diagonal from it with " << before
                    << " vertices, "
                    << (driven.Met ? "within" : "more than")
                    << " the MaximumDeviation of " << 100.0 * this->MaximumDeviation
                    << "%: those edges are kept (as SplitAtFeatures keeps them), with "
                    << kept.Driven.Remesh.Points.size() / 3 << " vertices.");
    run = std::move(kept);
    return;
  }
  this->KeepingSharpEdges = false;
  this->SharpEdgesTried = true;
  this->Atlas(); // (again the one of the run kept)
}
