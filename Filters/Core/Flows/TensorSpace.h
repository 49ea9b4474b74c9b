// Beltrami core: the log-Euclidean representation of symmetric positive
// definite tensor fields (Arsigny, Fillard, Pennec and Ayache 2006), in
// which the graph flows smooth diffusion tensors and other SPD fields: the
// flow averages matrix logarithms, so every result is positive definite
// (the exponential of a symmetric matrix) and averaging does not swell the
// tensors (the determinant of a mean is the geometric mean of the
// determinants; a field of equal determinants keeps it exactly).
//
// Tensors are VTK's 6-component symmetric layout (XX, YY, ZZ, XY, YZ, XZ).
// The log coordinates are (L_xx, L_yy, L_zz, sqrt2 L_xy, sqrt2 L_yz,
// sqrt2 L_xz), so that their Euclidean norm is the Frobenius norm of the
// logarithm: the Beltrami metric then sees the log-Euclidean distance.
#pragma once

#include "Support/Parallel.h"

namespace beltrami
{

class Partition;

/// In place: `count` tensors, the 6 values of every `stride` values, to log
/// coordinates.  Eigenvalues below `floor` times the largest eigenvalue of
/// the field (not positive definite, or nearly) are raised to it; returns
/// how many tensors were (0: all positive definite enough).  split
/// (optional, collective): the tensors are the rows of a piece of a mesh
/// split over processes (ghost rows too): the largest eigenvalue and the
/// count are those of the whole field.
std::int64_t SymmetricTensorsToLog(double* values, std::int64_t count, int stride, double floor = 1e-6,
  int numThreads = 0, const Partition* split = nullptr);
/// The inverse of SymmetricTensorsToLog: the matrix exponential.
void LogToSymmetricTensors(double* values, std::int64_t count, int stride, int numThreads = 0);

} // namespace beltrami
