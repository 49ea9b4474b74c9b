// vtkSurfaceRemeshing's private state, shared by its sources
// (vtkSurfaceRemeshing.cxx, vtkSurfaceRemeshingFallbacks.cxx).
#ifndef vtkSurfaceRemeshingInternals_h
#define vtkSurfaceRemeshingInternals_h

#include "vtkSurfaceRemeshing.h"

#include "vtkBeltramiSurface.h"

#include "Maps/Atlas.h"
#include "Remeshing/SurfaceRemeshing.h"

#include <array>
#include <iterator>
#include <memory>
#include <vector>

/// What a re-run with other sampling settings reuses: the input's surface
/// (topology with its edge table, points as doubles), and per layout (the
/// input's points, or their denoised copy where the input's charts failed)
/// its curvatures while the input's geometry stays, and its atlas while the
/// feature settings stay too (and, with sharp edges kept, the count: the
/// feature fragments it drops depend on the spacing).
struct vtkSurfaceRemeshing::Layout
{
  const double* Points = nullptr;
  std::unique_ptr<beltrami::AtlasResult> Atlas;
  beltrami::RemeshCache Remeshing; // of these points and atlas
  bool SplitAtFeatures = false;
  double FeatureAngle = 0.0;
  double FeatureSpacing = 0.0; // the shortest feature chain kept
  std::vector<double> Curvatures; // of the measure CurvatureImportance (-1: none yet)
  int CurvatureImportance = -1;
  std::vector<double> Metric; // from the principal curvatures, with the settings in MetricKey
  std::array<double, 4> MetricKey{}; // MaximumAnisotropy, MinimumImportance, Gradation, AtlasBuilds
};

/// One remesh of the kept surface with the filter's settings, on the active
/// layout: its importance, metric and options, and the result.
struct vtkSurfaceRemeshing::Run
{
  std::vector<double> Importance; // per input vertex (empty: uniform)
  std::vector<double> Metric;     // 6 per input vertex (empty: isotropic)
  beltrami::RemeshOptions Options;
  beltrami::DeviationRemeshResult Driven;
  /// Laid out on the denoised copy: the largest distance of its points from
  /// the remesh there, before it was moved onto the input (whose noise is no
  /// lost part); else -1.
  double LaidDistance = -1.0;
  const double* Weights() const { return this->Importance.empty() ? nullptr : this->Importance.data(); }
};

struct vtkSurfaceRemeshing::Kept
{
  const void* Input = nullptr;
  vtkMTimeType InputTime = 0;
  vtkBeltramiSurface Surface;
  std::vector<double> Storage; // the points as doubles, where they are not (or points were split)
  const double* Points = nullptr; // the input's
  static constexpr int Copies = static_cast<int>(std::size(beltrami::DenoisedLayoutSteps));
  Layout Layouts[1 + Copies]; // 0: on the input's points, 1 + k: on Denoised[k]
  int Active = 0;             // the layout of the run
  bool DenoisedTried[Copies] = {};
  std::vector<double> Denoised[Copies]; // DenoisedLayout of each step (empty: none, or not tried yet)
  /// This update's remesh on the smoothed copies (RemeshDenoised; null: not
  /// made yet), on copy DenoisedCopy (-1: none remeshed).
  std::unique_ptr<Run> DenoisedRun;
  int DenoisedCopy = -1;
  Layout& Laid() { return this->Layouts[this->Active]; }
  /// beltrami::FoldedEdgeShare of the input's points, measured once.
  double FoldedShare()
  {
    if (this->Folded < 0.0)
    {
      this->Folded = beltrami::FoldedEdgeShare(this->Surface.Topology(), this->Points);
    }
    return this->Folded;
  }

private:
  double Folded = -1.0;
};

#endif
