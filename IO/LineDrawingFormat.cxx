#include "LineDrawingFormat.h"

#include <cairo-pdf.h>
#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

namespace beltrami
{

namespace
{

using P3 = std::array<double, 3>;

double Dot(const P3& a, const P3& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

P3 Cross(const P3& a, const P3& b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

P3 Unit(const P3& a)
{
  const double n = std::sqrt(Dot(a, a));
  return n > 0.0 ? P3{ a[0] / n, a[1] / n, a[2] / n } : P3{ 0.0, 0.0, 0.0 };
}

/// Projects points onto the camera's image plane (right, up), perspective
/// or parallel; points at or behind the eye are not valid.
class Projection
{
public:
  Projection(const LineDrawingCamera& c, const LineDrawingInput& lines)
    : Parallel(c.Parallel)
    , Eye{ c.Position[0], c.Position[1], c.Position[2] }
  {
    Forward = Unit({ c.Direction[0], c.Direction[1], c.Direction[2] });
    if (Dot(Forward, Forward) == 0.0)
    {
      Forward = { 0.0, 0.0, -1.0 };
    }
    P3 up{ c.Up[0], c.Up[1], c.Up[2] };
    const double along = Dot(up, Forward);
    up = Unit({ up[0] - along * Forward[0], up[1] - along * Forward[1], up[2] - along * Forward[2] });
    if (Dot(up, up) == 0.0) // (up along the view: any perpendicular)
    {
      up = Unit(Cross(Forward, std::abs(Forward[0]) < 0.9 ? P3{ 1.0, 0.0, 0.0 } : P3{ 0.0, 1.0, 0.0 }));
    }
    Up = up;
    Right = Cross(Forward, Up);
    // Perspective: points nearer the eye's plane than 1e-9 of the farthest are cut.
    double far = 0.0;
    for (const std::int64_t i : lines.Connectivity)
    {
      far = std::max(far, Depth(lines.Points + 3 * i));
    }
    Near = 1e-9 * far;
  }
  bool Project(const double* p, double& x, double& y) const
  {
    if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])))
    {
      return false;
    }
    if (Parallel)
    {
      const P3 q{ p[0], p[1], p[2] };
      x = Dot(q, Right);
      y = Dot(q, Up);
      return true;
    }
    const double z = Depth(p);
    if (!(z > Near))
    {
      return false;
    }
    const P3 v{ p[0] - Eye[0], p[1] - Eye[1], p[2] - Eye[2] };
    x = Dot(v, Right) / z;
    y = Dot(v, Up) / z;
    return std::isfinite(x) && std::isfinite(y);
  }

private:
  double Depth(const double* p) const
  {
    return Dot({ p[0] - Eye[0], p[1] - Eye[1], p[2] - Eye[2] }, Forward);
  }
  bool Parallel;
  P3 Eye, Forward{}, Up{}, Right{};
  double Near = 0.0;
};

/// A polyline on the image plane with a width factor per point.
struct Piece
{
  int Style = 0;
  bool Closed = false;
  std::vector<double> XY, Factor;
};

/// The lines cut into pieces of projectable points (hidden ones dropped
/// unless drawn).
std::vector<Piece> ProjectLines(const LineDrawingInput& lines, const LineDrawingCamera& camera,
  const LineDrawingPageOptions& options, const std::vector<double>& factor)
{
  const Projection projection(camera, lines);
  std::vector<Piece> pieces;
  for (std::size_t l = 0; l + 1 < lines.Offsets.size(); ++l)
  {
    const bool hidden = !lines.Hidden.empty() && lines.Hidden[l] != 0;
    if (hidden && !options.DrawHidden)
    {
      continue;
    }
    const std::int64_t begin = lines.Offsets[l], end = lines.Offsets[l + 1];
    const std::size_t first = pieces.size();
    bool open = false;
    for (std::int64_t k = begin; k < end; ++k)
    {
      const std::int64_t i = lines.Connectivity[k];
      double x, y;
      if (!projection.Project(lines.Points + 3 * i, x, y))
      {
        open = false;
        continue;
      }
      if (!open)
      {
        pieces.emplace_back();
        pieces.back().Style = hidden ? HiddenStyle : lines.Types[l];
        open = true;
      }
      pieces.back().XY.insert(pieces.back().XY.end(), { x, y });
      pieces.back().Factor.push_back(hidden ? 1.0 : factor[i]);
    }
    const bool closed = end - begin > 2 && lines.Connectivity[begin] == lines.Connectivity[end - 1];
    if (closed && pieces.size() == first + 1 && pieces.back().XY.size() == 2 * static_cast<std::size_t>(end - begin))
    {
      pieces.back().Closed = true;
    }
  }
  pieces.erase(std::remove_if(pieces.begin(), pieces.end(), [](const Piece& p) { return p.XY.size() < 4; }),
    pieces.end());
  return pieces;
}

/// Per point: the width factor of tapering (1 without): the strength over
/// twice the median strength of its line type's points, in [0.2, 1], for
/// suggestive contours and highlights, ridges, valleys and apparent ridges.
std::vector<double> TaperFactors(const LineDrawingInput& lines, const LineDrawingPageOptions& options)
{
  std::size_t points = 0;
  for (const std::int64_t i : lines.Connectivity)
  {
    points = std::max(points, static_cast<std::size_t>(i) + 1);
  }
  std::vector<double> factor(points, 1.0);
  if (!options.TaperByStrength || !lines.PointStrength)
  {
    return factor;
  }
  for (const int type : { 1, 2, 3, 4, 7 })
  {
    std::vector<double> strengths;
    for (std::size_t l = 0; l < lines.Types.size(); ++l)
    {
      for (std::int64_t k = lines.Offsets[l]; k < lines.Offsets[l + 1] && lines.Types[l] == type; ++k)
      {
        strengths.push_back(std::abs(lines.PointStrength[lines.Connectivity[k]]));
      }
    }
    if (strengths.empty())
    {
      continue;
    }
    std::nth_element(strengths.begin(), strengths.begin() + strengths.size() / 2, strengths.end());
    const double reference = 2.0 * strengths[strengths.size() / 2];
    for (std::size_t l = 0; l < lines.Types.size(); ++l)
    {
      for (std::int64_t k = lines.Offsets[l]; k < lines.Offsets[l + 1] && lines.Types[l] == type; ++k)
      {
        const std::int64_t i = lines.Connectivity[k];
        const double s = std::abs(lines.PointStrength[i]);
        factor[i] = reference > 0.0 && std::isfinite(s) ? std::clamp(s / reference, 0.2, 1.0) : 1.0;
      }
    }
  }
  return factor;
}

/// Joins open pieces of one style whose ends meet (within `tolerance`, on
/// the page) where exactly two ends meet.
void JoinPieces(std::vector<Piece>& pieces, double tolerance)
{
  // Ends by (style, cell of the page): a pair of ends in one cell joins.
  std::map<std::array<long long, 3>, std::vector<std::size_t>> ends; // value: 2 * piece + end
  const auto key = [&](const Piece& p, int end) {
    const std::size_t at = end == 0 ? 0 : p.XY.size() - 2;
    return std::array<long long, 3>{ p.Style, std::llround(p.XY[at] / tolerance), std::llround(p.XY[at + 1] / tolerance) };
  };
  for (std::size_t i = 0; i < pieces.size(); ++i)
  {
    for (int e = 0; e < 2 && !pieces[i].Closed; ++e)
    {
      ends[key(pieces[i], e)].push_back(2 * i + e);
    }
  }
  std::vector<std::int64_t> partner(2 * pieces.size(), -1);
  for (const auto& [cell, list] : ends)
  {
    if (list.size() == 2 && list[0] / 2 != list[1] / 2)
    {
      partner[list[0]] = static_cast<std::int64_t>(list[1]);
      partner[list[1]] = static_cast<std::int64_t>(list[0]);
    }
  }
  const auto reversed = [](Piece p) {
    for (std::size_t a = 0, b = p.XY.size() - 2; a < b; a += 2, b -= 2)
    {
      std::swap(p.XY[a], p.XY[b]);
      std::swap(p.XY[a + 1], p.XY[b + 1]);
    }
    std::reverse(p.Factor.begin(), p.Factor.end());
    return p;
  };
  std::vector<std::uint8_t> used(pieces.size(), 0);
  std::vector<Piece> joined;
  const auto walk = [&](std::size_t i, int start) {
    Piece chain = start == 0 ? pieces[i] : reversed(pieces[i]);
    used[i] = 1;
    for (std::int64_t next = partner[2 * i + 1 - start]; next >= 0 && !used[next / 2];)
    {
      const std::size_t j = static_cast<std::size_t>(next / 2);
      const int entry = static_cast<int>(next % 2);
      const Piece add = entry == 0 ? pieces[j] : reversed(pieces[j]);
      chain.XY.insert(chain.XY.end(), add.XY.begin() + 2, add.XY.end());
      chain.Factor.insert(chain.Factor.end(), add.Factor.begin() + 1, add.Factor.end());
      used[j] = 1;
      next = partner[2 * j + 1 - entry];
    }
    joined.push_back(std::move(chain));
  };
  for (std::size_t i = 0; i < pieces.size(); ++i)
  {
    for (int e = 0; e < 2 && !used[i]; ++e)
    {
      if (pieces[i].Closed || partner[2 * i + e] < 0)
      {
        walk(i, e);
      }
    }
  }
  for (std::size_t i = 0; i < pieces.size(); ++i)
  {
    if (!used[i])
    {
      walk(i, 0); // (a loop of pieces: open at one join)
    }
  }
  pieces.swap(joined);
}

/// Douglas & Peucker: the indices of the points of xy (n points) kept
/// within `tolerance`, and every point where the width changes.
std::vector<std::size_t> Simplify(const std::vector<double>& xy, const std::vector<double>& width, double tolerance)
{
  const std::size_t n = xy.size() / 2;
  std::vector<std::uint8_t> keep(n, 0);
  keep[0] = keep[n - 1] = 1;
  for (std::size_t i = 1; i + 1 < n; ++i)
  {
    keep[i] = width[i] != width[i - 1] || width[i] != width[i + 1];
  }
  std::vector<std::pair<std::size_t, std::size_t>> stack{ { 0, n - 1 } };
  while (!stack.empty())
  {
    const auto [a, b] = stack.back();
    stack.pop_back();
    const double ax = xy[2 * a], ay = xy[2 * a + 1], dx = xy[2 * b] - ax, dy = xy[2 * b + 1] - ay;
    const double length2 = dx * dx + dy * dy;
    double worst = -1.0;
    std::size_t at = a;
    for (std::size_t i = a + 1; i < b; ++i)
    {
      const double px = xy[2 * i] - ax, py = xy[2 * i + 1] - ay;
      const double t = length2 > 0.0 ? std::clamp((px * dx + py * dy) / length2, 0.0, 1.0) : 0.0;
      const double ex = px - t * dx, ey = py - t * dy, d2 = ex * ex + ey * ey;
      if (d2 > worst)
      {
        worst = d2;
        at = i;
      }
    }
    if (worst > tolerance * tolerance)
    {
      keep[at] = 1;
      stack.emplace_back(a, at);
      stack.emplace_back(at, b);
    }
  }
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (keep[i])
    {
      kept.push_back(i);
    }
  }
  return kept;
}

/// The order styles are drawn in: hidden lines under everything, contours on top.
constexpr int DrawingOrder[NumberOfDrawingStyles] = { HiddenStyle, 3, 4, 2, 1, 7, 6, 5, 0 };

std::string Number(double x)
{
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", x);
  std::string s(text);
  while (!s.empty() && s.back() == '0')
  {
    s.pop_back();
  }
  if (!s.empty() && s.back() == '.')
  {
    s.pop_back();
  }
  return s == "-0" ? "0" : s;
}

} // namespace

LineDrawingPageOptions::LineDrawingPageOptions()
{
  // Like the suggestive contours paper's figures: black contours, thinner
  // suggestive contours; highlights grey; hidden lines grey and dashed.
  const double widths[NumberOfDrawingStyles] = { 1.2, 0.7, 0.7, 0.6, 0.6, 1.2, 0.9, 0.7, 0.5 };
  for (int s = 0; s < NumberOfDrawingStyles; ++s)
  {
    Styles[s].Width = widths[s];
  }
  for (int s : { 2, HiddenStyle })
  {
    std::fill(Styles[s].Color, Styles[s].Color + 3, 0.55);
  }
  Styles[HiddenStyle].Dash = 2.5;
}

const char* LineStyleName(int style)
{
  static const char* names[NumberOfDrawingStyles] = { "contour", "suggestive-contour", "suggestive-highlight",
    "ridge", "valley", "boundary", "crease", "apparent-ridge", "hidden" };
  return style >= 0 && style < NumberOfDrawingStyles ? names[style] : "unknown";
}

LineDrawingPage LayOutLineDrawing(const LineDrawingInput& lines, const LineDrawingCamera& camera,
  const LineDrawingPageOptions& options)
{
  std::vector<Piece> pieces = ProjectLines(lines, camera, options, TaperFactors(lines, options));
  LineDrawingPage page;
  double lo[2] = { HUGE_VAL, HUGE_VAL }, hi[2] = { -HUGE_VAL, -HUGE_VAL };
  for (const Piece& p : pieces)
  {
    for (std::size_t k = 0; k < p.XY.size(); ++k)
    {
      lo[k % 2] = std::min(lo[k % 2], p.XY[k]);
      hi[k % 2] = std::max(hi[k % 2], p.XY[k]);
    }
  }
  const double margin = std::max(options.Margin, 0.0);
  const double inner = std::max(options.PageSize - 2.0 * margin, 1.0);
  if (pieces.empty())
  {
    page.Width = page.Height = inner + 2.0 * margin;
    return page;
  }
  const double extent = std::max(hi[0] - lo[0], hi[1] - lo[1]);
  const double scale = extent > 0.0 ? inner / extent : 1.0;
  page.Width = (hi[0] - lo[0]) * scale + 2.0 * margin;
  page.Height = (hi[1] - lo[1]) * scale + 2.0 * margin;
  for (Piece& p : pieces)
  {
    for (std::size_t k = 0; k < p.XY.size(); k += 2)
    {
      p.XY[k] = margin + (p.XY[k] - lo[0]) * scale;
      p.XY[k + 1] = margin + (hi[1] - p.XY[k + 1]) * scale; // (y down)
    }
  }
  const double tolerance = options.Tolerance > 0.0 ? options.Tolerance : 1e-3;
  JoinPieces(pieces, tolerance);
  // Widths quantized to 1/8 of the style's (tapering), a path per run of one
  // width, simplified; in drawing order.
  for (const int style : DrawingOrder)
  {
    for (const Piece& p : pieces)
    {
      if (p.Style != style)
      {
        continue;
      }
      std::vector<double> width(p.Factor.size());
      for (std::size_t i = 0; i < width.size(); ++i)
      {
        width[i] = options.Styles[style].Width * std::ceil(8.0 * p.Factor[i]) / 8.0;
      }
      const std::vector<std::size_t> kept = Simplify(p.XY, width, tolerance);
      const std::size_t segments = kept.size() - 1;
      const auto segmentWidth = [&](std::size_t i) { return std::min(width[kept[i]], width[kept[i + 1]]); };
      for (std::size_t a = 0; a < segments;)
      {
        std::size_t b = a + 1; // segments [a, b) of one width: points a .. b
        while (b < segments && segmentWidth(b) == segmentWidth(a))
        {
          ++b;
        }
        PagePath path;
        path.Style = style;
        path.Width = segmentWidth(a);
        path.Closed = p.Closed && a == 0 && b == segments;
        for (std::size_t k = a; k <= b - (path.Closed ? 1 : 0); ++k)
        {
          path.XY.insert(path.XY.end(), { p.XY[2 * kept[k]], p.XY[2 * kept[k] + 1] });
        }
        page.Paths.push_back(std::move(path));
        a = b;
      }
    }
  }
  return page;
}

std::string LineDrawingSvg(const LineDrawingPage& page, const LineDrawingPageOptions& options)
{
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << Number(page.Width) << "pt\" height=\""
      << Number(page.Height) << "pt\" viewBox=\"0 0 " << Number(page.Width) << " " << Number(page.Height) << "\">\n";
  std::size_t i = 0;
  while (i < page.Paths.size())
  {
    const PagePath& first = page.Paths[i];
    const LineStyle& style = options.Styles[first.Style];
    char color[8];
    std::snprintf(color, sizeof color, "#%02x%02x%02x", static_cast<int>(std::lround(255 * std::clamp(style.Color[0], 0.0, 1.0))),
      static_cast<int>(std::lround(255 * std::clamp(style.Color[1], 0.0, 1.0))),
      static_cast<int>(std::lround(255 * std::clamp(style.Color[2], 0.0, 1.0))));
    out << "<g class=\"" << LineStyleName(first.Style) << "\" fill=\"none\" stroke=\"" << color << "\" stroke-width=\""
        << Number(first.Width) << "\" stroke-linecap=\"round\" stroke-linejoin=\"round\"";
    if (style.Dash > 0.0)
    {
      out << " stroke-dasharray=\"" << Number(style.Dash) << " " << Number(style.Dash) << "\"";
    }
    out << ">\n";
    for (; i < page.Paths.size() && page.Paths[i].Style == first.Style && page.Paths[i].Width == first.Width; ++i)
    {
      const PagePath& p = page.Paths[i];
      out << "<path d=\"";
      for (std::size_t k = 0; k < p.XY.size(); k += 2)
      {
        out << (k == 0 ? "M" : " L") << Number(p.XY[k]) << "," << Number(p.XY[k + 1]);
      }
      out << (p.Closed ? " Z" : "") << "\"/>\n";
    }
    out << "</g>\n";
  }
  out << "</svg>\n";
  return out.str();
}

bool WriteLineDrawingPdf(const LineDrawingPage& page, const LineDrawingPageOptions& options,
  const std::string& path, std::string& error)
{
  cairo_surface_t* surface = cairo_pdf_surface_create(path.c_str(), page.Width, page.Height);
  cairo_t* cr = cairo_create(surface);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (const PagePath& p : page.Paths)
  {
    const LineStyle& style = options.Styles[p.Style];
    cairo_set_source_rgb(cr, style.Color[0], style.Color[1], style.Color[2]);
    cairo_set_line_width(cr, p.Width);
    const double dash[2] = { style.Dash, style.Dash };
    cairo_set_dash(cr, dash, style.Dash > 0.0 ? 2 : 0, 0.0);
    for (std::size_t k = 0; k < p.XY.size(); k += 2)
    {
      (k == 0 ? cairo_move_to : cairo_line_to)(cr, p.XY[k], p.XY[k + 1]);
    }
    if (p.Closed)
    {
      cairo_close_path(cr);
    }
    cairo_stroke(cr);
  }
  cairo_show_page(cr);
  const cairo_status_t drawn = cairo_status(cr);
  cairo_destroy(cr);
  cairo_surface_finish(surface);
  const cairo_status_t written = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  const cairo_status_t status = drawn != CAIRO_STATUS_SUCCESS ? drawn : written;
  if (status != CAIRO_STATUS_SUCCESS)
  {
    error = cairo_status_to_string(status);
    return false;
  }
  return true;
}

} // namespace beltrami
