// Beltrami core: a bounding-volume hierarchy of a surface's triangles for
// ray (segment) queries: whether anything lies between a point and an eye.
#pragma once

#include "Mesh/Geometry.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace beltrami
{

class TriangleTree
{
public:
  /// `points`: 3 per vertex; `triangles`: 3 vertex ids each (triangles with
  /// a vertex that is not finite are left out).  Both are referenced, not
  /// copied: they must outlive the tree.  Built on `numThreads` threads (0:
  /// all), the same tree whatever their number.
  TriangleTree(const double* points, const Index* triangles, std::size_t numberOfTriangles, int numThreads = 1);
  /// Whether the segment origin + t direction, tmin < t < 1, passes through
  /// a triangle that `ignore` (asked only of the triangles it meets) does
  /// not rule out.  Closed triangles, their edges widened by 1e-9 of their
  /// barycentric range so that no ray slips between two.
  bool Blocks(const Vec3& origin, const Vec3& direction, double tmin,
    const std::function<bool(Index triangle)>& ignore) const;

private:
  /// A box (single precision, rounded outwards) and either two children
  /// (Count 0: nodes First and First + 1) or a leaf's triangles
  /// Order[First .. First + Count).
  struct Node
  {
    float Lo[3], Hi[3];
    std::int32_t First = 0, Count = 0;
  };
  /// A range of Order [Begin, End) whose subtree grows from node Node.
  struct Subtree
  {
    std::int32_t Node, Begin, End;
  };
  /// The top-down median splits (Grow: the subtree of Order [first, last)
  /// appended to `nodes`, its root first; Order's ranges of disjoint calls
  /// may be sorted concurrently).
  struct Builder
  {
    const std::vector<double>& Boxes;
    const std::vector<Index>& Slot;
    std::vector<Index>& Order;
    void Grow(std::vector<Node>& nodes, std::int32_t first, std::int32_t last, std::int32_t chunk,
      std::vector<Subtree>& deferred) const;
  };
  const double* Points;
  const Index* Triangles;
  std::vector<Node> Nodes;
  std::vector<Index> Order;
};

} // namespace beltrami
