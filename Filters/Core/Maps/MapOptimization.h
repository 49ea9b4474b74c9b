// Beltrami core, private to Maps/: the optimisations of thesis section 5.5
// over a computed map: the optimal mix of the conformal and authalic maps
// (5.5.1: the energy along the blend is a polynomial, minimised exactly) and
// gradient descent on the boundary points through the boundary basis (5.5.2).
#pragma once

#include "Maps/Parameterization.h"

#include <vector>

namespace beltrami::detail
{

/// Finds the minimum over [a, b] of the polynomial with coefficients `p`
/// (p[k] multiplies x^k): the derivative's roots by sign changes on a fine
/// grid refined by bisection, and the ends.
double MinimizePolynomial(const std::vector<double>& p, double a, double b);

/// Coefficients in l of the energy of U = U_chi + l (U_A - U_chi), u -> s u.
std::vector<double> MixEnergyPolynomial(const MeshTopology& topo, const double* points,
  const double* uvA, const double* uvX, double s, DistortionEnergy energy);

/// Gradient descent on the boundary points (section 5.5.2).
void OptimizeBoundary(const MeshTopology& topo, const double* points, const BoundaryBasis& basis,
  const ParameterizationOptions& options, std::vector<double>& uv, ParameterizationResult& result);

} // namespace beltrami::detail
