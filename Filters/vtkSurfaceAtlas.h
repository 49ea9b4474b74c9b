/**
 * @class   vtkSurfaceAtlas
 * @brief   An atlas of charts for triangle surfaces of any genus, open or
 *          closed, with any number of components (thesis section 4.2):
 *          texture coordinates ("UV unwrapping") of closed surfaces.
 *
 * The surface is cut into disk-like charts (approximate Voronoi regions of
 * seeds spread by area over every component and moved to their regions'
 * centres, grown along the dual graph, ragged boundaries smoothed, regions that are not disks -
 * bands around handles, closed components - split until every chart is
 * one), optionally the area-balanced refinement of section 4.2.4
 * (BalanceAreas, off by default: neighbouring charts of unequal area re-split
 * at the median of their area along a smooth seam; on the elephant the
 * largest chart over the smallest goes from 164 to 7.6, but the charts get
 * longer: more angle distortion, less packing, and it is slower).  Each chart is mapped by the discrete
 * conformal parameterization (DCP, chapter 5) onto its own square (ChartBoundary SQUARE, section
 * 4.2.2; the chart's boundary spaced by arc length, the square's corners at
 * its sharpest turns, so that no triangle lies flat on a side), onto the circle
 * (CIRCLE), or with a free boundary (NATURAL: the natural conformal map of
 * section 5.4.2): a chart whose square map would flip a triangle, or whose
 * free boundary would overlap itself, is mapped onto the circle instead, and a chart whose map still flips is split, so no
 * triangle is ever flipped.  The charts are packed into [0, 1]^2 at one
 * scale (the same texels per unit of surface length on every chart), with
 * MarginTexels texels of a TextureSize^2 texture between them.
 *
 * Seams: input array 0 (SetInputArrayToProcess, a cell array of labels:
 * a segmentation, part or material ids) makes the edges between cells of
 * different labels chart boundaries (no chart spans two labels); with
 * SplitAtFeatures (off by default) so are the sharp edges, whose triangles'
 * normals differ by more than FeatureAngle degrees (60; section 4.2.3) - a
 * sharp edge that ends inside a chart splits it.
 *
 * Settings: NumberOfCharts (charts to start from; splits add more; 0, the
 * default: about one per 2,000 triangles, at least one per component),
 * MaximumChartArea (0: no limit; larger charts are split),
 * ChartBoundary, SplitAtFeatures, FeatureAngle, TextureSize (1024),
 * MarginTexels (2), MapResolution (256; 0: no maps), MapLayout (CHARTS),
 * NumberOfThreads.
 *
 * Output: the surface cut along the chart seams (the points of a seam
 * duplicated, one copy per chart; the input's point and cell data carried)
 * with point arrays UV (packed, also the TCoords), ChartUV (each chart in
 * its own square) and vtkOriginalPointIds, cell arrays ChartId and
 * vtkOriginalCellIds (polygons and strips are triangulated; vertices and
 * lines are dropped), and field arrays AtlasCharts (the count),
 * AtlasChartArea, AtlasChartAngleDistortion (mean, degrees),
 * AtlasChartAreaDistortion (mean |log area ratio|), AtlasPackingEfficiency
 * (the charts' share of [0, 1]^2), AtlasSplitsForFlips and AtlasCutEdges
 * (seam and sharp edges kept as chart boundaries).
 *
 * Output 1 (MapResolution > 0): the geometry maps of every chart (section
 * 4.2.3), a vtkMultiBlockDataSet with one MapResolution^2 vtkImageData per
 * chart (smaller, with a warning, where the charts outnumber both 64 and one
 * per 2,000 triangles, e.g. many small components: they share the pixels of
 * that many full-size maps; block i = chart i, its pixel centres at ((i + 0.5) / n, (j + 0.5)
 * / n) of the chart's square, ChartUV): point arrays FaceId (the input cell
 * under the pixel, -1 outside the chart), Embedding (the surface point, 3
 * components: M_x), AreaRatio (3D area per unit of map area: M_A),
 * MeanCurvature and GaussianCurvature (M_H, M_K: the operators of chapter 2
 * at the vertices, interpolated; boundary points from their interior
 * neighbours) and every numeric point array of the input, interpolated
 * exactly (barycentric in the chart's triangles); NaN outside the chart.
 * With MapLayout ATLAS the maps are instead one MapResolution^2 image of the
 * packed atlas (block "Atlas": pixel centres in UV, the texels of a texture
 * of that size), with the same arrays (AreaRatio then per unit of UV area)
 * and ChartId (-1 between the charts): a texture bake of the surface's
 * geometry and data, one map set for the whole surface.
 *
 * Progress is reported while the charts are mapped, and AbortExecute stops
 * there (empty outputs).  Non-manifold or inconsistently oriented surfaces,
 * NaN coordinates and empty input are reported and give an empty output;
 * zero-area triangles and isolated points are accepted.  An atlas needs the
 * whole surface: in a distributed run (pvbatch, pvserver) a surface split
 * over the ranks is gathered on rank 0, which holds the cut surface (the
 * other ranks' outputs are empty).
 */
#ifndef vtkSurfaceAtlas_h
#define vtkSurfaceAtlas_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkPolyDataAlgorithm.h"

#include <cstddef> // for ChartMapResolution
#include <cstdint> // for ChartMapResolution
#include <vector>  // for WriteCutSurface

enum class vtkBeltramiCopy;
class vtkBeltramiSurface;
namespace beltrami
{
class MeshTopology;
struct AtlasOptions;
struct AtlasResult;
}

class BELTRAMIFILTERS_EXPORT vtkSurfaceAtlas : public vtkPolyDataAlgorithm
{
public:
  static vtkSurfaceAtlas* New();
  vtkTypeMacro(vtkSurfaceAtlas, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum ChartBoundaryType
  {
    CIRCLE = 0,
    SQUARE = 1,
    NATURAL = 3
  };

  /// Charts to start from (splits add more); 0: automatic, about one per 2,000 triangles and at
  /// least one per component. Default: 0.
  vtkSetClampMacro(NumberOfCharts, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfCharts, int);
  /// The largest chart area, in the input's units squared: larger charts are split until none is,
  /// and the number of charts to start from is at least the surface's area over it. 0: no limit.
  /// Default: 0.
  vtkSetClampMacro(MaximumChartArea, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumChartArea, double);
  /// Where each chart's boundary goes: the square of section 4.2.2, the circle, or free (Natural:
  /// the natural conformal map of section 5.4.2). A chart whose square map would flip a triangle,
  /// or whose free boundary would overlap itself, goes onto the circle. Values: 0 Circle, 1 Square,
  /// 3 Natural. Default: Square.
  virtual void SetChartBoundary(int boundary);
  vtkGetMacro(ChartBoundary, int);
  /// The texture the margins are measured in (texels per side). Default: 1024.
  vtkSetClampMacro(TextureSize, int, 1, VTK_INT_MAX);
  vtkGetMacro(TextureSize, int);
  /// Gap between packed charts, and around the atlas, in texels. Default: 2.0.
  vtkSetClampMacro(MarginTexels, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MarginTexels, double);
  /// The area-balanced refinement of section 4.2.4: neighbouring charts of unequal area are merged
  /// and split again at the median of their area along a smooth seam (kept where both halves are
  /// disks). Much more even chart areas (the elephant's largest over smallest chart 164 to 7.6),
  /// but longer charts with more angle distortion; off by default. Default: off.
  vtkSetMacro(BalanceAreas, bool);
  vtkGetMacro(BalanceAreas, bool);
  vtkBooleanMacro(BalanceAreas, bool);
  /// Keep sharp edges (normals of the two triangles differing by more than Feature Angle) as chart
  /// boundaries, as for CAD parts (section 4.2.3). A sharp edge that ends inside a chart splits it.
  /// A triangle turned over against two of its neighbours (a fold of the input, not a crease) makes
  /// none. Off by default: coarse organic meshes have scattered sharp edges (the elephant: 167
  /// above 60 degrees, 233 charts instead of 36). Default: off.
  vtkSetMacro(SplitAtFeatures, bool);
  vtkGetMacro(SplitAtFeatures, bool);
  vtkBooleanMacro(SplitAtFeatures, bool);
  /// Dihedral angle in degrees above which an edge is sharp (Split At Features). Default: 60.
  vtkSetClampMacro(FeatureAngle, double, 0.0, 180.0);
  vtkGetMacro(FeatureAngle, double);
  /// Pixels per side of every chart's geometry maps (the second output: FaceId, Embedding,
  /// AreaRatio, MeanCurvature, GaussianCurvature and the input's point arrays, sampled exactly in
  /// the chart's square); 0: no maps. Where the charts outnumber both 64 and one per 2,000
  /// triangles (many small components), they share the pixels of that many full-size maps: each is
  /// smaller, with a warning. Default: 256.
  vtkSetClampMacro(MapResolution, int, 0, 16384);
  vtkGetMacro(MapResolution, int);
  enum MapLayoutType
  {
    CHARTS = 0, ///< one image per chart, of its own square (ChartUV)
    ATLAS = 1   ///< one image of the packed atlas (UV): the texture's texels
  };
  /// One image per chart: every chart's maps sampled in its own square (ChartUV). One atlas image:
  /// a single MapResolution x MapResolution image of the packed atlas (UV: the texels of the
  /// texture), with the same arrays and ChartId (-1 between charts): a texture bake of the geometry
  /// and data. Values: 0 One image per chart, 1 One atlas image. Default: One image per chart.
  vtkSetClampMacro(MapLayout, int, CHARTS, ATLAS);
  vtkGetMacro(MapLayout, int);
  /// Threads for the charts' maps; 0 uses all cores, shared among the processes of an MPI job on
  /// the node (or BELTRAMI_NUM_THREADS). Default: 0.
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);

protected:
  vtkSurfaceAtlas();
  ~vtkSurfaceAtlas() override = default;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  /// (Composite inputs: vtkBeltramiSurface::NewCompositeOutputs.)
  vtkTypeBool ProcessRequest(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int MapResolution = 256;
  int MapLayout = CHARTS;
  // Defaults: the core's AtlasOptions{} (set in the constructor).
  int NumberOfCharts;
  double MaximumChartArea;
  bool BalanceAreas;
  bool SplitAtFeatures;
  double FeatureAngle;
  int ChartBoundary;
  int TextureSize;
  double MarginTexels;
  int NumberOfThreads;

private:
  vtkSurfaceAtlas(const vtkSurfaceAtlas&) = delete;
  void operator=(const vtkSurfaceAtlas&) = delete;

  /// The atlas of `input` into `output` (RequestData's value).
  int Build(vtkPolyData* input, vtkPolyData* output);
  /// The cut surface of `atlas` (built on `input`, whose triangle t came from
  /// input cell triangleCell[t]) into `output`.
  void WriteCutSurface(vtkPolyData* input, const vtkBeltramiSurface& surface, const beltrami::AtlasResult& atlas,
    const std::vector<vtkIdType>& triangleCell, vtkPolyData* output);
  /// The geometry maps of every chart into output 1.
  /// The pixels per side of each chart's maps: MapResolution, or less
  /// (with a warning) where the charts are many more than the surface's
  /// triangles make by default.
  int ChartMapResolution(std::size_t charts, std::int64_t triangles);
  void WriteMaps(vtkPolyData* input, const vtkBeltramiSurface& surface, const double* points,
    const beltrami::AtlasResult& atlas, const std::vector<vtkIdType>& triangleCell);
  /// The seam labels (input array 0, a cell array) per kept triangle into
  /// `options`; false (error reported) when the array is unusable.
  bool ReadSeamLabels(const vtkBeltramiSurface& surface, beltrami::AtlasOptions& options);
  /// Copies the settings to or from the core's options (one list of pairs).
  void CopySettings(beltrami::AtlasOptions& options, vtkBeltramiCopy direction);
};

#endif
