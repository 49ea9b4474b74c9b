// Benchmark: vtkDiscreteCurvatures against VTK's vtkCurvatures on the same
// meshes in the same run (times, ratios), and both methods' accuracy on the
// octahedral spheres of the thesis.  Run on demand, not a test:
//   build/bin/beltrami-benchmark-curvatures [bunny00.off]
#include "TestMeshes.h"

#include "vtkDiscreteCurvatures.h"
#include "vtkOFFReader.h"

#include <vtkCellArray.h>
#include <vtkCurvatures.h>
#include <vtkDoubleArray.h>
#include <vtkLoopSubdivisionFilter.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace
{

constexpr int Repeats = 5;

/// The first and the median time of `repeats` runs.
struct Times
{
  double First = 0.0;
  double Median = 0.0;
};

template <typename F>
Times MedianSeconds(F&& run, int repeats = Repeats)
{
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r)
  {
    const auto start = std::chrono::steady_clock::now();
    run();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  const double first = t.front();
  std::sort(t.begin(), t.end());
  return { first, t[t.size() / 2] };
}

/// Times of a fresh filter of type Filter on mesh, set up by configure.
template <typename Filter, typename Configure>
Times TimeFilter(vtkPolyData* mesh, Configure&& configure)
{
  return MedianSeconds([&]() {
    vtkNew<Filter> f;
    f->SetInputData(mesh);
    configure(f.Get());
    f->Update();
  });
}

double TimeVTK(vtkPolyData* mesh, int type)
{
  return TimeFilter<vtkCurvatures>(mesh, [type](vtkCurvatures* c) { c->SetCurvatureType(type); }).Median;
}

Times TimeOurs(vtkPolyData* mesh, int threads)
{
  return TimeFilter<vtkDiscreteCurvatures>(
    mesh, [threads](vtkDiscreteCurvatures* c) { c->SetNumberOfThreads(threads); });
}

vtkSmartPointer<vtkPolyData> ToPolyData(const beltrami::test::Mesh& m)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  for (beltrami::Index i = 0; i < m.NumberOfVertices(); ++i)
  {
    pts->InsertNextPoint(m.Points.data() + 3 * i);
  }
  vtkNew<vtkCellArray> tris;
  for (std::size_t t = 0; t < m.Triangles.size(); t += 3)
  {
    const vtkIdType ids[3] = { m.Triangles[t], m.Triangles[t + 1], m.Triangles[t + 2] };
    tris->InsertNextCell(3, ids);
  }
  pd->SetPoints(pts);
  pd->SetPolys(tris);
  return pd;
}

/// Mean relative error of a curvature array against an exact constant value.
double MeanRelativeError(vtkPolyData* pd, const char* name, double exact)
{
  vtkDataArray* a = pd->GetPointData()->GetArray(name);
  double sum = 0;
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
  {
    sum += std::abs(a->GetTuple1(i) - exact) / std::abs(exact);
  }
  return sum / a->GetNumberOfTuples();
}

void Timings(const char* label, vtkPolyData* mesh)
{
  std::printf("\n%s: %lld points, %lld triangles\n", label,
    static_cast<long long>(mesh->GetNumberOfPoints()), static_cast<long long>(mesh->GetNumberOfPolys()));
  const double vtkMean = TimeVTK(mesh, VTK_CURVATURE_MEAN);
  const double vtkGauss = TimeVTK(mesh, VTK_CURVATURE_GAUSS);
  const double vtkMax = TimeVTK(mesh, VTK_CURVATURE_MAXIMUM);
  const Times times1 = TimeOurs(mesh, 1);
  const Times times2 = TimeOurs(mesh, 2);
  const double ours1 = times1.Median, ours2 = times2.Median;
  std::printf("  vtkCurvatures Mean                    %8.3f s\n", vtkMean);
  std::printf("  vtkCurvatures Gaussian                %8.3f s\n", vtkGauss);
  std::printf("  vtkCurvatures Maximum                 %8.3f s\n", vtkMax);
  // The first run of a process also pays for faulting in fresh memory (about
  // 1 ms per MiB on machines where page faults are slow); later runs reuse
  // freed blocks (Core/Support/LargeBuffer.h).
  std::printf("  vtkDiscreteCurvatures, all outputs, 1 thread  %8.3f s (first run %.3f s)\n", ours1,
    times1.First);
  std::printf("  vtkDiscreteCurvatures, all outputs, 2 threads %8.3f s (first run %.3f s)\n", ours2,
    times2.First);
  std::printf("  ratio vtkCurvatures(Maximum) / ours(all, 1 thread):  %6.1fx\n", vtkMax / ours1);
  std::printf("  ratio vtkCurvatures(Maximum) / ours(all, 2 threads): %6.1fx\n", vtkMax / ours2);
  std::printf("  ratio vtkCurvatures(Mean+Gauss+Max) / ours(all, 2 threads): %6.1fx\n",
    (vtkMean + vtkGauss + vtkMax) / ours2);
}

} // namespace

int main(int argc, char* argv[])
{
  // vtkCurvatures warns at every point of a noisy scan; keep the report readable.
  vtkObject::GlobalWarningDisplayOff();
  const std::string path = argc > 1 ? argv[1] : std::string(BELTRAMI_TEST_DATA_DIR) + "/bunny00.off";
  vtkNew<vtkOFFReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  if (reader->GetOutput()->GetNumberOfPoints() == 0)
  {
    std::fprintf(stderr, "cannot read %s\n", path.c_str());
    return 1;
  }
  std::printf("Beltrami curvature benchmark (median of %d runs)\n", Repeats);
  Timings("real mesh (bunny00)", reader->GetOutput());
  vtkNew<vtkLoopSubdivisionFilter> loop;
  loop->SetInputConnection(reader->GetOutputPort());
  loop->SetNumberOfSubdivisions(2);
  loop->Update();
  Timings("bunny00, Loop-subdivided twice", loop->GetOutput());

  std::printf("\nAccuracy on octahedral unit spheres (mean relative error, %%)\n");
  std::printf("  %8s | %-21s | %-21s | %-21s\n", "vertices", "ours (Meyer 2003)", "ours (Taubin 1995)",
    "vtkCurvatures");
  std::printf("  %8s | %10s %10s | %10s %10s | %10s %10s\n", "", "kappa_H", "kappa_G", "kappa_H",
    "kappa_G", "kappa_H", "kappa_G");
  for (int level = 3; level <= 6; ++level)
  {
    const auto sphere = ToPolyData(beltrami::test::OctahedronSphere(level));
    double err[3][2];
    for (int method = 0; method < 2; ++method)
    {
      vtkNew<vtkDiscreteCurvatures> c;
      c->SetInputData(sphere);
      c->SetMethod(method);
      c->Update();
      err[method][0] = MeanRelativeError(c->GetOutput(), "MeanCurvature", 1.0);
      err[method][1] = MeanRelativeError(c->GetOutput(), "GaussianCurvature", 1.0);
    }
    for (int type : { VTK_CURVATURE_MEAN, VTK_CURVATURE_GAUSS })
    {
      vtkNew<vtkCurvatures> c;
      c->SetInputData(sphere);
      c->SetCurvatureType(type);
      c->Update();
      const char* name = type == VTK_CURVATURE_MEAN ? "Mean_Curvature" : "Gauss_Curvature";
      // vtkCurvatures' sign convention may differ: take the better of +-1.
      err[2][type == VTK_CURVATURE_GAUSS] = std::min(MeanRelativeError(c->GetOutput(), name, 1.0),
        MeanRelativeError(c->GetOutput(), name, -1.0));
    }
    std::printf("  %8lld | %10.4f %10.4f | %10.4f %10.4f | %10.4f %10.4f\n",
      static_cast<long long>(sphere->GetNumberOfPoints()), 100 * err[0][0], 100 * err[0][1],
      100 * err[1][0], 100 * err[1][1], 100 * err[2][0], 100 * err[2][1]);
  }
  return 0;
}
