/**
 * @class   vtkIntrinsicParameterization
 * @brief   Intrinsic parameterizations of thesis chapter 5: discrete
 *          conformal (DCP), discrete authalic (DAP) and their mixes, natural
 *          conformal maps, point constraints, near-optimal maps and boundary
 *          optimisation.
 *
 * Flattens a disk-like triangle mesh (one connected, manifold, oriented
 * surface of genus 0 with one or more boundary loops; polygons and strips are
 * triangulated internally) and writes the texture coordinates as the point
 * array "UV" (also set as the TCoords).  Closed, non-manifold or
 * higher-genus input is an error that says what the input is.
 *  - Energy ConformalWeight * E_A + AuthalicWeight * E_chi (section 5.3.4;
 *    default 1, 0: DCP).  E_chi is scaled by the mean squared edge length so
 *    the mix does not depend on the mesh's units.
 *  - Boundary: CIRCLE (default; centre (0.5, 0.5), radius 0.5), SQUARE
 *    ([0,1]^2) with BoundarySpacing ARC_LENGTH (default) or UNIFORM; GIVEN
 *    (every boundary point where input array 0, a 2-component point array,
 *    puts it); NATURAL (section 5.4.2: the natural conformal map, the two
 *    boundary points farthest apart pinned, then fitted into [0,1]^2; the
 *    conformal energy only).  With a fixed outer boundary, the other boundary
 *    loops (holes) are free.
 *  - Point constraints (section 5.4.1, Lagrange multipliers): by
 *    AddPointConstraint / AddSurfacePointConstraint, and/or input array 1, a
 *    2-component point array whose finite values are the targets of their
 *    points (NaN = free).  Line constraints (AddLineConstraint): a path of
 *    points along mesh edges mapped onto a segment at arc-length fractions;
 *    AddShortestPathLineConstraint (ParaView: LineConstraints) takes the
 *    shortest edge path between two points.  With natural boundaries and two
 *    or more constraints, the constraints replace the pins.
 *  - OptimizeMix (section 5.5.1): the map l U_A + (1-l) U_chi with the l in
 *    OptimalMixRange minimising OptimalEnergy (EDGE_LENGTH or AREA
 *    distortion, the map scaled to the surface's area); l is in GetOptimalMix().
 *  - BoundaryOptimizationSteps (section 5.5.2): gradient-descent steps on the
 *    boundary points for BoundaryEnergy through the impulse-response basis
 *    (steps that would flip a triangle are refused; point and line
 *    constraints stay met, also through the kept basis).  KeepBoundaryBasis keeps
 *    that basis after the update: ComputeUV() then gives the map for any new
 *    boundary positions without a new solve.
 *  - Boundary handles (AddBoundaryHandle; ParaView: BoundaryHandles) for
 *    interactive use: boundary points dragged to new (u, v), their loops
 *    following; when only the handles change, the map comes from the kept
 *    basis without a new solve (NumberOfSolves).
 *  - OutputFlattenedMesh: the output points are (u, v, 0) instead of the input's.
 * Cell arrays AngleDistortion (mean |2D - 3D| corner angle, degrees),
 * AreaDistortion (log of the normalised 2D/3D area ratio) and EdgeDistortion
 * (mean |log| of the normalised edge-length ratios); field arrays with their
 * means and maxima, FlippedTriangles, and OptimalMix / BoundaryEnergy when
 * used.  Distributed runs (pvbatch, pvserver): a surface that a reader
 * delivers whole to one rank (e.g. an OFF file) is parameterized there as in
 * a serial run.  A surface split over several ranks (without ghost cells) is
 * parameterized where it lies: the ranks exchange the triangles around their
 * common points, agree on each point's owner, check together that the whole
 * is a disk, gather only its boundary, and solve the conformal system
 * together (conjugate gradients preconditioned by hypre's BoomerAMG over the
 * ranks, to a residual reduction of 1e-10): the serial map to about 1e-10,
 * no rank holding more than its piece and a ring (field arrays
 * ParameterizationIterations and ParameterizationDistribution: each rank's
 * owned points, ghost points, triangles, values sent per exchange).  The
 * outer loop starts where a serial run's does, at its lowest point id, when
 * the pieces carry global point ids (vtkPointData::GetGlobalIds); without
 * them at its lexicographically first point (the serial map turned on the
 * circle, or its square's corners moved along the boundary).  Options the
 * split solve does not cover (beltrami::DistributedParameterizationLimitation:
 * the authalic energy and the optimal mix, NATURAL, point and line
 * constraints, a constraint target array, boundary optimisation, the kept
 * basis and handles) and pieces with
 * ghost cells gather the pieces on rank 0 (points shared by pieces merged,
 * ghost cells left out); it parameterizes the whole surface there and every
 * rank gets the UVs, points and distortion of its own points and cells: the
 * serial numbers, with the memory and time of one process.  The boundary
 * basis then lives on rank 0.  Pieces streamed one by one in one process
 * pass through with a warning.
 */
#ifndef vtkIntrinsicParameterization_h
#define vtkIntrinsicParameterization_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for the basis
#include <string> // for ParameterizeThroughAtlas
#include <vector> // for the constraints

class vtkBeltramiSurface;
enum class vtkBeltramiCopy;
namespace beltrami
{
struct DistortionReport;
struct ParameterizationOptions;
struct ParameterizationResult;
}
class vtkDataArray;
class vtkDoubleArray;
class vtkFieldData;
class vtkIdList;

class BELTRAMIFILTERS_EXPORT vtkIntrinsicParameterization : public vtkPolyDataAlgorithm
{
public:
  static vtkIntrinsicParameterization* New();
  vtkTypeMacro(vtkIntrinsicParameterization, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum BoundaryType
  {
    CIRCLE = 0,
    SQUARE = 1,
    GIVEN = 2,
    NATURAL = 3
  };
  enum SpacingType
  {
    ARC_LENGTH = 0,
    UNIFORM = 1
  };
  enum EnergyType
  {
    EDGE_LENGTH = 0,
    AREA = 1
  };

  ///@{
  /// lambda: weight of the discrete conformal (Dirichlet) energy. Default: 1.
  vtkSetMacro(ConformalWeight, double);
  vtkGetMacro(ConformalWeight, double);
  /// mu: weight of the discrete authalic (chi) energy, scaled by the mean squared edge length so
  /// the mix does not depend on the mesh's units. Default: 0.
  vtkSetMacro(AuthalicWeight, double);
  vtkGetMacro(AuthalicWeight, double);
  ///@}

  ///@{
  /// Circle: the outer loop on the circle of centre (0.5, 0.5) and radius 0.5. Square: on the unit
  /// square, corners at the quarters of its length. Given: every boundary point at the value of the
  /// Given Boundary UV Array. Natural: free boundary (natural conformal map), fitted into the unit
  /// square. Values: 0 Circle, 1 Square, 2 Given, 3 Natural. Default: Circle.
  vtkSetClampMacro(Boundary, int, CIRCLE, NATURAL);
  vtkGetMacro(Boundary, int);
  /// Spacing of the boundary points on the circle or square: proportional to the 3D edge lengths,
  /// or equal. Values: 0 Arc Length, 1 Uniform. Default: Arc Length.
  vtkSetClampMacro(BoundarySpacing, int, ARC_LENGTH, UNIFORM);
  vtkGetMacro(BoundarySpacing, int);
  ///@}

  ///@{
  /// Point constraints: a point, or a point of a triangle (barycentric
  /// weights summing to 1), mapped exactly onto (u, v).
  void AddPointConstraint(vtkIdType pointId, double u, double v);
  void AddSurfacePointConstraint(vtkIdType a, vtkIdType b, vtkIdType c, double wa, double wb,
    double wc, double u, double v);
  /// Line constraint (section 5.4.1): the path of points `pointIds`
  /// (consecutive ones joined by a mesh edge, e.g. the output of
  /// vtkDijkstraGraphGeodesicPath reversed to start at its start vertex)
  /// mapped onto the segment (u0, v0)-(u1, v1), each point at its
  /// arc-length fraction: the thesis' constraints on the line's
  /// intersections with the mesh edges.
  void AddLineConstraint(vtkIdList* pointIds, double u0, double v0, double u1, double v1);
  /// Line constraint along the shortest path over mesh edges from point
  /// `start` to point `end` (ParaView: the LineConstraints property).
  void AddShortestPathLineConstraint(vtkIdType start, vtkIdType end, double u0, double v0, double u1, double v1);
  /// Removes the point and the line constraints.
  void RemoveAllConstraints();
  int GetNumberOfConstraints() const;
  int GetNumberOfLineConstraints() const;
  ///@}

  ///@{
  /// Use the blend l DCP + (1-l) DAP (same boundary) with the l in the Optimal Mix Range that
  /// minimises the Optimal Energy (section 5.5.1); the weights above are then not used. Default:
  /// off.
  vtkSetMacro(OptimizeMix, bool);
  vtkGetMacro(OptimizeMix, bool);
  vtkBooleanMacro(OptimizeMix, bool);
  /// Distortion energy minimised by Optimize Mix. Values: 0 Edge Length, 1 Area. Default: Edge
  /// Length.
  vtkSetClampMacro(OptimalEnergy, int, EDGE_LENGTH, AREA);
  vtkGetMacro(OptimalEnergy, int);
  /// Range searched for the optimal blend l. Default: 0 1.
  vtkSetVector2Macro(OptimalMixRange, double);
  vtkGetVector2Macro(OptimalMixRange, double);
  /// The l found by the last update with OptimizeMix (-1 otherwise).
  vtkGetMacro(OptimalMix, double);
  ///@}

  ///@{
  /// Gradient-descent steps on the fixed boundary points (section 5.5.2), through the
  /// impulse-response basis; 0 = off. Steps that would flip a triangle are refused. The energies
  /// are in the field array BoundaryEnergy. Default: 0.
  vtkSetClampMacro(BoundaryOptimizationSteps, int, 0, VTK_INT_MAX);
  vtkGetMacro(BoundaryOptimizationSteps, int);
  /// Distortion energy minimised by the boundary optimisation. Values: 0 Edge Length, 1 Area.
  /// Default: Edge Length.
  vtkSetClampMacro(BoundaryEnergy, int, EDGE_LENGTH, AREA);
  vtkGetMacro(BoundaryEnergy, int);
  vtkSetMacro(KeepBoundaryBasis, bool);
  vtkGetMacro(KeepBoundaryBasis, bool);
  vtkBooleanMacro(KeepBoundaryBasis, bool);
  ///@}

  ///@{
  /// Closed, higher-genus or multi-component input (no disk): parameterize it through an atlas (as
  /// Surface Atlas: disk-like charts on squares, circles or free boundaries as Boundary says,
  /// packed into [0,1]^2) instead of refusing it. The output is then the surface cut along the
  /// chart seams. A disk still gets one map, unless that map flips triangles (obtuse triangles,
  /// free holes) and nothing pins it (constraints, handles, Given boundary, boundary optimisation,
  /// optimal mix): then the atlas, which never flips, is used instead, with a warning. Serial runs
  /// only (Surface Atlas handles distributed data). Default: on.
  vtkSetMacro(AtlasForNonDisks, bool);
  vtkGetMacro(AtlasForNonDisks, bool);
  vtkBooleanMacro(AtlasForNonDisks, bool);
  ///@}

  ///@{
  /// Output the flattened mesh (points (u, v, 0)) instead of the 3D surface. Default: off.
  vtkSetMacro(OutputFlattenedMesh, bool);
  vtkGetMacro(OutputFlattenedMesh, bool);
  vtkBooleanMacro(OutputFlattenedMesh, bool);
  ///@}

  ///@{
  /// Threads used for the assembly; 0 uses all cores, shared among the processes of an MPI job on
  /// the node (or BELTRAMI_NUM_THREADS). Default: 0.
  vtkSetClampMacro(NumberOfThreads, int, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

  ///@{
  /// Results of the last update.
  vtkGetMacro(MeanAngleDistortion, double);
  vtkGetMacro(MeanAreaDistortion, double);
  vtkGetMacro(MeanEdgeDistortion, double);
  vtkGetMacro(NumberOfFlippedTriangles, vtkIdType);
  ///@}

  ///@{
  /// With KeepBoundaryBasis: the fixed boundary points of the last update,
  /// and the UV of every point (2 components) for new positions of those
  /// points (2 components per id, in that order), without a new solve.
  /// ComputeUV returns false when no basis is kept or the sizes disagree.
  void GetBoundaryPointIds(vtkIdList* ids) const;
  bool ComputeUV(vtkDataArray* boundaryUV, vtkDoubleArray* uv) const;
  ///@}

  ///@{
  /// Boundary handles (section 5.4.2, interactive use): fixed boundary
  /// points moved to (u, v).  The other points of a handle's boundary loop
  /// follow, the handles' displacements interpolated along the loop by arc
  /// length (one handle translates the loop), and the map is the boundary
  /// basis applied to those positions.  When only the handles change, the
  /// next update reuses the kept basis: no new solve (NumberOfSolves tells).
  /// Fixed boundaries only (CIRCLE, SQUARE, GIVEN).  ParaView: the
  /// BoundaryHandles property (point id, u, v triples).
  void AddBoundaryHandle(vtkIdType pointId, double u, double v);
  void RemoveAllBoundaryHandles();
  int GetNumberOfBoundaryHandles() const;
  /// Linear solves (parameterizations computed) since the filter was made.
  vtkGetMacro(NumberOfSolves, int);
  ///@}

  /// Changes of the handles alone do not ask for a new solve.
  void Modified() override;

protected:
  vtkIntrinsicParameterization();
  ~vtkIntrinsicParameterization() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  // Defaults: the core's ParameterizationOptions{} (set in the constructor).
  double ConformalWeight;
  double AuthalicWeight;
  int Boundary;
  int BoundarySpacing;
  bool OptimizeMix;
  int OptimalEnergy;
  double OptimalMixRange[2];
  int BoundaryOptimizationSteps;
  int BoundaryEnergy;
  bool KeepBoundaryBasis;
  int NumberOfThreads;
  bool OutputFlattenedMesh = false;
  bool AtlasForNonDisks = true;

  double OptimalMix = -1.0;
  double MeanAngleDistortion = 0.0;
  double MeanAreaDistortion = 0.0;
  double MeanEdgeDistortion = 0.0;
  vtkIdType NumberOfFlippedTriangles = 0;
  int NumberOfSolves = 0;

private:
  vtkIntrinsicParameterization(const vtkIntrinsicParameterization&) = delete;
  void operator=(const vtkIntrinsicParameterization&) = delete;

  /// The map of the surface Execute built (RequestData's value).
  int Parameterize(vtkBeltramiSurface& surface);
  /// Whether the atlas may replace a single map that flips (see AtlasForNonDisks).
  bool CanUseAtlasInstead(const vtkBeltramiSurface& surface) const;
  /// The atlas path for input that is not a disk (AtlasForNonDisks).
  int ParameterizeThroughAtlas(vtkBeltramiSurface& surface, const std::string& why);
  /// The given boundary (input array 0, into `given`) and the constraint
  /// targets (input array 1) into `options`; false (after an error) if unusable.
  bool ReadInputArrays(vtkBeltramiSurface& surface, beltrami::ParameterizationOptions& options,
    std::vector<double>& given);
  /// A line constraint (path: the points, or waypoints joined by shortest
  /// edge paths).
  void AddLine(const std::vector<vtkIdType>& path, bool shortest, double u0, double v0, double u1, double v1);
  /// The map with the handles applied through the kept basis to the
  /// boundary of the solve's own map; false after an error.
  bool ApplyHandles(vtkBeltramiSurface& surface, std::vector<double>& uv);
  /// The parameterization of the surface into `result` (after ReadInputArrays);
  /// false after an error.  Keeps the basis and, with handles, the result.
  bool Solve(vtkBeltramiSurface& surface, beltrami::ParameterizationResult& result);
  /// Solve's split run: the ranks solve together (given: input array 0's
  /// values, grown to the topology's rows).
  beltrami::ParameterizationResult SolveSplit(
    vtkBeltramiSurface& surface, beltrami::ParameterizationOptions& options, std::vector<double>& given);
  /// Whether the kept basis and map serve this update (only the handles changed).
  bool CanReuseSolve(vtkBeltramiSurface& surface);
  /// Modification times of what a solve reads from the input.
  std::vector<vtkMTimeType> InputStamp(vtkBeltramiSurface& surface);
  /// UV (and the flattened points) into the output.
  void WriteMap(vtkBeltramiSurface& surface, const beltrami::ParameterizationResult& result);
  /// Per-cell distortion, the field-data report and the getters' values.
  void WriteDistortion(vtkBeltramiSurface& surface, const beltrami::DistortionReport& distortion,
    const beltrami::ParameterizationResult& result);
  /// Copies the settings to or from the core's options (one list of pairs).
  void CopySettings(beltrami::ParameterizationOptions& options, vtkBeltramiCopy direction);
  /// The distortion getters from the field data of an output (the ranks of a
  /// gathered distributed run other than 0).
  void ReadReport(vtkFieldData* fd);

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
