// Beltrami core: segments joined into polylines where they share an end
// (and, in LineChaining.cxx, a view's segments gathered and chained into
// the LineSet of DrawLines).
#pragma once

#include "Drawing/LineDrawing.h"

#include <vector>

namespace beltrami
{

/// One point of a chain: end `End` (0 or 1) of segment `Segment`.
struct ChainPoint
{
  Index Segment;
  int End;
};

/// A polyline of segment ends; a closed one does not repeat its first point.
struct SegmentChain
{
  std::vector<ChainPoint> Points;
  bool Closed = false;
  /// A closed loop's segment from its last point back to its first (the
  /// others: the piece from Points[i - 1] to Points[i] is Points[i]'s).
  Index ClosingSegment = -1;
};

/// Joins the segments whose ends have the same Key (>= 0) when exactly two
/// ends have it; an end with Key -1, with a Key of its own or one shared by
/// three or more ends (a junction) ends its chain there.  Open chains come
/// first, in the order of their first segment, then the closed loops; the
/// result does not depend on anything but the segments and their order.
/// `keys`: the two ends' Keys of each segment.
std::vector<SegmentChain> ChainSegments(const std::vector<std::int64_t>& keys);

} // namespace beltrami
