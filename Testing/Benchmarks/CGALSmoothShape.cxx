// The CGAL 5.5 side of benchmark_fairing.py (built only when Debian's
// libcgal-dev is installed): CGAL::Polygon_mesh_processing::smooth_shape
// (implicit mean-curvature flow) on an OFF mesh.
//   usage: beltrami-benchmark-cgal-smooth-shape in.off time iterations [out.off]
// Prints "seconds"; writes the smoothed mesh to out.off if given.
#include <CGAL/Polygon_mesh_processing/smooth_shape.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>

using Kernel = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;

int main(int argc, char* argv[])
{
  if (argc < 4)
  {
    std::fprintf(stderr, "usage: %s in.off time iterations [out.off]\n", argv[0]);
    return 2;
  }
  Mesh mesh;
  std::ifstream in(argv[1]);
  if (!(in >> mesh) || mesh.is_empty())
  {
    std::fprintf(stderr, "cannot read %s\n", argv[1]);
    return 1;
  }
  const double time = std::atof(argv[2]);
  const unsigned iterations = static_cast<unsigned>(std::atoi(argv[3]));
  const auto start = std::chrono::steady_clock::now();
  CGAL::Polygon_mesh_processing::smooth_shape(
    mesh, time, CGAL::parameters::number_of_iterations(iterations));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%.4f\n", seconds);
  if (argc > 4)
  {
    std::ofstream out(argv[4]);
    out << std::setprecision(17) << mesh;
  }
  return 0;
}
