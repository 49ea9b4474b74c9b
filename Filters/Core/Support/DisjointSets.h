// Beltrami core: the root of a union-find forest (disjoint sets as parent
// links), shared by the topology builder, the distributed parameterization
// and the remesher's squeezed parts.
#pragma once

#include "Support/Parallel.h"

#include <vector>

namespace beltrami
{

/// The root of `a` in the forest `parent` (a root is its own parent), with
/// path halving.
inline Index FindRoot(std::vector<Index>& parent, Index a)
{
  while (parent[a] != a)
  {
    parent[a] = parent[parent[a]];
    a = parent[a];
  }
  return a;
}

} // namespace beltrami
