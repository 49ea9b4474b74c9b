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
  std::vector<std::string_view> tokens;
  Tokenize(lines[0].Text, tokens);

  // Header keyword: [ST][C][N][4][n]OFF, optional.
  bool hasTexture = false, hasColor = false, hasNormal = false;
  std::size_t line = 0, first = 0;
  std::int64_t probe;
  if (!ParseInt(tokens[0], probe))
  {
    std::string_view key = tokens[0];
    if (key.substr(0, 2) == "ST")
    {
      hasTexture = true;
      key.remove_prefix(2);
    }
    if (!key.empty() && key.front() == 'C')
    {
      hasColor = true;
      key.remove_prefix(1);
    }
    if (!key.empty() && key.front() == 'N')
    {
      hasNormal = true;
      key.remove_prefix(1);
    }
    if (!key.empty() && (key.front() == '4' || key.front() == 'n'))
    {
      return fail(lines[0].Number, "4D and n-dimensional OFF files are not supported");
    }
    if (key != "OFF")
    {
      return fail(lines[0].Number,
        "not an OFF file: header '" + std::string(tokens[0].substr(0, 32)) + "'");
    }
    if (tokens.size() > 1 && tokens[1] == "BINARY")
    {
      return fail(lines[0].Number, "binary OFF files are not supported");
    }
    first = 1;
    if (tokens.size() <= 1)
    {
      line = 1;
      if (line >= lines.size())
      {
        return fail(lines[0].Number, "missing vertex and face counts");
      }
      Tokenize(lines[line].Text, tokens);
      first = 0;
    }
  }
  std::int64_t numVertices = -1, numFaces = -1;
  if (tokens.size() < first + 2 || !ParseInt(tokens[first], numVertices) ||
    !ParseInt(tokens[first + 1], numFaces) || numVertices < 0 || numFaces < 0)
  {
    return fail(lines[line].Number, "expected non-negative vertex and face counts");
  }
  ++line;
  const std::int64_t available = static_cast<std::int64_t>(lines.size() - line);
  if (numVertices > available || numFaces > available - numVertices)
  {
    std::ostringstream os;
    os << "the header declares " << numVertices << " vertices and " << numFaces
       << " faces but only " << available << " data lines follow (truncated or corrupt file)";
    return fail(lines[line - 1].Number, os.str());
  }

  // Vertices.
  const std::size_t base = 3 + (hasNormal ? 3 : 0);
  mesh.Points.resize(3 * numVertices);
  if (hasNormal)
  {
    mesh.Normals.resize(3 * numVertices);
  }
  if (hasColor)
  {
    mesh.PointColors.resize(4 * numVertices);
  }
  if (hasTexture)
  {
    mesh.TextureCoords.resize(2 * numVertices);
  }
  for (std::int64_t v = 0; v < numVertices; ++v, ++line)
  {
    Tokenize(lines[line].Text, tokens);
    const std::int64_t number = lines[line].Number;
    std::size_t colorCount = 0;
    if (hasColor)
    {
      const std::int64_t rest = static_cast<std::int64_t>(tokens.size()) -
        static_cast<std::int64_t>(base) - (hasTexture ? 2 : 0);
      colorCount = rest >= 4 ? 4 : 3;
    }
    const std::size_t needed = base + colorCount + (hasTexture ? 2 : 0);
    if (tokens.size() < needed)
    {
      return fail(number, "vertex line has too few values");
    }
    for (int d = 0; d < 3; ++d)
    {
      if (!ParseDouble(tokens[d], mesh.Points[3 * v + d]))
      {
        return fail(number, "invalid or non-finite vertex coordinate '" +
            std::string(tokens[d].substr(0, 32)) + "'");
      }
    }
    for (int d = 0; d < 3 && hasNormal; ++d)
    {
      if (!ParseDouble(tokens[3 + d], mesh.Normals[3 * v + d]))
      {
        return fail(number, "invalid vertex normal");
      }
    }
    if (hasColor)
    {
      if (!ParseColor(&tokens[base], colorCount, &mesh.PointColors[4 * v]))
      {
        return fail(number, "invalid vertex colour");
      }
      mesh.HasPointAlpha = mesh.HasPointAlpha || colorCount == 4;
    }
    for (int d = 0; d < 2 && hasTexture; ++d)
    {
      if (!ParseDouble(tokens[base + colorCount + d], mesh.TextureCoords[2 * v + d]))
      {
        return fail(number, "invalid texture coordinate");
      }
    }
  }

  // Faces.
  mesh.FaceOffsets.reserve(numFaces + 1);
  mesh.FaceOffsets.push_back(0);
  bool anyFaceColor = false;
  std::vector<std::uint8_t> faceColors;
  for (std::int64_t f = 0; f < numFaces; ++f, ++line)
  {
    Tokenize(lines[line].Text, tokens);
    const std::int64_t number = lines[line].Number;
    std::int64_t n;
    if (!ParseInt(tokens[0], n) || n < 3)
    {
      return fail(number, "expected a face with at least 3 vertices");
    }
    if (static_cast<std::uint64_t>(n) > tokens.size() - 1)
    {
      return fail(number, "face declares more vertices than the line holds");
    }
    for (std::int64_t k = 1; k <= n; ++k)
    {
      std::int64_t id;
      if (!ParseInt(tokens[k], id) || id < 0 || id >= numVertices)
      {
        return fail(number, "face vertex index '" + std::string(tokens[k].substr(0, 32)) +
            "' is not in [0, " + std::to_string(numVertices) + ")");
      }
      mesh.FaceIndices.push_back(id);
    }
    mesh.FaceOffsets.push_back(static_cast<std::int64_t>(mesh.FaceIndices.size()));
    const std::size_t extra = tokens.size() - 1 - static_cast<std::size_t>(n);
    std::uint8_t rgba[4] = { 200, 200, 200, 255 };
    if (extra == 3 || extra == 4)
    {
      if (!ParseColor(&tokens[1 + n], extra, rgba))
      {
        return fail(number, "invalid face colour");
      }
      anyFaceColor = true;
      mesh.HasFaceAlpha = mesh.HasFaceAlpha || extra == 4;
    }
    faceColors.insert(faceColors.end(), rgba, rgba + 4);
  }
  if (anyFaceColor)
  {
    mesh.FaceColors = std::move(faceColors);
  }
  return true;
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
