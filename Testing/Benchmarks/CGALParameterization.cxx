// The CGAL 5.5 side of benchmark_parameterization.py (built only when
// Debian's libcgal-dev is installed): DCP and DAP with a circle boundary
// (arc-length spacing), DCP on a square (CGAL's own corners) and LSCM (CGAL's natural conformal map, two pinned
// vertices) on an OFF mesh, each timed (best of `repeats`) and measured with
// the same mean angle and area distortions as vtkIntrinsicParameterization
// (per triangle the mean |angle_2D - angle_3D| in degrees, and
// |log((A_2D / sum A_2D) / (A_3D / sum A_3D))|, averaged over the
// triangles).  Prints one line per method: name seconds angle area.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/Circular_border_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_authalic_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_conformal_map_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Square_border_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Two_vertices_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>
#include <CGAL/Polygon_mesh_processing/measure.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

using Kernel = CGAL::Simple_cartesian<double>;
using Point2 = Kernel::Point_2;
using Point3 = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point3>;
using Halfedge = boost::graph_traits<Mesh>::halfedge_descriptor;
using Vertex = boost::graph_traits<Mesh>::vertex_descriptor;
using UVMap = Mesh::Property_map<Vertex, Point2>;
namespace SMP = CGAL::Surface_mesh_parameterization;

namespace
{
double Angle(double ax, double ay, double az, double bx, double by, double bz)
{
  const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
  return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), ax * bx + ay * by + az * bz);
}

/// Mean angle distortion (degrees) and mean |log area ratio| over the
/// triangles, as vtkIntrinsicParameterization measures them.
std::pair<double, double> MeanDistortions(const Mesh& mesh, UVMap uv)
{
  struct Triangle
  {
    double Angle, Area3, Area2;
  };
  std::vector<Triangle> triangles;
  double total3 = 0.0, total2 = 0.0;
  for (auto f : mesh.faces())
  {
    Vertex v[3];
    int k = 0;
    for (auto h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh))
    {
      v[k++ % 3] = mesh.target(h);
    }
    double d = 0.0;
    bool ok = true;
    for (int c = 0; c < 3; ++c)
    {
      const Point3 &p = mesh.point(v[c]), &q = mesh.point(v[(c + 1) % 3]), &r = mesh.point(v[(c + 2) % 3]);
      const Point2 &P = uv[v[c]], &Q = uv[v[(c + 1) % 3]], &R = uv[v[(c + 2) % 3]];
      const double a3 = Angle(q.x() - p.x(), q.y() - p.y(), q.z() - p.z(), r.x() - p.x(), r.y() - p.y(), r.z() - p.z());
      const double a2 = Angle(Q.x() - P.x(), Q.y() - P.y(), 0, R.x() - P.x(), R.y() - P.y(), 0);
      ok = ok && std::isfinite(a3) && std::isfinite(a2);
      d += std::abs(a2 - a3);
    }
    const double area3 = std::sqrt(CGAL::squared_area(mesh.point(v[0]), mesh.point(v[1]), mesh.point(v[2])));
    const double area2 = CGAL::area(uv[v[0]], uv[v[1]], uv[v[2]]); // signed
    if (ok && area3 > 0.0)
    {
      triangles.push_back({ d / 3.0 * 180.0 / M_PI, area3, area2 });
      total3 += area3;
      total2 += area2;
    }
  }
  double angle = 0.0, area = 0.0;
  for (const Triangle& t : triangles)
  {
    const double ratio = (t.Area2 / total2) / (t.Area3 / total3);
    angle += t.Angle;
    area += ratio > 0.0 ? std::abs(std::log(ratio)) : 50.0; // flipped: as vtkIntrinsicParameterization
  }
  const double n = static_cast<double>(triangles.size());
  return triangles.empty() ? std::make_pair(std::nan(""), std::nan("")) : std::make_pair(angle / n, area / n);
}

template <typename Parameterizer>
void Run(const char* name, Mesh& mesh, Halfedge border, int repeats, Parameterizer parameterizer)
{
  double best = 1e300;
  UVMap uv = mesh.add_property_map<Vertex, Point2>("v:uv").first;
  for (int r = 0; r < repeats; ++r)
  {
    const auto start = std::chrono::steady_clock::now();
    const SMP::Error_code err = SMP::parameterize(mesh, parameterizer, border, uv);
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (err != SMP::OK)
    {
      std::printf("%s failed %s\n", name, SMP::get_error_message(err));
      return;
    }
    best = std::min(best, t);
  }
  const std::pair<double, double> distortion = MeanDistortions(mesh, uv);
  std::printf("%s %.4f %.4f %.4f\n", name, best, distortion.first, distortion.second);
  std::fflush(stdout);
}
} // namespace

int main(int argc, char* argv[])
{
  if (argc < 2)
  {
    std::fprintf(stderr, "usage: %s mesh.off [repeats]\n", argv[0]);
    return 2;
  }
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 1;
  Mesh mesh;
  std::ifstream in(argv[1]);
  if (!(in >> mesh) || mesh.is_empty())
  {
    std::fprintf(stderr, "cannot read %s\n", argv[1]);
    return 1;
  }
  // The longest border: the outer boundary.
  Halfedge border = CGAL::Polygon_mesh_processing::longest_border(mesh).first;
  using Border = SMP::Circular_border_arc_length_parameterizer_3<Mesh>;
  Run("DCP", mesh, border, repeats, SMP::Discrete_conformal_map_parameterizer_3<Mesh, Border>());
  Run("DAP", mesh, border, repeats, SMP::Discrete_authalic_parameterizer_3<Mesh, Border>());
  Run("DCPsquare", mesh, border, repeats,
    SMP::Discrete_conformal_map_parameterizer_3<Mesh, SMP::Square_border_arc_length_parameterizer_3<Mesh>>());
  Run("LSCM", mesh, border, repeats, SMP::LSCM_parameterizer_3<Mesh, SMP::Two_vertices_parameterizer_3<Mesh>>());
  return 0;
}
