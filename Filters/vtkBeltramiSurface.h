// The one bridge from vtkPolyData to the Beltrami core, shared by every
// surface filter: triangulates polygons and strips, builds the core's
// MeshTopology once, and exposes the points without copying them when they
// are float or double.  In distributed runs it counts the ranks that hold
// data, exchanges the triangles around the pieces' common points where a
// filter needs 1-rings, agrees on the owner of every point where a filter
// solves over the ranks (both through vtkBeltramiPieces), or gathers split
// data on rank 0 (vtkBeltramiGather) for the filters that need the whole
// surface on one process.  Not wrapped: an
// implementation helper of the module.
#ifndef vtkBeltramiSurface_h
#define vtkBeltramiSurface_h

#include "BeltramiFiltersModule.h" // export macro
#include "vtkBeltramiPieces.h"       // the pieces of split runs

#include "Mesh/MeshTopology.h"
#include "Solvers/Partition.h"

#include <vtkSmartPointer.h>
#include <vtkType.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkBeltramiGather;
class vtkDataArray;
class vtkDataSet;
class vtkInformation;
class vtkInformationVector;
class vtkMultiProcessController;
class vtkPolyData;

class BELTRAMIFILTERS_EXPORT vtkBeltramiSurface
{
public:
  /// Builds the surface of `input`.  Returns false (with Error() set) when the
  /// input cannot be processed at all; an input with no polygons is valid and
  /// yields a topology without triangles.
  bool Build(vtkPolyData* input, int numberOfThreads);
  /// Build for the filters that work on the whole surface at once (the
  /// atlas, the remesher): an input without points or triangles gives a
  /// warning on `owner` that `product` (e.g. "the atlas") is empty, an
  /// unusable one an error.
  enum class Readiness
  {
    Ready,
    Empty, ///< nothing to do: the output stays empty (RequestData succeeds)
    Failed ///< error reported (RequestData fails)
  };
  Readiness BuildWhole(vtkAlgorithm* owner, vtkPolyData* input, int numberOfThreads, const char* product);

  /// What a filter needs of a distributed run (pvbatch, pvserver: one piece
  /// per rank).
  enum class Needs
  {
    Piece,       ///< each piece on its own
    OneRings,    ///< the whole 1-ring (star of triangles) of every point of the piece
    WholeSurface, ///< the whole surface at once
    /// the whole surface, solved over the ranks: OneRings and the owner of
    /// every point (Split)
    Distributed
  };

  /// For the filters with a composite output besides their surface (the
  /// atlas's and the remesher's maps), from their ProcessRequest: on
  /// REQUEST_DATA_OBJECT, a new object for every composite output but the
  /// first.  On a composite input the executive runs such a filter once per
  /// block, gathering each block's outputs into composite outputs of the
  /// input's structure; an output composite itself would otherwise be that
  /// gathering object, emptied and refilled by every block.
  static void NewCompositeOutputs(vtkInformation* request, vtkInformationVector* outputVector);

  /// The one way a surface filter's RequestData runs, serial or distributed:
  /// fetches the poly data input and output, passes the input through,
  /// builds the surface and calls `run(surface)` (the filter's work on
  /// Input(), Output() and Topology(); false on error).  Errors and warnings
  /// are reported on `owner` (no warning for an empty piece of distributed
  /// data).  Collective in distributed runs (see PiecesHoldingData): every
  /// rank must call it.  Returns RequestData's value.
  ///
  /// Needs::OneRings: the filter needs the whole 1-ring (star of triangles) of
  /// every point of its piece.  When the data are split over ranks and no
  /// rank's piece has ghost cells (sources and readers that cannot make
  /// them), the ranks exchange the triangles at the edges of their pieces
  /// (ExchangeOneRings): the topology then covers the piece's points first
  /// (same ids) and the ghost points after them (NumberOfTopologyPoints() >
  /// NumberOfInputPoints()); Input() stays the piece.
  ///
  /// Needs::Distributed: the filter solves over the whole surface, each rank
  /// on its own piece.  When the data are split over the ranks and no piece
  /// has ghost cells, the ranks exchange the rings as for OneRings and
  /// agree on the owner of every point of the topology (Split()); `run`
  /// then runs on every rank, an empty piece's too (with an empty topology),
  /// and must make the same collective calls on each.  Otherwise (not
  /// split, or pieces with ghost cells) as WholeSurface.
  ///
  /// Needs::WholeSurface: the filter needs the whole surface at once.  When
  /// the data are split over the ranks, vtkBeltramiGather::RunWhole gathers
  /// the pieces on rank 0, `run` works there on the whole surface as in a
  /// serial run (IsGathered()), and every rank's output gets the results for
  /// its piece; on the other ranks `received(output)` is called then
  /// (optional: e.g. to read the report from the output's field data).
  static int Execute(vtkAlgorithm* owner, vtkInformationVector** inputVector, vtkInformationVector* outputVector,
    int numberOfThreads, Needs needs, const std::function<bool(vtkBeltramiSurface&)>& run,
    const std::function<void(vtkPolyData*)>& received = {});
  /// The RequestData of the filters that make a new data set from the whole
  /// surface (the atlas, the remesher, the line drawing): fetches the poly
  /// data input and output 0 (an error on `owner` if either is missing),
  /// empties every other output, and calls run(input, output) on the whole
  /// surface: split data over the ranks are gathered on rank 0, which holds
  /// the result (the other ranks' outputs stay empty).  Collective in
  /// distributed runs.  Returns RequestData's value.
  static int RunOnWholeSurface(vtkAlgorithm* owner, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector, const std::function<int(vtkPolyData*, vtkPolyData*)>& run);
  /// Execute with Needs::Distributed: the split run (collective; `output`
  /// gets the input piece, `outInfo` is its request), or -1 when the data are
  /// not split over ranks that can solve together (then WholeSurface).
  /// Public for the filters whose surface is not output 0 (the line drawing).
  static int ExecuteDistributed(vtkAlgorithm* owner, vtkPolyData* input, vtkPolyData* output,
    vtkInformation* outInfo, int numberOfThreads, const std::function<bool(vtkBeltramiSurface&)>& run);
  /// True when Execute runs on the whole surface gathered from the ranks.
  bool IsGathered() const { return Gathered; }
  /// Needs::Distributed on split data: the topology's points over the ranks
  /// (the piece's points, then the ghost points); null otherwise.
  const beltrami::Partition* Split() const { return Rings.Split(); }
  /// The pieces of a split run (vtkBeltramiPieces: Split, AllAgree).
  const vtkBeltramiPieces& SplitPieces() const { return Rings; }
  /// Whether `ok` holds on every rank of a split run (collective there:
  /// every rank calls it); `ok` itself otherwise (vtkBeltramiPieces).
  bool AllAgree(bool ok) const { return Rings.AllAgree(ok); }
  /// Points of the input piece (the output's points).
  vtkIdType NumberOfInputPoints() const;
  /// Points of the topology: the input's, then the ghost points of the
  /// other pieces' triangles (Execute's OneRings).
  vtkIdType NumberOfTopologyPoints() const;
  vtkPolyData* Input() const { return InputData; }
  vtkPolyData* Output() const { return OutputData; }
  /// PiecesHoldingData of the request (Execute calls it on every rank).
  int PiecesWithData() const { return Holding; }

  /// How many pieces of the request on `outInfo` hold points of `input`.
  /// 1 when the request is not split.  In a distributed run where every rank
  /// of the global controller updates its own piece (pvbatch, pvserver),
  /// the count over the ranks, so that data read whole on one rank (a reader
  /// that cannot split, e.g. OFF files) is processed as in a serial run;
  /// this is collective there: every rank must call it.  Otherwise
  /// (streaming pieces one by one) the number of pieces.
  static int PiecesHoldingData(vtkInformation* outInfo, vtkDataSet* input);
  /// True when the request on `outInfo` is one piece per rank of the global
  /// controller, this rank's own (pvbatch, pvserver): the ranks can talk.
  static bool OnePiecePerRank(vtkInformation* outInfo);
  /// The warning of the smoothing filters on distributed data (`pieces`
  /// hold points), each piece smoothed on its own with `pieceBoundary`
  /// (e.g. "its piece boundary fixed").
  static void WarnDistributed(vtkAlgorithm* owner, int pieces, const char* pieceBoundary);
  /// The smoothing filters' warning after Execute has built the surface: WarnDistributed for pieces
  /// streamed one by one (no gathering), else the topology's defects
  /// (TopologyWarning) followed by `consequence`.
  void WarnAboutInput(vtkAlgorithm* owner, const char* pieceBoundary, const char* consequence) const;

  const beltrami::MeshTopology& Topology() const { return *Mesh; }

  /// Coordinates as 3 interleaved values per point: exactly one is non-null.
  const float* FloatPoints() const { return Floats; }
  const double* DoublePoints() const { return Doubles; }

  /// The point array selected as input array `idx` of `owner`
  /// (SetInputArrayToProcess), or null when none is selected (no name, or
  /// ParaView's "None").  A selected array missing from the input gives a
  /// warning (naming it as `what`) and null; `error` is set when it has not
  /// exactly `components` components.
  vtkDataArray* SelectedPointArray(
    vtkAlgorithm* owner, int idx, int components, const char* what, std::string& error) const;
  /// The same for any data set input (components <= 0: any number); the one
  /// array lookup of every Beltrami filter, image filters included.
  static vtkDataArray* SelectedPointArray(vtkAlgorithm* owner, vtkDataSet* input, int idx,
    int components, const char* what, std::string& error);
  /// The same for a cell array.
  static vtkDataArray* SelectedCellArray(vtkAlgorithm* owner, vtkDataSet* input, int idx,
    int components, const char* what, std::string& error);

  /// A new array of VTK type `dataType` (name, components, tuples), its values
  /// uninitialized.  Arrays of 2 MiB or more are placed on memory the kernel
  /// may back with huge pages (see Core/Support/LargeBuffer.h): filling the outputs of
  /// a 1M-vertex mesh otherwise costs tens of thousands of page faults.
  static vtkSmartPointer<vtkDataArray> NewArray(
    int dataType, const char* name, int components, vtkIdType tuples);

  /// The selected point array `idx` of `owner` as a mask (non-zero = 1),
  /// one value per point; empty when none is selected.  Errors as
  /// SelectedPointArray (one component needed).
  static std::vector<std::uint8_t> SelectedPointMask(
    vtkAlgorithm* owner, vtkDataSet* input, int idx, const char* what, std::string& error);

  /// Warns on `owner` when points of `input` have NaN or infinite
  /// coordinates: "N points have NaN or infinite coordinates: " followed by
  /// `consequence`.  Returns that count.
  static vtkIdType WarnNonFinitePoints(vtkAlgorithm* owner, vtkDataSet* input, const char* consequence);

  /// The points as 3 doubles each: the input's own array when it is double
  /// (and nothing was split), else a converted copy kept in `storage`.
  const double* PointsAsDouble(std::vector<double>& storage) const;

  /// For the filters that need a manifold surface and write new points (the
  /// atlas, the remesher), after Build: where separate parts of the surface
  /// meet at a point or along an edge of three or more triangles, each part
  /// gets its own copies of the points (beltrami::SplitPinchedVertices).
  /// Topology() is then the split surface, whose vertices from
  /// NumberOfInputPoints() on are copies (InputPoint), with their points in
  /// PointsAsDouble.  What was split, for a warning (empty: nothing).
  std::string SplitNonManifold(int numberOfThreads);
  /// The input point of vertex v of Topology(): v, or the point a copy of
  /// SplitNonManifold copies.
  beltrami::Index InputPoint(beltrami::Index v) const
  {
    return v < static_cast<beltrami::Index>(NumberOfInputPoints()) ? v : Copied[v - NumberOfInputPoints()];
  }

  /// Calls f(const T* points) with the points' native precision.
  template <typename F>
  auto Dispatch(F&& f) const
  {
    return Floats ? f(Floats) : f(Doubles);
  }

  /// The input cell (vtkPolyData cell id: verts, lines, polys, strips) that
  /// triangle t of the triangle list given to the topology came from; call
  /// it with Topology().OriginalTriangleIds()[k] for kept triangle k.  -1
  /// for a triangle of another piece's (Execute's OneRings).
  vtkIdType TriangleCell(beltrami::Index t) const
  {
    return CellOfTriangle.empty() ? FirstPolygonCell + t : CellOfTriangle[t];
  }

  vtkIdType NumberOfInputCells() const { return InputCells; }
  vtkIdType NumberOfIgnoredCells() const { return IgnoredCells; } ///< verts and lines
  vtkIdType NumberOfInvalidCells() const { return InvalidCells; } ///< bad point ids
  const std::string& Error() const { return ErrorText; }

  /// Warnings about defects that the topology found (empty if none).
  std::string TopologyWarning() const;

  /// What Build repaired on a whole surface (serial, or gathered on one
  /// rank; a piece of split data is left as it is): exactly coincident
  /// boundary points merged (an unwelded triangle soup), edges of zero
  /// length collapsed, repeated triangles dropped and triangles turned to a
  /// consistent orientation (SurfaceRepair.h).  Empty when nothing was
  /// repaired; a sentence for a warning otherwise.
  const std::string& RepairWarning() const { return RepairText; }
  /// For every input point, the one it was merged into (itself when kept);
  /// empty when no point was merged.  The merged-away points are used by no
  /// triangle of Topology().
  const std::vector<beltrami::Index>& MergedPoints() const { return Merge; }
  /// A point array of Output() that holds each point's share of a measure
  /// (an area): SpreadToMergedPoints gives it 0 at the merged-away points,
  /// so that its sum over the points counts the measure once.
  void MarkShareOfMeasure(vtkDataArray* array) { Shares.push_back(array); }
  /// After a filter has written its point results on Output(): the arrays it
  /// added (those not passed through from the input) and its new points get,
  /// at every merged-away point, the values of the point it was merged into
  /// (the shares of a measure, MarkShareOfMeasure: 0).
  void SpreadToMergedPoints() const;

private:
  /// The general path of Build: any polygons (triangulated) and strips.
  void BuildTriangles(vtkPolyData* input, beltrami::IndexArray& triangles);

  /// Execute's one-ring exchange (collective): builds the piece's topology
  /// and grows it by the other pieces' triangles around its points
  /// (vtkBeltramiPieces::AddRings, at its boundary and non-manifold
  /// vertices), so that every point of the piece gets its whole star, also
  /// where three or more pieces meet.  The topology is then rebuilt with
  /// those triangles (TriangleCell -1) and their other points (after the
  /// piece's).  Returns true when the topology is built (with or without a
  /// ring), false when Build is still to be called (the pieces came with
  /// ghost cells, or the piece could not be built).
  /// Pieces that overlap (cells copied, unmarked, to several pieces): a
  /// triangle repeated within the piece is kept once, the corners of those
  /// other pieces hold too are shared points, and a ring triangle the piece
  /// holds already is not joined again (vtkBeltramiPieces::ShareCopiedCells).
  bool ExchangeOneRings(int numberOfThreads);
  /// The topology rebuilt without the triangles flagged in `drop` (one per
  /// triangle of the topology; TriangleCell kept for the others).
  bool DropTriangles(const std::vector<std::uint8_t>& drop, int numberOfThreads);
  /// The topology of `triangles` over `points` (TriangleCell: `cells`);
  /// false (with Error()) when it cannot be built.
  bool Remake(beltrami::Index points, beltrami::IndexArray triangles, std::vector<vtkIdType> cells, int numberOfThreads);
  /// The topology rebuilt with the triangles of the rings (the first `kept`
  /// triangles are the piece's own; `ghostPoints` after the piece's points).
  bool Rebuild(beltrami::IndexArray triangles, const std::vector<double>& ghostPoints, std::size_t kept,
    int numberOfThreads);
  /// Execute's start on InputData and OutputData: the pass-through, the
  /// empty and missing cases, and the surface (unless `built`).  Returns
  /// RequestData's value when there is nothing for `run` to do, else -1.
  int Start(vtkAlgorithm* owner, int numberOfThreads, bool built);

  /// The coordinates of topology point i (for vtkBeltramiPieces).
  void PointAt(beltrami::Index i, double* x) const;
  /// run(*this), then SpreadToMergedPoints; RequestData's value.
  int RunAndSpread(const std::function<bool(vtkBeltramiSurface&)>& run)
  {
    const bool ran = run(*this);
    SpreadToMergedPoints();
    return ran ? 1 : 0;
  }
  /// Build's repairs of a whole surface (RepairWarning).
  void Repair(int numberOfThreads);


  std::unique_ptr<beltrami::MeshTopology> Mesh;
  vtkBeltramiPieces Rings; // ExchangeOneRings, and the split of ExecuteDistributed's run
  bool Gathered = false;
  vtkPolyData* InputData = nullptr;
  vtkPolyData* OutputData = nullptr;
  int Pieces = 1;  // UPDATE_NUMBER_OF_PIECES of the request
  int Holding = 1; // PiecesHoldingData
  vtkSmartPointer<vtkDataArray> PointData; // keeps converted points alive
  const float* Floats = nullptr;
  const double* Doubles = nullptr;
  std::vector<vtkIdType> CellOfTriangle; // empty: the polygons are all triangles
  vtkIdType FirstPolygonCell = 0;
  vtkIdType InputCells = 0;
  vtkIdType IgnoredCells = 0;
  vtkIdType InvalidCells = 0;
  std::string ErrorText;
  std::vector<beltrami::Index> Merge; // MergedPoints
  std::vector<vtkDataArray*> Shares;  // MarkShareOfMeasure
  std::vector<beltrami::Index> Copied; // SplitNonManifold's copies: the input point of each
  std::string RepairText;
};

#endif
// VTK-HeaderTest-Exclude: vtkBeltramiSurface.h
