// Beltrami core: the constrained Delaunay triangulation of a planar point set
// inside a polygonal domain (thesis section 4.4.1), over CGAL 5.5's
// Constrained_Delaunay_triangulation_2 with exact predicates and inexact
// constructions (a robust CDT is a project of its own; CGAL is header-only on
// Debian).  Only this file's implementation sees CGAL: it is compiled with
// -frounding-math, which CGAL's interval filters need.
#pragma once

#include "Support/Parallel.h"

#include <string>
#include <vector>

namespace beltrami
{

struct DomainTriangulation
{
  std::string Error;              ///< non-empty: no triangles
  std::vector<Index> Triangles;   ///< 3 point ids per triangle, counter-clockwise
  std::vector<Index> Unused;      ///< points in no kept triangle (outside the domain)
};

/// Triangulates `points` (2 per point) with the segments `segments` (2 point
/// ids each) as edges, and keeps the triangles inside the domain they bound:
/// those reached from outside across an odd number of segments.  No point is
/// added: coincident points, segments that cross or pass through a point are
/// an error.
DomainTriangulation TriangulateDomain(const std::vector<double>& points, const std::vector<Index>& segments);

} // namespace beltrami
