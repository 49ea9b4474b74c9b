/**
 * @class   vtkTetGenTetrahedralizer
 * @brief   Quality tetrahedral meshes of the volume inside a closed triangle
 *          surface, by TetGen (Debian's libtet 1.5).
 *
 * Input: a closed, manifold, consistently oriented surface (polygons are
 * triangulated; strips too).  Output: a vtkUnstructuredGrid of tetrahedra
 * (VTK_TETRA) filling the enclosed volume, for the volume filters of
 * section 2.8.2 (vtkTetrahedralBeltramiDenoising).  Options (TetGen switches):
 *  - RadiusEdgeRatio (q, default 2; 0: no quality refinement): the largest
 *    ratio of circumradius to shortest edge of a tetrahedron;
 *  - MinimumDihedralAngle (degrees, default 0 = TetGen's own);
 *  - MaximumVolume (a, default 0 = no limit);
 *  - PreserveSurface (Y, default on): no Steiner points on the surface, so
 *    the boundary of the output is the input's triangles.
 * Point data: the input points are the first output points with their data;
 * numeric point arrays are extended harmonically to the new (Steiner) points:
 * the volume Laplacian of the output (Tetrahedra.h) is zero there, with the
 * input points' values held - exact for linear fields.  Points of no triangle (of line or vertex cells)
 * are not meshed: they come back unused at their places.  An open, non-manifold or empty surface is an error
 * naming the defect.  TetGen runs in a helper process (build/lib/beltrami-tetgen,
 * Core/Support/HelperProcess.h), kept running between runs of the filter, because
 * libtet 1.5 crashes (frees its pools twice) when it meets a
 * self-intersecting or nearly touching surface: a crash there is diagnosed
 * with TetGen's self-intersection check (-d) and reported with the number
 * of intersecting triangles, and the next run starts a new helper; TetGen's
 * other failures are reported with TetGen's reason.  Abort kills the helper.  Distributed runs
 * (pvbatch, pvserver): pieces that are closed surfaces of their own are meshed where they are; a
 * surface split over the ranks (open pieces) is gathered on rank 0 (vtkBeltramiGather) and meshed
 * whole there, the other ranks' outputs staying empty.  A streamed piece of a closed surface is
 * open: the error says so.  Field data: TetGenSwitches.
 */
#ifndef vtkTetGenTetrahedralizer_h
#define vtkTetGenTetrahedralizer_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkUnstructuredGridAlgorithm.h"

#include <string>

class vtkIdTypeArray;
class vtkPointData;
class vtkUnstructuredGrid;

class vtkBeltramiSurface;
class vtkPolyData;

class BELTRAMIFILTERS_EXPORT vtkTetGenTetrahedralizer : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkTetGenTetrahedralizer* New();
  vtkTypeMacro(vtkTetGenTetrahedralizer, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Largest circumradius / shortest edge of a tetrahedron (TetGen -q); 0: no quality refinement.
  /// Default: 2.0.
  vtkSetClampMacro(RadiusEdgeRatio, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(RadiusEdgeRatio, double);
  /// Smallest dihedral angle in degrees (TetGen -q/angle); 0: TetGen's default. Default: 0.
  vtkSetClampMacro(MinimumDihedralAngle, double, 0.0, 70.0);
  vtkGetMacro(MinimumDihedralAngle, double);
  /// Largest tetrahedron volume (TetGen -a); 0: no limit. With Preserve Surface, tetrahedra at the
  /// surface may exceed it. Default: 0.
  vtkSetClampMacro(MaximumVolume, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumVolume, double);
  /// No new points on the surface (TetGen -Y): the boundary of the output is the input's triangles.
  /// Default: on.
  vtkSetMacro(PreserveSurface, bool);
  vtkGetMacro(PreserveSurface, bool);
  vtkBooleanMacro(PreserveSurface, bool);

  /// The TetGen switches of the settings (e.g. "pQzq2Y").
  std::string GetSwitches() const;

protected:
  vtkTetGenTetrahedralizer() = default;
  ~vtkTetGenTetrahedralizer() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// The input's point arrays (numInput tuples) on the output points.
  void InterpolatePointData(
    vtkPointData* inPD, vtkIdType numInput, vtkUnstructuredGrid* output, vtkIdTypeArray* connectivity);

  double RadiusEdgeRatio = 2.0;
  double MinimumDihedralAngle = 0.0;
  double MaximumVolume = 0.0;
  bool PreserveSurface = true;

private:
  vtkTetGenTetrahedralizer(const vtkTetGenTetrahedralizer&) = delete;
  void operator=(const vtkTetGenTetrahedralizer&) = delete;

  /// Meshes `input` into `output` (RequestData's value); `holding`: how
  /// many pieces of distributed data hold points (for the error message);
  /// `built`: `input`'s surface when already built (else built here).
  int Mesh(vtkPolyData* input, vtkUnstructuredGrid* output, int holding,
    vtkBeltramiSurface* built = nullptr);
};

#endif
