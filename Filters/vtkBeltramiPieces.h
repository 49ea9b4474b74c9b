// The pieces of data split over the ranks of pvbatch or pvserver, for the
// filters that solve over the ranks: each piece grown by the
// cells of the other pieces around its points (so that every point of the
// piece has its whole star: rings), and the owner of every point (the
// core's Partition).  What does not depend on the cell type: triangles for
// vtkBeltramiSurface (the surface filters), tetrahedra for
// vtkTetrahedralBeltramiDenoising.  Common points of the pieces are matched
// by their coordinates (vtkBeltramiGather::CoincidentPoints), as in the
// gathering.  Not wrapped: an implementation helper of the module.
#ifndef vtkBeltramiPieces_h
#define vtkBeltramiPieces_h

#include "BeltramiFiltersModule.h" // export macro

#include "Solvers/Partition.h"

#include <vtkType.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

class vtkBoundingBox;
class vtkDataSet;
class vtkFieldData;
class vtkInformation;
class vtkMultiProcessController;

class BELTRAMIFILTERS_EXPORT vtkBeltramiPieces
{
public:
  /// The coordinates of point i of the piece (with its rings) into x[3].
  using Coordinates = std::function<void(beltrami::Index i, double* x)>;

  /// Whether the request on `outInfo` is one piece per rank of the global
  /// controller, this rank's own (vtkBeltramiSurface::OnePiecePerRank), and
  /// the ranks talk over MPI: they can solve together.  Not collective.
  static bool CanSolveTogether(vtkInformation* outInfo);
  /// Whether the pieces of `input` lack the rings: some piece holds points
  /// and none came with ghost cells (readers and sources that cannot make
  /// them).  Collective over the global controller.
  static bool RingsAreMissing(vtkDataSet* input);

  /// Grows the piece's cells (`corners` point ids each, into its
  /// `numberOfPoints` points) by the other pieces' cells that touch its
  /// points (collective: every rank calls it, an empty piece's too).  `edge`
  /// flags the points at the edge of the piece (on a boundary face or
  /// non-manifold; where pieces meet, each has its common points there):
  /// the edge points that other pieces hold too are found (among those in
  /// another piece's bounding box), every piece offers the cells at them,
  /// and keeps those of the others that touch one of its own.  Their points that the piece lacks
  /// become ghost points, numbered after its points (GhostPoints()).
  /// Returns whether cells were added.
  /// stars: which points get their whole star: All (every point of the
  /// piece: a filter that works on every point, e.g. the curvatures), or
  /// Owned (only the points this rank will own, BuildPartition's owners:
  /// a solve over the ranks, which assembles the owned rows only; about
  /// half the ring).
  enum class Stars
  {
    All,
    Owned
  };
  bool AddRings(int corners, beltrami::Index numberOfPoints, const Coordinates& point,
    const std::vector<std::uint8_t>& edge, std::vector<beltrami::Index>& cells, Stars stars = Stars::All);
  /// Cells that other pieces hold too (collective): readers and filters
  /// that copy the cells on a cut to every piece they touch without marking
  /// them as ghost cells (RedistributeDataSet's "Assign to all regions").
  /// Of the piece's `cells` (`corners` point ids each), those with a corner
  /// at the edge of the piece (`edge`, as for AddRings) and the same corner
  /// coordinates as a cell of another rank's piece get all their corners
  /// flagged in `edge` (shared: owned by the lowest rank holding them);
  /// AddRings then joins a cell the piece holds already only once.
  void ShareCopiedCells(int corners, beltrami::Index numberOfPoints, const Coordinates& point,
    const std::vector<beltrami::Index>& cells, std::vector<std::uint8_t>& edge) const;
  /// Flags in `repeated` (one per cell, sized by the caller) the cells with
  /// the same corners as an earlier cell of `cells`; only cells whose every
  /// corner is `suspect` are compared (none given: all).
  static void RepeatedCells(int corners, const std::vector<beltrami::Index>& cells, std::vector<std::uint8_t>& repeated,
    const std::function<bool(beltrami::Index)>& suspect = {});
  /// AddRings' ghost points: 3 coordinates each.
  const std::vector<double>& GhostPoints() const { return Ghosts; }
  /// The cells of the piece with its rings (AddRings' result).
  std::int64_t NumberOfCells() const { return Cells; }
  /// After BuildPartition: the field array `name` of a run split over the
  /// ranks, added to `fd`: this rank's owned points, ghost points, cells
  /// (its piece's with the rings) and values sent per exchange of the ghosts.
  void AddDistribution(vtkFieldData* fd, const char* name) const;

  /// After AddRings (collective): the owner of each of the `rows` points of
  /// the piece with its rings (its first `pieceRows` are the piece's own):
  /// a point that pieces share belongs to the lowest rank holding it, a
  /// ghost point to the piece it came from.  From then on Split() is set
  /// and AllAgree collective.  False (with `error`) when a point has no
  /// owner.
  bool BuildPartition(beltrami::Index rows, beltrami::Index pieceRows, const Coordinates& point, std::string& error);
  /// The same for structured pieces (images; collective): this rank holds
  /// the samples of extent `inExt` (its piece `outExt` and a ring around
  /// it); a sample belongs to the lowest rank whose piece holds it, at its
  /// index in that rank's `inExt`.  Every rank's extents are gathered.
  /// False (with `error`) when a sample of `inExt` is in no rank's piece.
  bool BuildGridPartition(const int* inExt, const int* outExt, std::string& error);
  /// The points of the piece with its rings over the ranks; null before
  /// BuildPartition (or when it failed).
  const beltrami::Partition* Split() const { return Rows.get(); }
  /// The same, shared: for a filter that keeps it beyond the run (the line
  /// drawing's geometry, drawn again for each view).
  std::shared_ptr<const beltrami::Partition> SharedSplit() const { return Rows; }

  /// Marks the run collective (every rank takes part): AllAgree talks.
  void SetCollective(bool collective) { Collective = collective; }
  /// Whether `ok` holds on every rank of a collective run (every rank calls
  /// it); `ok` itself otherwise.  A distributed filter checks its input with
  /// it before its collective work, so that a rank's error stops all ranks
  /// instead of leaving them waiting.
  bool AllAgree(bool ok) const;

  /// Every rank's `mine` appended in rank order (collective: every rank
  /// calls it); rank r's values at [offsets[r], offsets[r + 1]).
  static std::vector<double> AllGather(
    vtkMultiProcessController* controller, const std::vector<double>& mine, std::vector<vtkIdType>& offsets);

private:
  /// The points flagged in `edge` that other pieces may hold too: those in
  /// another piece's bounding box (collective: the boxes are gathered).
  /// Only they are offered and matched, so that the pieces' own boundaries
  /// (the surface of a volume mesh) travel nowhere.
  /// The other pieces' bounding boxes, slightly grown (collective).
  static std::vector<vtkBoundingBox> OtherBoxes(beltrami::Index numberOfPoints, const Coordinates& point);
  std::vector<beltrami::Index> SharedCandidates(
    beltrami::Index numberOfPoints, const Coordinates& point, const std::vector<std::uint8_t>& edge) const;

  /// AddRings' first stage (collective): the candidates matched over the
  /// ranks; those that other pieces hold too (EdgePoints) and their owners
  /// (EdgeOwners: the lowest rank holding each).
  void FindSharedPoints(
    beltrami::Index numberOfPoints, const Coordinates& point, const std::vector<std::uint8_t>& edge);

  /// Split() from the owner of each row (collective: throws nowhere; false
  /// with `error` where some rank names a row its owner does not own).
  bool MakeRows(beltrami::Index rows, const std::vector<int>& ownerRank, const std::vector<beltrami::Index>& ownerRow,
    std::string& error);

  std::vector<beltrami::Index> EdgePoints;    // the piece's points that other pieces hold too
  std::vector<int> EdgeOwners;                // and their owners
  std::vector<beltrami::Index> OfferedPoints; // and the corners of the cells it offered
  std::vector<double> Ghosts;
  std::int64_t Cells = 0;
  std::shared_ptr<beltrami::Partition> Rows;
  bool Collective = false;
};

#endif
// VTK-HeaderTest-Exclude: vtkBeltramiPieces.h
