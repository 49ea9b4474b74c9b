// Beltrami core: line drawings of a triangle surface: contours,
// suggestive contours and highlights (DeCarlo, Finkelstein, Rusinkiewicz &
// Santella 2003; DeCarlo & Rusinkiewicz 2007), ridges and valleys,
// apparent ridges (Judd, Durand & Adelson 2007: Drawing/ApparentRidges.h),
// boundaries and creases, chained into polylines.
//
// Two passes:
//  - LineDrawingGeometry::Build, view independent and kept between views:
//    the curvature tensors of chapter 2 (ComputeCurvatures), their
//    derivatives (ComputeCurvatureDerivatives), the boundary edges and
//    each vertex's sharpest edge; the crease edges of a crease angle and
//    the ridge and valley candidates when first asked for;
//  - DrawLines, per view: n.v, the radial curvature kappa_r and its
//    derivative D_r kappa_r at the vertices, their zero sets on the faces
//    (interpolated inside the triangles, not along mesh edges), the tests
//    applied by clipping each segment where its tested quantity crosses its
//    threshold, and the segments chained into polylines.
//
// Conventions: normals point out of the surface as the triangles' orientation
// says, kappa > 0 where the surface bends away from its normal (a sphere with
// outward normals).  v is the unit vector from the surface to the camera, w
// its projection onto the tangent plane, r = w/|w|, theta the angle between n
// and v.  kappa_r = II(r, r), and along r (v taken as locally constant, as
// DeCarlo et al. do) D_r kappa_r = C(r,r,r) - 2 cot(theta) tau^2, tau =
// II(r, r x n) the geodesic torsion: at kappa_r = 0 this is their
// C(r,r,r) + 2 K cot(theta).
#pragma once

#include "Mesh/Geometry.h"
#include "Mesh/MeshTopology.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace beltrami
{

class Partition;
struct OcclusionIndex;

enum class LineType : std::uint8_t
{
  Contour = 0,             ///< n.v = 0
  SuggestiveContour = 1,   ///< kappa_r = 0, D_r kappa_r > 0
  SuggestiveHighlight = 2, ///< kappa_r = 0, D_r kappa_r < 0
  Ridge = 3,               ///< D_e1 kappa_1 = 0, a maximum along e1, kappa_1 > threshold
  Valley = 4,              ///< D_e2 kappa_2 = 0, a minimum along e2, kappa_2 < -threshold
  Boundary = 5,            ///< edges of one triangle
  Crease = 6,              ///< edges whose dihedral angle exceeds the crease angle
  ApparentRidge = 7        ///< D_t1 q1 = 0, a maximum along t1, q1 > threshold (Drawing/ApparentRidges.h)
};
constexpr int NumberOfLineTypes = 8;

/// The camera: a position (perspective) or a direction of projection
/// (orthographic: the direction the camera looks along).
struct LineView
{
  bool Perspective = true;
  Vec3 Position = Vec3(0, 0, 1);
  Vec3 Direction = Vec3(0, 0, -1);
};

/// Which parts of the lines a drawing keeps (Drawing/Visibility.h).
enum class LineVisibility : std::uint8_t
{
  All = 0,             ///< every part, seen or not (hidden lines left to a renderer's depth test)
  Visible = 1,         ///< the parts seen from the camera
  VisibleAndHidden = 2 ///< both, the hidden parts marked (LineSet::Hidden)
};

struct LineDrawingOptions
{
  /// Which line types to draw, by LineType.
  bool Draw[NumberOfLineTypes] = { true, true, false, false, false, true, true, false };
  /// The length that makes the thresholds scale-free; 0: automatic (1% of
  /// the bounding-box diagonal).
  double FeatureSize = 0.0;
  /// The normals and curvatures are measured on a copy of the surface
  /// faired over this many FeatureSize (Drawing/FieldSmoothing.h; 0: on the
  /// surface itself); the lines lie on the surface.  Applied by the
  /// view-independent pass (the caller passes it to Build).
  double CurvatureSmoothing = 0.5;
  /// Suggestive contours (highlights) are drawn where D_r kappa_r (its
  /// negative) times FeatureSize^2 exceeds this ...
  double SuggestiveThreshold = 0.1;
  /// ... and where the surface turns at least this angle (degrees) away from
  /// the viewer: near theta = 0 the radial direction is unstable.
  double SuggestiveAngle = 15.0;
  /// Ridges (valleys) where kappa_1 (-kappa_2) times FeatureSize exceeds this.
  double RidgeThreshold = 0.4;
  /// Apparent ridges where the view-dependent curvature q1 times
  /// FeatureSize exceeds this.
  double ApparentRidgeThreshold = 1.0;
  /// Creases where the normals of an edge's two triangles differ by more
  /// than this (degrees; above VTK's 30 so that coarse organic meshes do
  /// not draw their tessellation).
  double CreaseAngle = 40.0;
  /// Suggestive contours and highlights, ridges, valleys and apparent ridges are left out of
  /// the triangles at a crease vertex (an end of an edge sharper than
  /// CreaseAngle): there the curvature estimates see the crease itself
  /// (huge and arbitrary in direction), not the smooth surface on its two
  /// sides, and CAD parts got suggestive contours along their creases.
  bool AvoidCreases = true;
  /// Drop the pieces of every type but contours where n.v < 0.
  bool DropBackFacing = true;
  /// Lines of every type but boundaries and creases whose polylines are
  /// shorter than this many FeatureSize are dropped (0: all kept): on raw
  /// scans the noise breaks the curvature lines into short pieces and draws
  /// small contour loops around its bumps.
  double MinimumLength = 2.0;
  /// Hysteresis of the curvature lines' thresholds (in (0, 1]; 1: none):
  /// suggestive contours and highlights, ridges, valleys and apparent ridges are traced
  /// down to this fraction of their thresholds, and a polyline is kept if
  /// its strength passes the full threshold somewhere (Canny's rule: on
  /// scans the noise breaks a line wherever it dips below the threshold).
  double HysteresisRatio = 0.5;
  /// Which parts to keep: every part, or split where the lines pass behind
  /// the surface (SplitByVisibility, applied by the caller).
  LineVisibility Visibility = LineVisibility::All;
  int NumberOfThreads = 0;
};

/// One end of a segment: on a mesh edge (Key identifies it, so that the
/// segments of neighbouring faces join there), on a vertex, or inside a face
/// where a test clipped it (Key -1); W: barycentric weights in Face.
struct LineEnd
{
  std::int64_t Key = -1;
  double W[3] = { 0, 0, 0 };
};
struct LineSegment
{
  Index Face = 0;
  LineEnd End[2];
};
/// The segments of a whole surface (a large array: see LargeBuffer.h).
using SegmentList = LargeVector<LineSegment>;

/// The view-independent pass' smoothing of the curvature fields
/// (Drawing/FieldSmoothing.h).
struct FieldSmoothingOptions
{
  /// The normals, curvatures and their derivatives are measured on a copy
  /// of the surface faired over Amount feature sizes, and the lines placed
  /// on the surface itself (0: measured on the surface).
  double Amount = 0.0;
  double FeatureSize = 0.0; ///< 0: the automatic one
};

/// The view-independent pass, kept while only the view or thresholds change.
class LineDrawingGeometry
{
public:
  /// Builds everything from a topology and its points (3 per vertex).
  /// Split over processes (`split`: the topology's points, a piece and the
  /// whole stars of its points, as the curvatures need; collective), the
  /// ghost points take their owners' curvatures and derivatives, the feature
  /// size is the whole surface's, and each face, boundary and crease edge is
  /// drawn by one process (Partition::CountsTriangle, CountsEdge): DrawLines
  /// then gathers the segments and chains them on process 0.
  /// With `smoothing`, the fields are measured on a faired copy (creases
  /// are still found on the surface); where the fairing cannot run, on the
  /// surface, and SmoothingWarning says why.
  template <typename T>
  void Build(const MeshTopology& topology, const T* points, int numThreads = 0,
    std::shared_ptr<const Partition> split = nullptr, const FieldSmoothingOptions& smoothing = {});

  Index NumberOfVertices() const { return static_cast<Index>(K1.size()); }
  Index NumberOfFaces() const { return static_cast<Index>(Triangles.size() / 3); }
  double AutomaticFeatureSize() const { return DefaultFeatureSize; }

  IndexArray Triangles; ///< the topology's kept triangles
  /// (Each written whole by the pass that makes it: no zeros written first.)
  UninitializedVector<double> Points, Normals, K1, K2, E1, E2;
  UninitializedVector<double> Derivatives; ///< 4 per vertex: see ComputeCurvatureDerivatives
  /// Vertices of triangles whose curvature is undefined (boundary,
  /// non-manifold, NaN or degenerate 1-rings; over all processes).
  Index UndefinedVertices = 0;
  /// Non-empty where the smoothing asked for could not run.
  std::string SmoothingWarning;
  /// Whether the fields were measured on a faired copy, FairedPoints (3 per
  /// vertex), or on the surface itself.
  bool Smoothed = false;
  UninitializedVector<double> FairedPoints;
  /// The points the normals, curvatures and view fields belong to: the
  /// lines are their zero sets on this surface (visibility included), drawn
  /// at the same places of the triangles of Points.
  const double* FieldPoints() const { return Smoothed ? FairedPoints.data() : Points.data(); }
  /// Split runs: the points over the processes, and per face whether this
  /// process draws it (empty: not split, every face).
  std::shared_ptr<const Partition> Split;
  std::vector<std::uint8_t> DrawnFaces;
  bool Draws(Index f) const { return DrawnFaces.empty() || DrawnFaces[f] != 0; }
  /// The id of vertex v in the keys of segment ends (split: its global row).
  std::int64_t KeyId(Index v) const { return Split ? GlobalIds[v] : v; }
  /// How many ids KeyId gives (the points of the whole surface).
  std::int64_t NumberOfKeyIds() const { return Split ? KeyIds : NumberOfVertices(); }
  /// Candidates, before thresholds and the view: boundary edges (ridges and
  /// valleys: RidgeCandidates).
  SegmentList BoundaryEdges;
  /// Per vertex: the smallest cosine of the angle between the normals of
  /// two of its triangles that share an edge (1 without such edges;
  /// NormalCosine, in single precision).
  LargeVector<float> SharpestCosine;
  /// Fields measured on a faired copy: per vertex the smallest
  /// SharpestCosine within as many rings as the smoothing's length spans
  /// (AtCrease's test; empty: SharpestCosine's).
  LargeVector<float> NearSharpestCosine;
  /// The cosine of a crease angle (degrees): edges whose cosine is below
  /// it are creases.
  static float CreaseCosine(double angle);
  /// The edges of two triangles sharper than the crease angle (degrees)
  /// that this process draws, in (vertex, neighbour) order, and their
  /// angles (degrees): found on the first call for an angle from the
  /// vertices' SharpestCosine, then kept (not for concurrent calls on one
  /// geometry).
  struct CreaseList
  {
    bool Valid = false;
    float Cosine = 0.0f;
    SegmentList Edges;
    std::vector<double> Angles;
  };
  const CreaseList& Creases(double angle) const;
  /// Whether face f has a vertex with an edge sharper than the crease angle
  /// of `creaseCosine` (inline: the per-view pass asks it of every
  /// candidate segment).
  bool AtCrease(Index f, float creaseCosine) const
  {
    const Index* v = Triangles.data() + 3 * static_cast<std::int64_t>(f);
    const LargeVector<float>& sharpest = NearSharpestCosine.empty() ? SharpestCosine : NearSharpestCosine;
    return sharpest[v[0]] < creaseCosine || sharpest[v[1]] < creaseCosine || sharpest[v[2]] < creaseCosine;
  }
  /// The segment along edge a-b of `face`, its ends keyed by the vertices.
  LineSegment EdgeSegment(Index a, Index b, Index face) const;

  /// The ridge (valleys: valley) candidates kept by the threshold at
  /// `size` (the feature size; the lower threshold with hysteresis) and the
  /// crease rule of `options`: the
  /// view-independent part of their tests, kept for the next views while
  /// those settings stay (not for concurrent calls on one geometry).
  const SegmentList& ThresholdedRidges(bool valleys, double size, const LineDrawingOptions& options) const;
  /// The ridge (valleys: valley) candidates, with the maximum (minimum)
  /// test passed, before thresholds: found on the first call after Build
  /// (drawings without ridges and valleys, the default, do not pay for
  /// them), then kept (not for concurrent calls on one geometry).
  const SegmentList& RidgeCandidates(bool valleys) const;
  /// The triangles in a tree for the visibility rays, and the faces around
  /// each vertex (Drawing/Visibility.cxx defines it): built on the first
  /// call after Build, then kept (not for concurrent calls on one geometry).
  const OcclusionIndex& Occluders() const;

private:
  double DefaultFeatureSize = 0.0;
  LargeVector<std::int64_t> GlobalIds; // split runs: the global row of each vertex
  std::int64_t KeyIds = 0;
  /// Split runs: ghost rows of the curvatures (and their count of undefined
  /// vertices) made the owners'.
  void ShareCurvatures(const MeshTopology& topology);
  void FindRidges() const;
  int Threads = 0;                           // Build's thread count, for FindRidges
  mutable bool RidgesFound = false;          // FindRidges ran since Build
  mutable SegmentList Ridges[2];             // ridges, valleys (RidgeCandidates)
  /// (everyVertex: also the regular vertices' SharpestCosine, which
  /// ComputeCurvatures gives when it measures the surface itself.)
  void FindFeatureEdges(const MeshTopology& topology, int numThreads, bool everyVertex);
  /// FairedPoints and NearSharpestCosine made (SharpestCosine known).
  void Fair(const MeshTopology& topology, int numThreads, const FieldSmoothingOptions& smoothing);
  /// NearSharpestCosine: SharpestCosine's smallest within `rings` rings.
  void SpreadCreases(const MeshTopology& topology, double rings, int numThreads);
  /// A x B of face f at its vertex a (A, B: its edges from a to the next
  /// and the previous vertex), as the 1-ring loops compute it.
  Vec3 FaceCross(Index f, Index a) const;
  mutable CreaseList CreaseEdges; // Creases' last angle
  mutable std::shared_ptr<const OcclusionIndex> Occlusion; // Occluders, when first asked for
  struct RidgeCache
  {
    bool Valid = false, AvoidCreases = false;
    double Size = 0.0, Threshold = 0.0, CreaseAngle = 0.0; // (Threshold: the one applied)
    SegmentList Kept;
  };
  mutable RidgeCache Thresholded[2]; // ridges, valleys
};

/// Per-vertex quantities of one view (outputs; null ones skipped).
struct ViewFields
{
  double* NdotV = nullptr;
  double* RadialCurvature = nullptr;           ///< kappa_r
  double* RadialCurvatureDerivative = nullptr; ///< D_r kappa_r
};

/// Polylines: line l has the points Connectivity[Offsets[l] .. Offsets[l+1]),
/// a closed one repeating its first point at its end.
struct LineSet
{
  std::vector<double> Points, Normals; ///< 3 per point
  /// 3 per point: the point on the copy of the surface the fields were
  /// measured on (LineDrawingGeometry::FieldPoints; Points without one),
  /// where the visibility rays start.
  std::vector<double> FieldPoints;
  std::vector<double> PointStrength;   ///< the tested quantity (1 for contours, boundaries)
  std::vector<Index> Offsets{ 0 }, Connectivity;
  std::vector<std::uint8_t> Type;      ///< LineType per line
  std::vector<std::uint8_t> Closed;    ///< 1 for a closed loop
  std::vector<double> Strength;        ///< mean point strength per line
  /// Per line: 1 for the parts behind the surface (SplitByVisibility with
  /// the hidden parts kept; empty: none tested).
  std::vector<std::uint8_t> Hidden;
  /// Per entry of Connectivity: the face that the piece from that point to
  /// the next lies in (-1: the last point of a line, or not known).
  std::vector<Index> EdgeFace;
  /// Split runs (process 0's lines, chained from every process' segments):
  /// the key ids (LineDrawingGeometry::KeyId) of the corners of the faces
  /// that EdgeFace names, 3 per face; empty: EdgeFace names the geometry's
  /// own triangles.
  std::vector<std::int64_t> FaceCorners;
  Index NumberOfLines() const { return static_cast<Index>(Type.size()); }
};

/// One view's segments with their ends resolved, so that they chain on any
/// process: per line type, 2 keys (LineEnd::Key) and 2 x ValuesPerEnd values
/// (position, unit normal, the tested strength, the position on the copy
/// the fields were measured on) per segment.
struct ViewSegments
{
  static constexpr int ValuesPerEnd = 10;
  std::vector<std::int64_t> Keys[NumberOfLineTypes];
  std::vector<double> Ends[NumberOfLineTypes];
  /// The face of each segment: this process' numbering; after a gather,
  /// an index into FaceCorners.
  std::vector<Index> Faces[NumberOfLineTypes];
  /// Gathered segments: the key ids of the corners of their faces, 3 each.
  std::vector<std::int64_t> FaceCorners;
};

/// The per-view pass: the segments of this process' faces and edges
/// (CollectViewSegments), gathered on process 0 in split runs
/// (GatherViewSegments: collective; the others return no lines), chained
/// and filtered (ChainViewSegments).
LineSet DrawLines(const LineDrawingGeometry& geometry, const LineView& view,
  const LineDrawingOptions& options, const ViewFields& fields = {});
ViewSegments CollectViewSegments(const LineDrawingGeometry& geometry, const LineView& view,
  const LineDrawingOptions& options, const ViewFields& fields = {});
/// Every process' segments on process 0, with their faces as corner key
/// ids (collective); the others get none.
ViewSegments GatherViewSegments(const ViewSegments& mine, const LineDrawingGeometry& geometry);
/// `size`: the feature size the segments were found with.
LineSet ChainViewSegments(const ViewSegments& segments, const LineDrawingOptions& options, double size);

} // namespace beltrami
