// Beltrami core: the level of additive Gaussian noise in data, from the data
// alone (denoising without hand-tuned parameters).
//
// Each estimator computes, per sample, a high-pass response that cancels
// linear data and turns white noise of deviation sigma into noise of a known
// deviation c sigma, and a gradient independent of that response (odd where
// the response is even).  Edges and texture add to the response; two robust
// steps keep them out: only the half of the samples with the smallest
// gradient count, and the median absolute response is used instead of the
// mean (sigma = median / 0.6745 / c).
//  - Images: Immerkaer's mask N = [1 -2 1] x [1 -2 1] (Immerkaer 1996, "Fast
//    noise variance estimation"), c = 6; Sobel gradient.
//  - Volumes: the same mask one dimension up, [1 -2 1]^3, c = sqrt(216);
//    central-difference gradient.
//  - Point data on meshes (a neighbour graph): r_i = f_i - mean_j f_j over
//    the neighbours, c = sqrt(1 + 1/n_i); the gradient is the least-squares
//    fit to the neighbours' values about their centroid (it does not read f_i).
// Flat data (a masked or padded background, clipped values) carry no noise:
// where some samples are at or next to them (a value equal to most of its
// neighbours), the estimate comes from the others; a skull-stripped MRI
// volume (three quarters of it 0) within 5% of the added noise, where the
// flat samples made it 0 before.  Clean piecewise-constant data stay at 0.
// Beyond about 2^18 (262,144) samples, all components together, rows
// (vertices) are taken at a regular stride: the median is as good (0.3% relative standard error), and
// big images and volumes need neither the time nor the memory of all.
// Camera, coffee and astronaut with added noise of 0.02-0.2: within 10% of
// the added noise (the originals' own noise, about 0.01 in coffee, counts
// too); see the tests for volumes and meshes.
#pragma once

#include "Flows/GraphFlow.h"
#include "Mesh/MeshTopology.h"
#include "Solvers/Partition.h"

#include <cstdint>

namespace beltrami
{

/// The noise level (standard deviation, in the units of the values) of an
/// image of `components` interleaved values per pixel: the mean over the
/// components.  0 for images smaller than 3 x 3 pixels.  The samples are
/// computed on numThreads threads (0: all), with the same result.  piece
/// (optional, collective): `grid` is a piece of a grid split over processes
/// (GridPiece); the estimate of the whole grid, the same on every process.
double EstimateImageNoise(const PixelGrid& grid, int components, const double* values, int numThreads = 0,
  const GridPiece* piece = nullptr);

/// The same for a 3D image (0 below 3 x 3 x 3 voxels).
double EstimateVolumeNoise(const VoxelGrid& grid, int components, const double* values, int numThreads = 0,
  const GridPiece* piece = nullptr);

/// The same for point data on a graph of `size` vertices (neighbours of i:
/// neighbors[offsets[i] .. offsets[i + 1]), points 3 doubles per vertex).
/// Vertices marked in `skip` (optional) and with fewer than 3 neighbours do
/// not count; 0 when fewer than 8 count.  split (optional, collective): a
/// graph split over processes (Solvers/Partition), every process's owned
/// rows counted, the median and the half of the samples taken over all of
/// them: the serial estimate (beyond the sample budget the stride runs over
/// the partition's global numbering, so the sampled rows differ).
double EstimateGraphNoise(Index size, const std::int64_t* offsets, const Index* neighbors, const double* points,
  int components, const double* values, const std::uint8_t* skip = nullptr, const Partition* split = nullptr);

/// A hash of a point's three coordinates (their bits, SplitMix64): the same
/// for a point wherever it lies in the numbering, so that a surface split
/// over processes samples and draws what the serial run does.
std::uint64_t PointHash(const double* point);

/// The noise of a surface's geometry (EstimateSurfaceNoise).
struct SurfaceNoise
{
  double Deviation = 0.0; ///< standard deviation of the points' normal displacements (length)
  int Rings = 0;          ///< the neighbourhoods' size in rings of edges (0: too few points)
  double MedianDihedral = 0.0; ///< degrees, between the normals of the triangles of an edge (median)
  /// The same estimate with every neighbourhood one ring wider (0: too few
  /// points).  White noise measures the same at both sizes; the shape's own
  /// variation, which the quadrics do not fit, grows with the neighbourhood.
  double WiderDeviation = 0.0;
  /// The estimate on the rings the median dihedral angle gives, before a
  /// crumpled surface's is measured again on wider ones (the scale of the
  /// tangential estimate, EstimateTangentialNoise, for their comparison).
  double LocalDeviation = 0.0;
};

/// The standard deviation of white noise along the normals of a triangle
/// mesh's points, from the geometry alone.  At each (sampled) point a
/// quadric height function z(u, v) over its k-ring (in the frame of the
/// ring's principal axes about the point) is fitted to the other points by
/// least squares, so the surface's own curvature cancels; the point's
/// height above the fit, divided by its noise gain sqrt(1 + sum w_j^2) (w_j
/// the fit's weights of its value at the point), is a sample of the noise,
/// and the median of their magnitudes / 0.6745 is the estimate, robust to
/// sharp features and corners (less than half the points).  A quadric fits
/// a neighbourhood only where it is a height field well beyond the noise:
/// noise comparable to the edge length crumples the 2-ring and the fit takes
/// up part of it (bunny00, noise of 2 edge lengths: a quarter of it
/// measured on 2-rings, all of it on 6-rings), while on a coarse mesh wider
/// rings add the shape's detail.  The rings follow how crumpled the mesh
/// is, by the median angle between the normals of adjacent triangles: below
/// 35 degrees 2 rings, below 45 3, below 52 4, else 6; from 45 degrees on
/// (noise of an edge length and more tilts the fits' frames, the principal
/// axes of their points) it is measured again at fewer points by fits on
/// 2-rings in the frame of the vector area of the 12-ring (the sum of its
/// triangles' area vectors, which the noise hardly tilts), and that
/// estimate kept where it is more than a tenth larger (the wider estimate
/// then the same).  On a coarse mesh whose shape varies at the scale of its
/// triangles, that detail counts as noise (elephant: 0.13% of the diagonal
/// without noise).  Points marked in `skip` and points with fewer than 9 others in
/// the ring do not count; beyond 2^15 points they are sampled (by PointHash).  split (optional, collective): a surface split over processes,
/// each with the stars of the points it owns; a point counts where its
/// whole k-ring is on its owner (an estimate close to the serial one).
SurfaceNoise EstimateSurfaceNoise(const MeshTopology& topology, const double* points,
  const std::uint8_t* skip = nullptr, const Partition* split = nullptr, int numThreads = 0);

/// The standard deviation, per direction, of white noise in the tangent
/// planes of a triangle mesh's points (the rest of an isotropic noise:
/// a scan's points displaced in every direction, not only along the
/// normals).  At each (sampled, as EstimateSurfaceNoise's) interior point,
/// the part in its tangent plane (`normals`: 3 per point, unit) of the move
/// to the centroid of its k neighbours over its noise gain 1 + 1/k, whose
/// median square is 2 ln 2 times the variance.  An irregular sampling
/// counts as tangential noise (the corpus' clean meshes: 0.03-0.17 of their
/// mean edge length).  0 with fewer than 8 points.
double EstimateTangentialNoise(const MeshTopology& topology, const double* points, const double* normals,
  const std::uint8_t* skip = nullptr, const Partition* split = nullptr);

} // namespace beltrami
