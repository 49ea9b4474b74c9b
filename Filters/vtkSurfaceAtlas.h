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
 * chart (block i = chart i, its pixel centres at ((i + 0.5) / n, (j + 0.5)
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

#include <vector> // for WriteCutSurface

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

  vtkSetClampMacro(NumberOfCharts, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfCharts, int);
  /// The largest chart area (the input's units squared; 0, the default: no
  /// limit): larger charts are split, and NumberOfCharts is raised to the
  /// surface's area over it.
  vtkSetClampMacro(MaximumChartArea, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumChartArea, double);
  /// CIRCLE, SQUARE or NATURAL; other values are ignored.
  virtual void SetChartBoundary(int boundary);
  vtkGetMacro(ChartBoundary, int);
  vtkSetClampMacro(TextureSize, int, 1, VTK_INT_MAX);
  vtkGetMacro(TextureSize, int);
  vtkSetClampMacro(MarginTexels, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MarginTexels, double);
  vtkSetMacro(BalanceAreas, bool);
  vtkGetMacro(BalanceAreas, bool);
  vtkBooleanMacro(BalanceAreas, bool);
  /// Sharp edges (normals differing by more than FeatureAngle degrees) as
  /// chart boundaries (off by default).
  vtkSetMacro(SplitAtFeatures, bool);
  vtkGetMacro(SplitAtFeatures, bool);
  vtkBooleanMacro(SplitAtFeatures, bool);
  vtkSetClampMacro(FeatureAngle, double, 0.0, 180.0);
  vtkGetMacro(FeatureAngle, double);
  vtkSetClampMacro(MapResolution, int, 0, 16384);
  vtkGetMacro(MapResolution, int);
  enum MapLayoutType
  {
    CHARTS = 0, ///< one image per chart, of its own square (ChartUV)
    ATLAS = 1   ///< one image of the packed atlas (UV): the texture's texels
  };
  vtkSetClampMacro(MapLayout, int, CHARTS, ATLAS);
  vtkGetMacro(MapLayout, int);
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);

protected:
  vtkSurfaceAtlas();
  ~vtkSurfaceAtlas() override = default;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
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
  void WriteCutSurface(vtkPolyData* input, const beltrami::AtlasResult& atlas,
    const std::vector<vtkIdType>& triangleCell, vtkPolyData* output);
  /// The geometry maps of every chart into output 1.
  void WriteMaps(vtkPolyData* input, const beltrami::MeshTopology& topology, const double* points,
    const beltrami::AtlasResult& atlas, const std::vector<vtkIdType>& triangleCell);
  /// The seam labels (input array 0, a cell array) per kept triangle into
  /// `options`; false (error reported) when the array is unusable.
  bool ReadSeamLabels(const vtkBeltramiSurface& surface, beltrami::AtlasOptions& options);
  /// Copies the settings to or from the core's options (one list of pairs).
  void CopySettings(beltrami::AtlasOptions& options, vtkBeltramiCopy direction);
};

#endif
