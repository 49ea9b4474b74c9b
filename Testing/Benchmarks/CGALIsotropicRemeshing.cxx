// The CGAL 5.5 side of benchmark_remeshing.py (built only when Debian's
// libcgal-dev is installed): CGAL::Polygon_mesh_processing::isotropic_remeshing
// on an OFF mesh, with the edges sharper than `angle` degrees
// (detect_sharp_edges; 0: none) kept as constrained polylines.
//   usage: beltrami-benchmark-cgal-isotropic-remeshing in.off target_edge_length iterations angle out.off
// Prints "seconds" (sharp-edge detection and remeshing); writes the remesh.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

int main(int argc, char* argv[])
{
  if (argc < 6)
  {
    std::fprintf(stderr, "usage: %s in.off target_edge_length iterations angle out.off\n", argv[0]);
    return 2;
  }
  Mesh mesh;
  std::ifstream in(argv[1]);
  if (!(in >> mesh) || mesh.is_empty())
  {
    std::fprintf(stderr, "cannot read %s\n", argv[1]);
    return 1;
  }
  const double target = std::atof(argv[2]);
  const unsigned iterations = static_cast<unsigned>(std::atoi(argv[3]));
  const double angle = std::atof(argv[4]);
  const auto start = std::chrono::steady_clock::now();
  auto sharp = mesh.add_property_map<Mesh::Edge_index, bool>("e:sharp", false).first;
  if (angle > 0.0)
  {
    PMP::detect_sharp_edges(mesh, angle, sharp);
  }
  PMP::isotropic_remeshing(faces(mesh), target, mesh,
    CGAL::parameters::number_of_iterations(iterations).edge_is_constrained_map(sharp));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%.4f\n", seconds);
  mesh.collect_garbage();
  std::ofstream out(argv[5]);
  out << std::setprecision(17) << mesh;
  return 0;
}
