// VTK-free parser for the OFF mesh format (Geomview's Object File Format, as
// used by CGAL, libigl, PMP and Princeton's shape benchmark).
//
// Supported: the OFF, COFF, NOFF, CNOFF, STOFF, STCOFF, STNOFF, STCNOFF
// headers (in the order ST C N of the keyword; vertex lines hold
// x y z [nx ny nz] [r g b [a]] [s t]), '#' comments, blank lines, counts on
// the header line or the next one, polygons of any size, optional per-face
// colours (r g b [a] after the indices), colours as integers 0-255 or floats
// in [0, 1].  Not supported (clear error): binary OFF, 4OFF and nOFF.
//
// Nothing in the file is trusted: counts are checked against the number of
// lines actually present before anything is allocated, every index is range
// checked, every number must parse completely and be finite.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace beltrami
{

struct OFFMesh
{
  std::vector<double> Points;           ///< 3 per vertex
  std::vector<double> Normals;          ///< 3 per vertex, if the header says N
  std::vector<double> TextureCoords;    ///< 2 per vertex, if the header says ST
  std::vector<std::uint8_t> PointColors;///< 4 per vertex (RGBA), if the header says C
  std::vector<std::int64_t> FaceOffsets;///< CSR: FaceOffsets.size() == faces + 1
  std::vector<std::int64_t> FaceIndices;
  std::vector<std::uint8_t> FaceColors; ///< 4 per face (RGBA), if any face has one
  bool HasPointAlpha = false;           ///< an alpha value appeared on a vertex line
  bool HasFaceAlpha = false;

  std::int64_t NumberOfPoints() const { return static_cast<std::int64_t>(Points.size() / 3); }
  std::int64_t NumberOfFaces() const
  {
    return FaceOffsets.empty() ? 0 : static_cast<std::int64_t>(FaceOffsets.size() - 1);
  }
};

/// Parses OFF text. On failure returns false and sets `error` to a message
/// that names the line; `mesh` is then left empty.
bool ParseOFF(const char* data, std::size_t size, OFFMesh& mesh, std::string& error);

/// Reads a whole file and parses it.
bool ReadOFFFile(const std::string& fileName, OFFMesh& mesh, std::string& error);

} // namespace beltrami
