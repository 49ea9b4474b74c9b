#include "OFFFormat.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string_view>

namespace beltrami
{

namespace
{

struct Line
{
  std::string_view Text;
  std::int64_t Number; // 1-based line number in the file
};

bool IsSpace(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

// Non-empty lines with comments removed.
std::vector<Line> SplitLines(const char* data, std::size_t size)
{
  std::vector<Line> lines;
  std::size_t pos = 0;
  std::int64_t number = 0;
  while (pos < size)
  {
    ++number;
    std::size_t end = pos;
    while (end < size && data[end] != '\n')
    {
      ++end;
    }
    std::size_t stop = pos;
    while (stop < end && data[stop] != '#')
    {
      ++stop;
    }
    std::size_t b = pos;
    while (b < stop && IsSpace(data[b]))
    {
      ++b;
    }
    std::size_t e = stop;
    while (e > b && IsSpace(data[e - 1]))
    {
      --e;
    }
    if (e > b)
    {
      lines.push_back({ std::string_view(data + b, e - b), number });
    }
    pos = end + 1;
  }
  return lines;
}

void Tokenize(std::string_view text, std::vector<std::string_view>& tokens)
{
  tokens.clear();
  std::size_t i = 0;
  while (i < text.size())
  {
    while (i < text.size() && IsSpace(text[i]))
    {
      ++i;
    }
    std::size_t j = i;
    while (j < text.size() && !IsSpace(text[j]))
    {
      ++j;
    }
    if (j > i)
    {
      tokens.push_back(text.substr(i, j - i));
    }
    i = j;
  }
}

bool ParseInt(std::string_view t, std::int64_t& value)
{
  if (!t.empty() && t.front() == '+')
  {
    t.remove_prefix(1);
  }
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  return ec == std::errc() && ptr == t.data() + t.size();
}

bool ParseDouble(std::string_view t, double& value)
{
  if (!t.empty() && t.front() == '+')
  {
    t.remove_prefix(1);
  }
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  return ec == std::errc() && ptr == t.data() + t.size() && std::isfinite(value);
}

bool LooksIntegral(std::string_view t)
{
  return t.find_first_of(".eEnNiI") == std::string_view::npos;
}

// Parses 3 or 4 colour components (integers 0-255 or floats 0-1) into RGBA.
bool ParseColor(const std::string_view* t, std::size_t count, std::uint8_t* rgba)
{
  rgba[3] = 255;
  for (std::size_t k = 0; k < count; ++k)
  {
    double v;
    if (!ParseDouble(t[k], v))
    {
      return false;
    }
    if (LooksIntegral(t[k]))
    {
      if (v < 0 || v > 255)
      {
        return false;
      }
      rgba[k] = static_cast<std::uint8_t>(v);
    }
    else
    {
      rgba[k] = static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
    }
  }
  return true;
}

struct Fail
{
  std::string& Error;
  OFFMesh& Mesh;
  bool operator()(std::int64_t line, const std::string& message) const
  {
    std::ostringstream os;
    if (line > 0)
    {
      os << "line " << line << ": ";
    }
    os << message;
    Error = os.str();
    Mesh = OFFMesh();
    return false;
  }
};

/// The parse of one file: the lines, the current line `At` and its tokens,
/// the header's flags and counts; each stage returns false after `Fail`.
struct Parser
{
  const std::vector<Line>& Lines;
  const Fail& Failed;
  OFFMesh& Mesh;
  std::vector<std::string_view> Tokens;
  std::size_t At = 0;
  bool HasTexture = false, HasColor = false, HasNormal = false;
  std::int64_t NumVertices = -1, NumFaces = -1;

  bool Header();
  bool Vertices();
  bool Faces();
};

/// The keyword [ST][C][N][4][n]OFF (optional) and the counts.
bool Parser::Header()
{
  Tokenize(Lines[0].Text, Tokens);
  std::size_t first = 0;
  std::int64_t probe;
  if (!ParseInt(Tokens[0], probe))
  {
    std::string_view key = Tokens[0];
    if (key.substr(0, 2) == "ST")
    {
      HasTexture = true;
      key.remove_prefix(2);
    }
    if (!key.empty() && key.front() == 'C')
    {
      HasColor = true;
      key.remove_prefix(1);
    }
    if (!key.empty() && key.front() == 'N')
    {
      HasNormal = true;
      key.remove_prefix(1);
    }
    if (!key.empty() && (key.front() == '4' || key.front() == 'n'))
    {
      return Failed(Lines[0].Number, "4D and n-dimensional OFF files are not supported");
    }
    if (key != "OFF")
    {
      return Failed(Lines[0].Number,
        "not an OFF file: header '" + std::string(Tokens[0].substr(0, 32)) + "'");
    }
    if (Tokens.size() > 1 && Tokens[1] == "BINARY")
    {
      return Failed(Lines[0].Number, "binary OFF files are not supported");
    }
    first = 1;
    if (Tokens.size() <= 1)
    {
      At = 1;
      if (At >= Lines.size())
      {
        return Failed(Lines[0].Number, "missing vertex and face counts");
      }
      Tokenize(Lines[At].Text, Tokens);
      first = 0;
    }
  }
  if (Tokens.size() < first + 2 || !ParseInt(Tokens[first], NumVertices) ||
    !ParseInt(Tokens[first + 1], NumFaces) || NumVertices < 0 || NumFaces < 0)
  {
    return Failed(Lines[At].Number, "expected non-negative vertex and face counts");
  }
  ++At;
  const std::int64_t available = static_cast<std::int64_t>(Lines.size() - At);
  if (NumVertices > available || NumFaces > available - NumVertices)
  {
    std::ostringstream os;
    os << "the header declares " << NumVertices << " vertices and " << NumFaces
       << " faces but only " << available << " data lines follow (truncated or corrupt file)";
    return Failed(Lines[At - 1].Number, os.str());
  }

  return true;
}

/// The vertex lines: points, and normals, colours and texture coordinates
/// as the keyword says.
bool Parser::Vertices()
{
  const std::size_t base = 3 + (HasNormal ? 3 : 0);
  Mesh.Points.resize(3 * NumVertices);
  if (HasNormal)
  {
    Mesh.Normals.resize(3 * NumVertices);
  }
  if (HasColor)
  {
    Mesh.PointColors.resize(4 * NumVertices);
  }
  if (HasTexture)
  {
    Mesh.TextureCoords.resize(2 * NumVertices);
  }
  for (std::int64_t v = 0; v < NumVertices; ++v, ++At)
  {
    Tokenize(Lines[At].Text, Tokens);
    const std::int64_t number = Lines[At].Number;
    std::size_t colorCount = 0;
    if (HasColor)
    {
      const std::int64_t rest = static_cast<std::int64_t>(Tokens.size()) -
        static_cast<std::int64_t>(base) - (HasTexture ? 2 : 0);
      colorCount = rest >= 4 ? 4 : 3;
    }
    const std::size_t needed = base + colorCount + (HasTexture ? 2 : 0);
    if (Tokens.size() < needed)
    {
      return Failed(number, "vertex line has too few values");
    }
    for (int d = 0; d < 3; ++d)
    {
      if (!ParseDouble(Tokens[d], Mesh.Points[3 * v + d]))
      {
        return Failed(number, "invalid or non-finite vertex coordinate '" +
            std::string(Tokens[d].substr(0, 32)) + "'");
      }
    }
    for (int d = 0; d < 3 && HasNormal; ++d)
    {
      if (!ParseDouble(Tokens[3 + d], Mesh.Normals[3 * v + d]))
      {
        return Failed(number, "invalid vertex normal");
      }
    }
    if (HasColor)
    {
      if (!ParseColor(&Tokens[base], colorCount, &Mesh.PointColors[4 * v]))
      {
        return Failed(number, "invalid vertex colour");
      }
      Mesh.HasPointAlpha = Mesh.HasPointAlpha || colorCount == 4;
    }
    for (int d = 0; d < 2 && HasTexture; ++d)
    {
      if (!ParseDouble(Tokens[base + colorCount + d], Mesh.TextureCoords[2 * v + d]))
      {
        return Failed(number, "invalid texture coordinate");
      }
    }
  }

  return true;
}

/// The face lines: vertex ids (validated), and colours where a line has 3
/// or 4 values after them.
bool Parser::Faces()
{
  Mesh.FaceOffsets.reserve(NumFaces + 1);
  Mesh.FaceOffsets.push_back(0);
  bool anyFaceColor = false;
  std::vector<std::uint8_t> faceColors;
  for (std::int64_t f = 0; f < NumFaces; ++f, ++At)
  {
    Tokenize(Lines[At].Text, Tokens);
    const std::int64_t number = Lines[At].Number;
    std::int64_t n;
    if (!ParseInt(Tokens[0], n) || n < 3)
    {
      return Failed(number, "expected a face with at least 3 vertices");
    }
    if (static_cast<std::uint64_t>(n) > Tokens.size() - 1)
    {
      return Failed(number, "face declares more vertices than the line holds");
    }
    for (std::int64_t k = 1; k <= n; ++k)
    {
      std::int64_t id;
      if (!ParseInt(Tokens[k], id) || id < 0 || id >= NumVertices)
      {
        return Failed(number, "face vertex index '" + std::string(Tokens[k].substr(0, 32)) +
            "' is not in [0, " + std::to_string(NumVertices) + ")");
      }
      Mesh.FaceIndices.push_back(id);
    }
    Mesh.FaceOffsets.push_back(static_cast<std::int64_t>(Mesh.FaceIndices.size()));
    const std::size_t extra = Tokens.size() - 1 - static_cast<std::size_t>(n);
    std::uint8_t rgba[4] = { 200, 200, 200, 255 };
    if (extra == 3 || extra == 4)
    {
      if (!ParseColor(&Tokens[1 + n], extra, rgba))
      {
        return Failed(number, "invalid face colour");
      }
      anyFaceColor = true;
      Mesh.HasFaceAlpha = Mesh.HasFaceAlpha || extra == 4;
    }
    faceColors.insert(faceColors.end(), rgba, rgba + 4);
  }
  if (anyFaceColor)
  {
    Mesh.FaceColors = std::move(faceColors);
  }
  return true;
}

} // namespace

bool ParseOFF(const char* data, std::size_t size, OFFMesh& mesh, std::string& error)
{
  mesh = OFFMesh();
  error.clear();
  const Fail fail{ error, mesh };
  const std::vector<Line> lines = SplitLines(data, size);
  if (lines.empty())
  {
    return fail(0, "empty file (no OFF header)");
  }
  Parser parser{ lines, fail, mesh };
  return parser.Header() && parser.Vertices() && parser.Faces();
}

bool ReadOFFFile(const std::string& fileName, OFFMesh& mesh, std::string& error)
{
  mesh = OFFMesh();
  std::ifstream in(fileName, std::ios::binary);
  if (!in)
  {
    error = "cannot open file '" + fileName + "'";
    return false;
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad())
  {
    error = "error while reading file '" + fileName + "'";
    return false;
  }
  const std::string text = buffer.str();
  return ParseOFF(text.data(), text.size(), mesh, error);
}

} // namespace beltrami
