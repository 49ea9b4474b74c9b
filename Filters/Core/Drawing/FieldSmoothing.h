// Beltrami core: the smoothing of a line drawing's curvature fields.
//
// On raw scans the noise of the triangles draws contours and suggestive
// contours as short dashes: the fields the lines are zero sets of (the
// normals, the principal curvatures and directions, their derivatives)
// vary at the scale of the triangles.  Measured on a copy of the surface
// faired by one implicit curvature-flow step (Flows/Fairing.h, eq. 3.9 and
// 3.13) of time (Amount x FeatureSize)^2, they keep the shape's lines and
// lose the noise's: the flow moves points by half the Laplacian of their
// positions, so the step divides a bump of wavelength w by
// 1 + 2 (pi Amount FeatureSize / w)^2: with Amount 0.5 a bump one feature
// size wide keeps a sixth of its height, one ten feature sizes wide 95%.
#pragma once

#include "Mesh/MeshTopology.h"

#include <string>
#include <vector>

namespace beltrami
{

class Partition;

/// A copy of `points` (3 per vertex) faired by one implicit step of the
/// curvature flow of time length^2 (boundaries fixed, no volume scaling:
/// each point moves with its neighbourhood alone).  The copy is faired at
/// a scale of the length by a power of two (exact), so that huge and tiny
/// coordinates are smoothed alike.  Split (collective): the owned points'
/// copies are those of a serial run, to the solver's tolerance, and the
/// ghosts' their owners'.  Empty where the fairing cannot run (`warning`
/// says why).
std::vector<double> FairedCopy(const MeshTopology& topology, const double* points, double length, int numThreads,
  const Partition* split, std::string& warning);

} // namespace beltrami
