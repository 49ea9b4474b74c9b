// Beltrami core, private to Flows/: the anisotropic, feature-preserving
// weights of thesis section 3.7.1 and the feature curves they find, for
// FairSurface.
#pragma once

#include "Flows/Fairing.h"
#include "Mesh/Geometry.h"
#include "Solvers/Partition.h"

#include <vector>

namespace beltrami::detail
{

/// Section 3.7.1: w = 1 in noisy regions, 0 at corners, kappa_min / kappa_H on
/// edges, clamped below.  `along` receives, for edge vertices, the principal
/// direction of the smaller curvature (along the edge); zero elsewhere.
/// Distributed (`split`): the weights of the owned points (the ghosts' are
/// their owners' business), `featureVertices` counted over all processes.
std::vector<double> AnisotropicWeights(const MeshTopology& topo, const double* x,
  const FairingOptions& opt, std::vector<Vec3>* along, Index& featureVertices, const Partition* split = nullptr);

/// Feature curves for the curve-smoothing pass: edges between edge vertices
/// that run along both vertices' edge directions (within 30 degrees); only
/// vertices with exactly two such edges are smoothed.  Distributed (`along`
/// of the ghosts their owners'), the chains at the owned points are whole:
/// a ghost's missing edges only change whether a ghost is on a curve, and
/// its row is its owner's.
void FeatureChains(const MeshTopology& topo, const double* x, const std::vector<Vec3>& along,
  std::vector<std::vector<Index>>& chains, std::vector<std::uint8_t>& onCurve);

} // namespace beltrami::detail
