/**
 * @class   vtkSurfaceLineDrawing
 * @brief   Line drawings of a triangle surface for a camera: contours,
 *          suggestive contours and highlights, ridges and valleys,
 *          boundaries and creases, as polylines on the surface.
 *
 * The thesis (1.1, figure 1.1a) names line drawing as a first use of its
 * operators.  The lines are zero sets interpolated inside the triangles
 * (not along mesh edges), chained into polylines:
 *  - CONTOUR: n.v = 0, v the unit vector from the surface to the camera.
 *  - SUGGESTIVE_CONTOUR (DeCarlo, Finkelstein, Rusinkiewicz & Santella
 *    2003): the radial curvature kappa_r (the normal curvature along the
 *    projection w of v onto the tangent plane) is 0 and its derivative
 *    D_w kappa_r > 0; drawn where D_w kappa_r * FeatureSize^2 exceeds
 *    SuggestiveContourThreshold and the surface turns at least
 *    SuggestiveContourAngle degrees away from the viewer.
 *  - SUGGESTIVE_HIGHLIGHT (DeCarlo & Rusinkiewicz 2007): kappa_r = 0 with
 *    D_w kappa_r < 0, the same tests on -D_w kappa_r.
 *  - RIDGE / VALLEY: the maximum principal curvature kappa_1 at a maximum
 *    along its direction with kappa_1 * FeatureSize > RidgeThreshold / the
 *    minimum one kappa_2 at a minimum with -kappa_2 * FeatureSize >
 *    RidgeThreshold.
 *  - APPARENT_RIDGE (Judd, Durand & Adelson 2007): the view-dependent
 *    curvature q1 (the normal's turn per unit length in the image) at a
 *    maximum along its direction, q1 * FeatureSize > ApparentRidgeThreshold,
 *    on the side facing the viewer (Drawing/ApparentRidges.h).
 *  - BOUNDARY: edges of one triangle; CREASE: edges whose triangles'
 *    normals differ by more than CreaseAngle degrees.  With AvoidCreases
 *    (default) the curvature lines (suggestive, ridges, valleys) are left
 *    out of the triangles at a crease vertex.
 * Curvature is positive where the surface bends away from its normal (a
 * sphere with outward normals), the normals following the triangles'
 * orientation.  The curvature tensor is the thesis' (chapter 2,
 * vtkDiscreteCurvatures); its derivative per vertex is Rusinkiewicz's
 * (2004) per-face least-squares fit averaged with the mixed areas.
 * FeatureSize 0 (default) is 1% of the bounding-box diagonal.
 *
 * The camera: CameraPosition (perspective, default) or, with
 * ParallelProjection on, ViewDirection (the direction the camera looks
 * along).  In ParaView, beltrami_paraview.follow_camera(drawing, view)
 * (Python/beltrami_paraview.py) keeps them equal to a view's camera, in the
 * GUI's Python shell and in pvpython.
 *
 * The view-independent part (curvatures, their derivatives, feature-edge
 * candidates; the ridge and valley candidates when ridges or valleys are
 * first drawn) is kept while the input does not change: a new camera or
 * threshold re-runs only the per-view pass (GetGeometryBuilds() counts the
 * other).  With DropBackFacing (default)
 * the pieces of suggestive contours, highlights, ridges and valleys where
 * n.v < 0 are dropped (hidden lines are the renderer's depth test).
 *
 * Output 0: polylines, cell arrays LineType (the enumeration below) and
 * Strength (the mean of the tested quantity along the line: D_w kappa_r
 * FeatureSize^2 for suggestive lines, |kappa| FeatureSize for ridges and
 * valleys, q1 FeatureSize for apparent ridges, the dihedral angle for
 * creases, 1 for contours and boundaries),
 * point arrays Strength (the same per point, for fading) and Normals (the
 * surface normal, for offset rendering).  Output 1: the input surface with
 * point arrays CurvatureDerivative (4 components: C(e1,e1,e1),
 * C(e1,e1,e2), C(e1,e2,e2), C(e2,e2,e2) in the principal frame), and per
 * view NdotV, RadialCurvature and RadialCurvatureDerivative, for shading.
 *
 * Boundary, non-manifold and degenerate vertices have no curvature: the
 * lines that need it stop at their triangles, with a warning; contours,
 * boundaries and creases are drawn everywhere.
 *
 * Visibility (VISIBLE_LINES, VISIBLE_AND_HIDDEN_LINES) splits the lines
 * where they pass behind the surface, tested by rays from their points to
 * the eye (Drawing/Visibility.h); the lines' field data keep the view for
 * vtkLineDrawingWriter.
 *
 * Distributed runs (pvbatch, pvserver): a surface split over the ranks is
 * drawn where it lies.  The ranks exchange the triangles around their
 * common points (so that every point of a piece has its whole 1-ring),
 * each computes the curvatures and their derivatives of its piece and
 * takes its neighbours' values for the ring, and finds the segments of the
 * triangles and edges it owns; only the segments travel, to rank 0, which
 * chains them and holds the polylines (the serial drawing up to the order
 * of the lines).  With Visibility, every rank casts rank 0's rays through
 * its own triangles (with the stars of its ghost points from their owners)
 * and the answers are combined: the serial visible and hidden lines, the
 * surface never gathered.  Output 1 is each rank's piece with its arrays; field
 * array LineDrawingDistribution: the rank's owned points, ghost points,
 * triangles with the ring, values sent per exchange.  Pieces that come with
 * ghost cells are gathered on rank 0.
 */
#ifndef vtkSurfaceLineDrawing_h
#define vtkSurfaceLineDrawing_h

#include "BeltramiFiltersModule.h"
#include <vtkPolyDataAlgorithm.h>

#include <memory> // for the kept geometry

enum class vtkBeltramiCopy;
class vtkBeltramiSurface;
namespace beltrami
{
struct LineDrawingOptions;
struct FieldSmoothingOptions;
}

class BELTRAMIFILTERS_EXPORT vtkSurfaceLineDrawing : public vtkPolyDataAlgorithm
{
public:
  static vtkSurfaceLineDrawing* New();
  vtkTypeMacro(vtkSurfaceLineDrawing, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum VisibilityModes
  {
    ALL_LINES = 0,
    VISIBLE_LINES = 1,
    VISIBLE_AND_HIDDEN_LINES = 2
  };

  enum LineTypes
  {
    CONTOUR = 0,
    SUGGESTIVE_CONTOUR = 1,
    SUGGESTIVE_HIGHLIGHT = 2,
    RIDGE = 3,
    VALLEY = 4,
    BOUNDARY = 5,
    CREASE = 6,
    APPARENT_RIDGE = 7
  };

  /// The camera's position (perspective). Kept equal to a view's camera by
  /// beltrami_paraview.follow_camera. Default: 0 0 1.
  vtkSetVector3Macro(CameraPosition, double);
  vtkGetVector3Macro(CameraPosition, double);
  /// The direction the camera looks along, used with Parallel Projection. Default: 0 0 -1.
  vtkSetVector3Macro(ViewDirection, double);
  vtkGetVector3Macro(ViewDirection, double);
  /// The camera's up direction: the vertical of the page for vtkLineDrawingWriter. Default: 0 1 0.
  vtkSetVector3Macro(ViewUp, double);
  vtkGetVector3Macro(ViewUp, double);
  /// Orthographic view along View Direction instead of the perspective from Camera Position.
  /// Default: off.
  vtkSetMacro(ParallelProjection, bool);
  vtkGetMacro(ParallelProjection, bool);
  vtkBooleanMacro(ParallelProjection, bool);

  /// Draw the contours: n.v = 0 interpolated in the triangles. Default: on.
  vtkSetMacro(Contours, bool);
  vtkGetMacro(Contours, bool);
  vtkBooleanMacro(Contours, bool);
  /// Draw the suggestive contours: the radial curvature is 0 and its derivative towards the viewer
  /// positive. Default: on.
  vtkSetMacro(SuggestiveContours, bool);
  vtkGetMacro(SuggestiveContours, bool);
  vtkBooleanMacro(SuggestiveContours, bool);
  /// Draw the suggestive highlights: the radial curvature is 0 and its derivative negative.
  /// Default: off.
  vtkSetMacro(SuggestiveHighlights, bool);
  vtkGetMacro(SuggestiveHighlights, bool);
  vtkBooleanMacro(SuggestiveHighlights, bool);
  /// Draw the ridges: the maximum principal curvature at a maximum along its direction. Default:
  /// off.
  vtkSetMacro(Ridges, bool);
  vtkGetMacro(Ridges, bool);
  vtkBooleanMacro(Ridges, bool);
  /// Draw the valleys: the minimum principal curvature at a minimum along its direction. Default:
  /// off.
  vtkSetMacro(Valleys, bool);
  vtkGetMacro(Valleys, bool);
  vtkBooleanMacro(Valleys, bool);
  /// Draw the edges of one triangle. Default: on.
  vtkSetMacro(Boundaries, bool);
  vtkGetMacro(Boundaries, bool);
  vtkBooleanMacro(Boundaries, bool);
  /// Draw the edges whose two triangles' normals differ by more than Crease Angle. Default: on.
  vtkSetMacro(Creases, bool);
  vtkGetMacro(Creases, bool);
  vtkBooleanMacro(Creases, bool);

  /// Draw the apparent ridges (Judd et al. 2007): the view-dependent curvature at a maximum along
  /// its direction. Default: off.
  vtkSetMacro(ApparentRidges, bool);
  vtkGetMacro(ApparentRidges, bool);
  vtkBooleanMacro(ApparentRidges, bool);

  /// The length that makes the thresholds scale-free; 0: 1% of the bounding-box diagonal. Default:
  /// 0.
  vtkSetClampMacro(FeatureSize, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(FeatureSize, double);
  /// The normals and curvatures the lines are found from are measured on a copy of the surface
  /// smoothed over this many Feature Size (one implicit curvature-flow step), and the lines drawn
  /// on the surface itself: the noise of raw scans no longer breaks them into dashes. 0: measured
  /// on the surface itself. Default: 0.5.
  vtkSetClampMacro(CurvatureSmoothing, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(CurvatureSmoothing, double);
  /// Suggestive contours and highlights are drawn where the derivative of the radial curvature
  /// times Feature Size^2 exceeds this. Default: 0.1.
  vtkSetClampMacro(SuggestiveContourThreshold, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(SuggestiveContourThreshold, double);
  /// Suggestive lines are drawn only where the surface turns at least this angle (degrees) away
  /// from the viewer. Default: 15.
  vtkSetClampMacro(SuggestiveContourAngle, double, 0.0, 90.0);
  vtkGetMacro(SuggestiveContourAngle, double);
  /// Ridges (valleys) are drawn where the maximum curvature (minus the minimum one) times Feature
  /// Size exceeds this. Default: 0.4.
  vtkSetClampMacro(RidgeThreshold, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(RidgeThreshold, double);
  /// Apparent ridges are drawn where the view-dependent curvature times Feature Size exceeds this.
  /// Default: 1.
  vtkSetClampMacro(ApparentRidgeThreshold, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(ApparentRidgeThreshold, double);
  /// Dihedral angle in degrees above which an edge is a crease. Default: 40.
  vtkSetClampMacro(CreaseAngle, double, 0.0, 180.0);
  vtkGetMacro(CreaseAngle, double);
  /// Lines of every type but boundaries and creases whose polylines are shorter than this many
  /// Feature Size are dropped (0: all kept), and with Visibility the visible (hidden) parts of a
  /// line that are shorter. Values of 1-3 clean the short pieces and small contour loops that the
  /// noise of raw scans draws. Default: 2.
  vtkSetClampMacro(MinimumLineLength, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MinimumLineLength, double);
  /// Hysteresis of the curvature lines' thresholds (1: none). Suggestive contours and highlights,
  /// ridges, valleys and apparent ridges are traced down to this fraction of their thresholds, and
  /// a line is kept where it passes the full threshold somewhere: on raw scans, 0.5 joins the
  /// pieces that the noise breaks wherever it dips below the threshold. Default: 0.5.
  vtkSetClampMacro(HysteresisRatio, double, 0.01, 1.0);
  vtkGetMacro(HysteresisRatio, double);
  /// Leave suggestive contours and highlights, ridges, valleys and apparent ridges out of the
  /// triangles at a crease vertex (an end of an edge sharper than Crease Angle): the curvature
  /// there is the crease's, not the surface's, and CAD parts would get suggestive contours along
  /// their creases. Default: on.
  vtkSetMacro(AvoidCreases, bool);
  vtkGetMacro(AvoidCreases, bool);
  vtkBooleanMacro(AvoidCreases, bool);
  /// Drop the pieces of suggestive lines, ridges and valleys on back-facing triangles (n.v < 0).
  /// Default: on.
  vtkSetMacro(DropBackFacing, bool);
  vtkGetMacro(DropBackFacing, bool);
  vtkBooleanMacro(DropBackFacing, bool);
  /// Which parts of the lines to keep: all of them (hidden parts are left to the renderer's depth
  /// test), the visible ones only, or both with cell array Hidden. Values: 0 All lines, 1 Visible
  /// lines, 2 Visible and hidden lines. Default: All lines.
  vtkSetClampMacro(Visibility, int, ALL_LINES, VISIBLE_AND_HIDDEN_LINES);
  vtkGetMacro(Visibility, int);
  /// Threads; 0 uses all cores, shared among the processes of an MPI job on the node (or
  /// BELTRAMI_NUM_THREADS). Default: 0.
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);

  /// How many times the view-independent pass ran (it is kept while the
  /// input stays the same).
  vtkGetMacro(GeometryBuilds, int);

protected:
  vtkSurfaceLineDrawing();
  ~vtkSurfaceLineDrawing() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double CameraPosition[3] = { 0.0, 0.0, 1.0 };
  double ViewDirection[3] = { 0.0, 0.0, -1.0 };
  double ViewUp[3] = { 0.0, 1.0, 0.0 };
  bool ParallelProjection = false;
  int Visibility = 0;
  bool Contours = true;
  bool SuggestiveContours = true;
  bool SuggestiveHighlights = false;
  bool Ridges = false;
  bool Valleys = false;
  bool Boundaries = true;
  bool Creases = true;
  bool ApparentRidges = false;
  double FeatureSize = 0.0;
  double CurvatureSmoothing = 0.0;
  double SuggestiveContourThreshold = 0.0;
  double SuggestiveContourAngle = 0.0;
  double RidgeThreshold = 0.0;
  double ApparentRidgeThreshold = 0.0;
  double CreaseAngle = 0.0;
  double MinimumLineLength = 0.0;
  double HysteresisRatio = 1.0;
  bool DropBackFacing = true;
  bool AvoidCreases = true;
  int NumberOfThreads = 0;
  int GeometryBuilds = 0;

private:
  vtkSurfaceLineDrawing(const vtkSurfaceLineDrawing&) = delete;
  void operator=(const vtkSurfaceLineDrawing&) = delete;

  void CopySettings(beltrami::LineDrawingOptions& options, vtkBeltramiCopy direction);
  /// The drawing of the whole surface (serial, or gathered on rank 0).
  int Draw(vtkPolyData* input, vtkPolyData* output);
  /// The drawing of a surface split over the ranks, each on its piece
  /// (collective); -1 when the data are not split (then Draw).
  int DrawSplit(vtkInformationVector** inputVector, vtkInformationVector* outputVector);
  /// Builds the view-independent pass unless the kept one is for `input`;
  /// false (output empty) when there is nothing to draw or an error.
  int UpdateGeometry(vtkPolyData* input, bool& ready);
  /// Whether the kept view-independent pass is the one of `input`.
  bool Keeps(vtkPolyData* input) const;
  /// The view-independent pass' smoothing of the current settings.
  beltrami::FieldSmoothingOptions Smoothing() const;
  /// Builds the view-independent pass of `surface` (the topology of `input`;
  /// split: over the ranks, collective) and keeps it.
  void KeepGeometry(const vtkBeltramiSurface& surface, vtkPolyData* input, bool split);
  /// The per-view pass on the kept geometry: the polylines into `lines`, the
  /// per-view arrays onto `surface` (collective in split runs).
  int DrawView(vtkPolyData* lines, vtkPolyData* surface);

  struct Kept;
  std::unique_ptr<Kept> Cache;
};

#endif
