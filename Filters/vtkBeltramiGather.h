// Distributed runs of the filters that need the whole mesh at once (a
// parameterization, an implicit smoothing step: one global solve): the
// pieces of a surface (vtkPolyData) or of a volume mesh (vtkUnstructuredGrid)
// split over the ranks are gathered on rank 0 as one data set, the filter
// runs there as in a serial run, and each rank gets back the results for its
// own points and cells.  The numbers are those of a serial run; the memory
// and the time are those of one process.  Not wrapped.
#ifndef vtkBeltramiGather_h
#define vtkBeltramiGather_h

#include "BeltramiFiltersModule.h" // export macro

#include <vtkSmartPointer.h>
#include <vtkType.h>

#include <functional>
#include <vector>

class vtkAlgorithm;
class vtkInformation;
class vtkMultiProcessController;
class vtkPoints;
class vtkPointSet;

class BELTRAMIFILTERS_EXPORT vtkBeltramiGather
{
public:
  /// Where the results of a gathered run go.
  enum class Results
  {
    ToEveryPiece, ///< each rank's output gets the results for its points and cells
    OnRankZero    ///< a new data set (e.g. a mesh of the whole volume) on rank 0; other ranks' outputs empty
  };
  /// The filter's work: `input` to `output`; `holding` > 1: a piece of
  /// streamed or distributed data run on its own.  Returns RequestData's value.
  using Run = std::function<int(vtkPointSet* input, vtkPointSet* output, int holding)>;

  /// The one way a filter that needs the whole data set runs (surface filters:
  /// vtkBeltramiSurface::Execute, which builds on this class).  Collective in
  /// distributed runs: every rank calls it.  When the data are split over
  /// the ranks (one piece per rank) and `gatherIf` (collective, optional:
  /// default yes) says so, the pieces are collected on rank 0, run(whole,
  /// wholeOutput, 1) runs there as in a serial run, and the results go where
  /// `results` says; otherwise run(input, output, holding) runs on this
  /// rank's data.  Returns RequestData's value (rank 0's outcome for every
  /// rank of a gathered run with ToEveryPiece).
  static int RunWhole(vtkInformation* outInfo, vtkPointSet* input, vtkPointSet* output, Results results,
    const Run& run, const std::function<bool()>& gatherIf = {});

  /// Collective over `controller` (every rank calls it).  Sends this rank's
  /// piece (its points, its cells without ghost cells, all point arrays) to
  /// rank 0, which returns the whole data set: the pieces appended, points
  /// closer than 1e-12 of the bounding box diagonal merged into one (the
  /// copies that pieces share of their common points; coincident points of
  /// one piece too), the cells in the pieces' order.  Other ranks return
  /// null.
  vtkSmartPointer<vtkPointSet> Collect(vtkMultiProcessController* controller, vtkPointSet* piece);

  /// Collective, after Collect.  Rank 0 passes the filter's output for the
  /// whole surface (`wholeInput` the surface it ran on) and `ok`; every rank
  /// passes its own output (a shallow copy of its input piece).  Each output
  /// gets, for its points and cells, the point and cell arrays of the whole
  /// output that are not those of the whole input, loses the ones the filter
  /// removed, gets the whole output's points when the filter replaced them,
  /// and its field data.  Returns rank 0's `ok` (the outputs stay the inputs
  /// when it failed).
  bool Distribute(vtkPointSet* wholeInput, vtkPointSet* wholeOutput, bool ok, vtkPointSet* output);

  /// For every point of `points`, the id of the one point that represents
  /// it and the points within `tolerance` of it (vtkStaticPointLocator::
  /// MergePoints, chains resolved; a representative represents itself):
  /// how the pieces' copies of their common points are joined.
  static std::vector<vtkIdType> CoincidentPoints(vtkPoints* points, double tolerance);

private:
  /// Collect's stages on rank 0: the points of all pieces with their copies
  /// of common points merged (PointIds; returns the count), and the cells in
  /// the pieces' order (CellIds).
  vtkIdType JoinPoints(
    const std::vector<vtkSmartPointer<vtkPointSet>>& pieces, vtkPointSet* reference, vtkPointSet* whole);
  void JoinCells(const std::vector<vtkSmartPointer<vtkPointSet>>& pieces, vtkPointSet* whole);

  vtkMultiProcessController* Controller = nullptr;
  // Rank 0: for every rank, its points' and cells' ids in the whole surface
  // (-1: a ghost cell, left out).
  std::vector<std::vector<vtkIdType>> PointIds, CellIds;
};

#endif
// VTK-HeaderTest-Exclude: vtkBeltramiGather.h
