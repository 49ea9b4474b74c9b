#include "Remeshing/ConstrainedDelaunay.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cstdint>
#include <deque>
#include <utility>

namespace beltrami
{

namespace
{

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<Index, Kernel>;
using FaceInfo = CGAL::Triangulation_face_base_with_info_2<int, Kernel>; // nesting level, -1 unknown
using FaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel, FaceInfo>;
using DataStructure = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<Kernel, DataStructure,
  CGAL::No_constraint_intersection_requiring_constructions_tag>;

/// Nesting levels by a breadth-first walk from the infinite faces: +1 across
/// a constrained edge.
void MarkNesting(CDT& cdt)
{
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
  {
    f->info() = -1;
  }
  std::deque<std::pair<CDT::Face_handle, int>> queue = { { cdt.infinite_face(), 0 } };
  std::deque<std::pair<CDT::Face_handle, int>> next;
  while (!queue.empty())
  {
    // Faces of one level are flooded first; across constraints they seed the next level.
    while (!queue.empty())
    {
      auto [face, level] = queue.front();
      queue.pop_front();
      if (face->info() >= 0)
      {
        continue;
      }
      face->info() = level;
      for (int i = 0; i < 3; ++i)
      {
        const CDT::Face_handle neighbour = face->neighbor(i);
        if (neighbour->info() < 0)
        {
          const bool constrained = cdt.is_constrained(CDT::Edge(face, i));
          (constrained ? next : queue).push_back({ neighbour, level + (constrained ? 1 : 0) });
        }
      }
    }
    std::swap(queue, next);
  }
}

} // namespace

DomainTriangulation TriangulateDomain(const std::vector<double>& points, const std::vector<Index>& segments)
{
  DomainTriangulation out;
  const Index n = static_cast<Index>(points.size() / 2);
  std::vector<std::pair<Kernel::Point_2, Index>> input(n);
  for (Index i = 0; i < n; ++i)
  {
    input[i] = { Kernel::Point_2(points[2 * i], points[2 * i + 1]), i };
  }
  CDT cdt;
  cdt.insert(input.begin(), input.end());
  std::vector<CDT::Vertex_handle> handle(n);
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
  {
    handle[v->info()] = v;
  }
  if (static_cast<Index>(cdt.number_of_vertices()) != n)
  {
    out.Error = std::to_string(n - static_cast<Index>(cdt.number_of_vertices())) + " points coincide with others";
    return out;
  }
  try
  {
    for (std::size_t s = 0; s + 1 < segments.size(); s += 2)
    {
      cdt.insert_constraint(handle[segments[s]], handle[segments[s + 1]]);
    }
  }
  catch (const CDT::Intersection_of_constraints_exception&)
  {
    out.Error = "two boundary segments cross";
    return out;
  }
  for (std::size_t s = 0; s + 1 < segments.size(); s += 2)
  {
    if (!cdt.is_edge(handle[segments[s]], handle[segments[s + 1]]))
    {
      out.Error = "a point lies on a boundary segment";
      return out;
    }
  }
  MarkNesting(cdt);
  std::vector<std::uint8_t> used(n, 0);
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
  {
    if (f->info() % 2 == 1)
    {
      for (int k = 0; k < 3; ++k)
      {
        out.Triangles.push_back(f->vertex(k)->info());
        used[f->vertex(k)->info()] = 1;
      }
    }
  }
  for (Index i = 0; i < n; ++i)
  {
    if (!used[i])
    {
      out.Unused.push_back(i);
    }
  }
  return out;
}

} // namespace beltrami
