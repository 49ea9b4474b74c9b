// Benchmark: tetrahedra per second through vtkTetGenTetrahedralizer against
// calling TetGen (libtet 1.5) directly with the same switches on the same
// closed surfaces, and the filter's overhead (TetGen runs in a helper
// process there: Core/Support/HelperProcess.h).  Run on demand, not a test:
//   build/bin/beltrami-benchmark-tetgen [surface.off ...]
#include "vtkOFFReader.h"
#include "vtkTetGenTetrahedralizer.h"

#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#define TETLIBRARY
#include <tetgen.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace
{

constexpr int Repeats = 7;

template <typename F>
double Seconds(F&& run)
{
  const auto start = std::chrono::steady_clock::now();
  run();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double Median(std::vector<double> t)
{
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

/// What a user calling TetGen directly writes: the triangles as facets.
void FillInput(vtkPolyData* surface, tetgenio& in)
{
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(surface->GetNumberOfPoints());
  in.pointlist = new REAL[3 * in.numberofpoints];
  for (int i = 0; i < in.numberofpoints; ++i)
  {
    surface->GetPoint(i, in.pointlist + 3 * i);
  }
  in.numberoffacets = static_cast<int>(surface->GetNumberOfPolys());
  in.facetlist = new tetgenio::facet[in.numberoffacets];
  vtkIdType n;
  const vtkIdType* ids;
  int f = 0;
  for (surface->GetPolys()->InitTraversal(); surface->GetPolys()->GetNextCell(n, ids); ++f)
  {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = static_cast<int>(n);
    facet.polygonlist[0].vertexlist = new int[n];
    for (vtkIdType k = 0; k < n; ++k)
    {
      facet.polygonlist[0].vertexlist[k] = static_cast<int>(ids[k]);
    }
  }
}

int RunTetGen(vtkPolyData* surface, const std::string& switches)
{
  tetgenio in, out;
  FillInput(surface, in);
  std::vector<char> s(switches.begin(), switches.end());
  s.push_back('\0');
  tetrahedralize(s.data(), &in, &out);
  return out.numberoftetrahedra;
}

} // namespace

int main(int argc, char* argv[])
{
  std::vector<std::string> files;
  for (int a = 1; a < argc; ++a)
  {
    files.emplace_back(argv[a]);
  }
  if (files.empty())
  {
    files = { std::string(BELTRAMI_TEST_DATA_DIR) + "/bunny00.off",
      std::string(BELTRAMI_TEST_DATA_DIR) + "/elephant.off" };
  }
  std::printf("TetGen benchmark (median of %d interleaved runs, default filter settings)\n", Repeats);
  for (const std::string& file : files)
  {
    vtkNew<vtkOFFReader> reader;
    reader->SetFileName(file.c_str());
    reader->Update();
    vtkPolyData* surface = reader->GetOutput();
    vtkNew<vtkTetGenTetrahedralizer> filter;
    filter->SetInputData(surface);
    const std::string switches = filter->GetSwitches();
    // Interleaved runs: the machine's speed drifts between runs (shared
    // machines), both sides see the same drift.
    int tets = 0;
    std::vector<double> direct, ours;
    for (int r = 0; r < Repeats; ++r)
    {
      direct.push_back(Seconds([&]() { tets = RunTetGen(surface, switches); }));
      ours.push_back(Seconds([&]() {
        filter->Modified();
        filter->Update();
      }));
    }
    const vtkIdType ourTets = filter->GetOutput()->GetNumberOfCells();
    std::printf("\n%s: %lld points, %lld triangles, switches '%s'\n", file.c_str(),
      static_cast<long long>(surface->GetNumberOfPoints()),
      static_cast<long long>(surface->GetNumberOfPolys()), switches.c_str());
    const double t0 = Median(direct), t1 = Median(ours);
    std::printf("  TetGen directly               %8.3f s  %8d tetrahedra  %10.0f tetrahedra/s\n", t0, tets,
      tets / t0);
    std::printf("  vtkTetGenTetrahedralizer      %8.3f s  %8lld tetrahedra  %10.0f tetrahedra/s\n", t1,
      static_cast<long long>(ourTets), ourTets / t1);
    std::printf("  overhead of the filter: %.1f%% (its first run, which starts the helper process: %.3f s)\n",
      100.0 * (t1 / t0 - 1.0), ours.front());
  }
  return 0;
}
