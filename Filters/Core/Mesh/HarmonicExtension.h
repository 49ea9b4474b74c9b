// Beltrami core: carrying point data to new vertices.  Values known at some
// vertices (the input points of a tetrahedral mesh, the samples of a
// remeshed surface that fall on old vertices) are extended to the others by
// the discrete harmonic extension: (K u)_i = 0 at every unknown vertex, K the
// stiffness of a Laplacian from the shared assembler (the cotangent Laplacian
// of a surface, the volume Laplacian of a tetrahedral mesh).  Both have
// linear precision, so a linear field is reproduced exactly where the mesh
// is a Delaunay-like (non-negative weight) triangulation of a flat or
// straight region.
#pragma once

#include "Mesh/Laplacian.h"

#include <cstdint>

namespace beltrami
{

struct HarmonicExtensionReport
{
  int Iterations = 0;     ///< conjugate-gradient iterations, summed over the column blocks
  bool Converged = true;  ///< every block reached the tolerance
};

/// values: `columns` interleaved values per vertex of `laplacian`'s graph;
/// rows with known[i] != 0 keep their values, the others are replaced by the
/// harmonic extension (initial guess: their values on entry).  Any number of
/// columns (solved 8 at a time); tolerance: the residual reduction.
HarmonicExtensionReport ExtendHarmonically(const GraphLaplacian& laplacian, const std::uint8_t* known,
  int columns, double* values, double tolerance = 1e-12, int maximumIterations = 5000, int numThreads = 0);

} // namespace beltrami
