// Beltrami core: the remesh being built (thesis section 4.4): an editable
// triangle mesh (Mesh/HalfEdgeMesh) over the samples of
// Remeshing/SurfaceSampling, where every vertex knows where it lies on the
// input surface (a triangle and barycentric weights: positions are lifted
// through the input, never through a sampled embedding map) and every face
// the chart it was triangulated in, with its corners' positions in that
// chart's parameter plane.  Vertices on chart boundaries (seams, features,
// the surface's boundary) also know their path and arc length, so that they
// only ever slide along it.
#pragma once

#include "Maps/Atlas.h"
#include "Mesh/HalfEdgeMesh.h"
#include "Remeshing/SurfaceSampling.h"

#include <string>
#include <vector>

namespace beltrami
{

struct Remesh
{
  std::string Error;               ///< non-empty: no mesh
  HalfEdgeMesh Mesh;               ///< vertices = samples (same ids), on the input surface
  std::vector<int> FaceChart;      ///< per face: the chart it lies in
  std::vector<double> CornerUV;    ///< 2 per half-edge: its tail vertex in the face's chart (the chart's own square)
  std::vector<Index> Triangle;     ///< per vertex: the input triangle it lies on
  std::vector<double> Barycentric; ///< 3 per vertex: weights of that triangle's corners
  std::vector<SampleKind> Kind;    ///< per vertex
  std::vector<int> Path;           ///< per vertex: the path of a Boundary vertex (SurfaceSamples::Paths), else -1
  std::vector<double> Arc;         ///< per vertex: its arc length along that path
};

/// The position in `chart`'s own square of the surface point at `triangle`,
/// `barycentric`; false unless every vertex with a non-zero weight is in the
/// chart (true for a point of a chart triangle or of the chart's boundary).
bool ChartPosition(const MeshTopology& topology, const AtlasChart& chart, Index triangle, const double* barycentric,
  double* uv);

/// The surface point at (triangle, barycentric weights).
Vec3 SurfacePoint(const MeshTopology& topology, const double* points, Index triangle, const double* barycentric);

/// Mesh creation (section 4.4.1): the constrained Delaunay triangulation of
/// every chart's samples in its parameter plane, with the sample paths along
/// its boundary as constraints (Remeshing/ConstrainedDelaunay), joined along
/// the shared boundary samples into one mesh: watertight, with the input's
/// topology.  An interior sample that falls outside its chart's polygon of
/// boundary samples is moved to the nearest triangle inside (located by
/// the charts' locators of `cache`, built there when it has none).
Remesh CreateRemesh(const MeshTopology& topology, const double* points, const AtlasResult& atlas,
  const SurfaceSamples& samples, int numThreads = 0, RemeshCache* cache = nullptr);

} // namespace beltrami
