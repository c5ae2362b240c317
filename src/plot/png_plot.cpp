#include "plot/png_plot.hpp"

#include "plot/bitmap_font.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace rcfd::plot {
namespace {

// ---------------------------------------------------------------------------
// Pixels

constexpr Rgb kWhite{255, 255, 255};
constexpr Rgb kText{25, 25, 25};
constexpr Rgb kFrame{70, 70, 70};
constexpr Rgb kGrid{226, 226, 226};
constexpr Rgb kLegendBorder{190, 190, 190};
constexpr Rgb kMissingCell{205, 205, 205};
constexpr double kBandAlpha = 0.22;

struct Rect {
  int left = 0, top = 0, width = 0, height = 0;
  int right() const { return left + width; }  // exclusive
  int bottom() const { return top + height; } // exclusive
  bool contains(int x, int y) const { return x >= left && x < right() && y >= top && y < bottom(); }
};

class Canvas {
public:
  Canvas(int width, int height, Rgb background)
      : width_(width), height_(height), rgb_(std::size_t(width) * height * 3) {
    for (std::size_t i = 0; i < rgb_.size(); i += 3) {
      rgb_[i] = background.r;
      rgb_[i + 1] = background.g;
      rgb_[i + 2] = background.b;
    }
  }

  int width() const { return width_; }
  int height() const { return height_; }

  /// Mixes colour c into pixel (x, y) with weight alpha; outside is ignored.
  void blend(int x, int y, Rgb c, double alpha) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_ || !(alpha > 0)) return;
    const double a = std::min(alpha, 1.0);
    std::uint8_t *p = &rgb_[(std::size_t(y) * width_ + x) * 3];
    const auto mix = [a](std::uint8_t under, std::uint8_t over) {
      return static_cast<std::uint8_t>(std::lround(under + (over - under) * a));
    };
    p[0] = mix(p[0], c.r);
    p[1] = mix(p[1], c.g);
    p[2] = mix(p[2], c.b);
  }

  void fillRect(const Rect &r, Rgb c, double alpha = 1.0) {
    for (int y = std::max(r.top, 0); y < std::min(r.bottom(), height_); ++y)
      for (int x = std::max(r.left, 0); x < std::min(r.right(), width_); ++x) blend(x, y, c, alpha);
  }

  /// One-pixel outline just outside r.
  void outline(const Rect &r, Rgb c) {
    fillRect({r.left - 1, r.top - 1, r.width + 2, 1}, c);
    fillRect({r.left - 1, r.bottom(), r.width + 2, 1}, c);
    fillRect({r.left - 1, r.top, 1, r.height}, c);
    fillRect({r.right(), r.top, 1, r.height}, c);
  }

  std::vector<std::uint8_t> take() { return std::move(rgb_); }

private:
  int width_, height_;
  std::vector<std::uint8_t> rgb_;
};

// Coverage in [0, 1] over a rectangle of the canvas.  Each series is drawn
// into its own mask first, combining pieces by maximum, so that overlapping
// pieces of one curve (segment joints, neighbouring band columns) do not show
// darker where they meet; the mask is then composited in one go.  The mask's
// rectangle is also the clip rectangle.
class Mask {
public:
  explicit Mask(const Rect &r) : rect_(r), cov_(std::size_t(r.width) * r.height, 0.0f) {}

  const Rect &rect() const { return rect_; }

  void cover(int x, int y, double c) {
    if (!rect_.contains(x, y)) return;
    float &v = cov_[index(x, y)];
    v = std::max(v, static_cast<float>(std::min(c, 1.0)));
  }

  void compositeOnto(Canvas &canvas, Rgb c, double alpha) const {
    for (int y = rect_.top; y < rect_.bottom(); ++y)
      for (int x = rect_.left; x < rect_.right(); ++x) {
        const float v = cov_[index(x, y)];
        if (v > 0) canvas.blend(x, y, c, v * alpha);
      }
  }

  /// Adds weight * coverage to ink (same rectangle), to find empty corners.
  void accumulateInto(std::vector<float> &ink, float weight) const {
    for (std::size_t i = 0; i < cov_.size(); ++i) ink[i] += weight * cov_[i];
  }

private:
  std::size_t index(int x, int y) const {
    return std::size_t(y - rect_.top) * rect_.width + (x - rect_.left);
  }

  Rect rect_;
  std::vector<float> cov_;
};

struct Point {
  double x = 0, y = 0;
};

bool finite(Point p) { return std::isfinite(p.x) && std::isfinite(p.y); }

// Liang-Barsky: shortens segment ab to its part inside [x0, x1] x [y0, y1];
// false when nothing is inside.
bool clipSegment(Point &a, Point &b, double x0, double y0, double x1, double y1) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  double t0 = 0, t1 = 1;
  const auto edge = [&](double p, double q) {
    if (p == 0) return q >= 0;
    const double t = q / p;
    if (p < 0) {
      if (t > t1) return false;
      t0 = std::max(t0, t);
    } else {
      if (t < t0) return false;
      t1 = std::min(t1, t);
    }
    return true;
  };
  if (!edge(-dx, a.x - x0) || !edge(dx, x1 - a.x) || !edge(-dy, a.y - y0) || !edge(dy, y1 - a.y))
    return false;
  const Point start{a.x + t0 * dx, a.y + t0 * dy};
  b = {a.x + t1 * dx, a.y + t1 * dy};
  a = start;
  return true;
}

// A round-capped stroke of half width hw: coverage falls off linearly over
// one pixel at the edge, which is a cheap but good-looking antialiasing.
void strokeSegment(Mask &mask, Point a, Point b, double hw) {
  const Rect &r = mask.rect();
  const double grow = hw + 2;
  if (!finite(a) || !finite(b) ||
      !clipSegment(a, b, r.left - grow, r.top - grow, r.right() + grow, r.bottom() + grow))
    return;
  const int xBegin = std::max(r.left, static_cast<int>(std::floor(std::min(a.x, b.x) - hw - 1)));
  const int xEnd = std::min(r.right(), static_cast<int>(std::ceil(std::max(a.x, b.x) + hw + 1)));
  const int yBegin = std::max(r.top, static_cast<int>(std::floor(std::min(a.y, b.y) - hw - 1)));
  const int yEnd = std::min(r.bottom(), static_cast<int>(std::ceil(std::max(a.y, b.y) + hw + 1)));
  const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
  const double reach2 = (hw + 0.5) * (hw + 0.5);
  for (int y = yBegin; y < yEnd; ++y)
    for (int x = xBegin; x < xEnd; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double t =
          len2 > 0 ? std::clamp(((px - a.x) * dx + (py - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
      const double ex = a.x + t * dx - px, ey = a.y + t * dy - py;
      const double d2 = ex * ex + ey * ey;
      if (d2 < reach2) mask.cover(x, y, hw + 0.5 - std::sqrt(d2));
    }
}

// The band between two vertical edges (x, yLow..yHigh) at a and b, filled
// column by column; partial coverage at the top and bottom of each column.
void fillBandPiece(Mask &mask, Point lowA, Point highA, Point lowB, Point highB) {
  if (!finite(lowA) || !finite(highA) || !finite(lowB) || !finite(highB)) return;
  if (lowA.x > lowB.x) {
    std::swap(lowA, lowB);
    std::swap(highA, highB);
  }
  if (!(lowB.x > lowA.x)) return;
  const Rect &r = mask.rect();
  // Columns whose centre lies in [a.x, b.x].
  const double first = std::max(std::ceil(lowA.x - 0.5), double(r.left));
  const double last = std::min(std::floor(lowB.x - 0.5), double(r.right() - 1));
  for (double col = first; col <= last; ++col) {
    const double t = (col + 0.5 - lowA.x) / (lowB.x - lowA.x);
    const double y1 = lowA.y + t * (lowB.y - lowA.y), y2 = highA.y + t * (highB.y - highA.y);
    const double top = std::max(std::min(y1, y2), double(r.top));
    const double bottom = std::min(std::max(y1, y2), double(r.bottom()));
    for (double row = std::floor(top); row < bottom; ++row) {
      const double c = std::min(row + 1, bottom) - std::max(row, top);
      if (c > 0) mask.cover(static_cast<int>(col), static_cast<int>(row), c);
    }
  }
}

// ---------------------------------------------------------------------------
// Text: the bitmap font enlarged by an integer scale.

struct TextStyle {
  int scale = 2;
  Rgb color = kText;
  bool bold = false; // drawn twice, one pixel apart
};

int textWidth(const std::string &text, const TextStyle &style) {
  const int n = static_cast<int>(font::decodeUtf8(text).size());
  return n > 0 ? font::runWidth(n) * style.scale + (style.bold ? 1 : 0) : 0;
}

int textHeight(int scale) { return font::kGlyphHeight * scale; }
int capHeight(int scale) { return font::kCapHeight * scale; }

// Calls put(u, v) for every inked font pixel of text, u along the text and v
// down from the glyph top, both in font pixels.
template <typename Put> void forEachInkedPixel(const std::string &text, Put &&put) {
  const std::u32string codes = font::decodeUtf8(text);
  for (std::size_t k = 0; k < codes.size(); ++k) {
    const font::Glyph &g = font::glyph(codes[k]);
    for (int row = 0; row < font::kGlyphHeight; ++row)
      for (int col = 0; col < font::kGlyphWidth; ++col)
        if (g[row] & (1u << (font::kGlyphWidth - 1 - col)))
          put(static_cast<int>(k) * font::kAdvance + col, row);
  }
}

/// Horizontal text with its top-left corner at (x, top).
void drawText(Canvas &canvas, int x, int top, const std::string &text, const TextStyle &style) {
  const int s = style.scale;
  forEachInkedPixel(text, [&](int u, int v) {
    for (int shift = 0; shift <= (style.bold ? 1 : 0); ++shift)
      canvas.fillRect({x + u * s + shift, top + v * s, s, s}, style.color);
  });
}

/// Text turned a quarter turn anticlockwise (read from bottom to top), for a
/// y-axis label; its glyph tops face left, at column `left`, and the text
/// starts at row `bottom` - 1 going up.
void drawTextUp(Canvas &canvas, int left, int bottom, const std::string &text,
                const TextStyle &style) {
  const int s = style.scale;
  forEachInkedPixel(text, [&](int u, int v) {
    for (int shift = 0; shift <= (style.bold ? 1 : 0); ++shift)
      canvas.fillRect({left + v * s, bottom - (u + 1) * s - shift, s, s}, style.color);
  });
}

// Splits text into lines at most maxWidth pixels wide, breaking at spaces and
// after slashes (paths); a piece longer than a line is cut.  Beyond maxLines
// the text is cut short with "...".  Empty text gives no lines.
std::vector<std::string> wrapText(const std::string &text, int maxWidth, const TextStyle &style,
                                  std::size_t maxLines) {
  const int advance = font::kAdvance * style.scale;
  const std::size_t perLine = static_cast<std::size_t>(std::max(
      1, (maxWidth - (style.bold ? 1 : 0) + advance - font::kGlyphWidth * style.scale) / advance));
  const std::u32string codes = font::decodeUtf8(text);
  std::vector<std::u32string> lines;
  std::u32string current;
  bool spaceBefore = false;
  for (std::size_t i = 0; i < codes.size();) {
    std::size_t j = i;
    while (j < codes.size() && codes[j] != U' ' && codes[j] != U'/') ++j;
    if (j < codes.size() && codes[j] == U'/') ++j;
    const std::u32string piece = codes.substr(i, j - i);
    const bool spaceAfter = j < codes.size() && codes[j] == U' ';
    i = spaceAfter ? j + 1 : j;
    if (piece.empty()) {
      spaceBefore = spaceBefore || spaceAfter;
      continue;
    }
    const bool joinWithSpace = spaceBefore && !current.empty();
    if (current.empty() || current.size() + joinWithSpace + piece.size() <= perLine) {
      if (joinWithSpace) current += U' ';
      current += piece;
    } else {
      lines.push_back(current);
      current = piece;
    }
    for (; current.size() > perLine; current.erase(0, perLine))
      lines.push_back(current.substr(0, perLine));
    spaceBefore = spaceAfter;
  }
  if (!current.empty()) lines.push_back(current);
  if (lines.size() > maxLines) {
    lines.resize(maxLines);
    std::u32string &last = lines.back();
    last.resize(std::min(last.size(), perLine > 3 ? perLine - 3 : 0));
    last += U"...";
  }
  std::vector<std::string> out;
  for (const auto &line : lines) out.push_back(font::encodeUtf8(line));
  return out;
}

// Height of a bold title of the given lines plus the space below it.
int titleBlockHeight(const std::vector<std::string> &lines, int scale) {
  const int n = static_cast<int>(lines.size());
  return n == 0 ? 0 : n * textHeight(scale) + (n - 1) * 2 * scale + 4 * scale;
}

// ---------------------------------------------------------------------------
// Ranges and ticks

struct Range {
  double lo = 0, hi = 1;
  double span() const { return hi - lo; }
};

struct Extent {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return lo > hi; }
};

// Axis limits from the data extent, a relative margin and the fixed limits
// (NaN = free).  A degenerate extent is widened so the axis has some length.
Range resolveRange(const Extent &data, double margin, double fixedLo, double fixedHi) {
  Range d{0, 1};
  if (!data.empty()) {
    d = {data.lo, data.hi};
    const double mid = 0.5 * (d.lo + d.hi);
    if (d.span() <= 1e-12 * std::max(std::fabs(d.lo), std::fabs(d.hi))) {
      const double half = mid != 0 ? 0.05 * std::fabs(mid) : 0.5;
      d = {mid - half, mid + half};
    } else {
      d = {d.lo - margin * d.span(), d.hi + margin * d.span()};
    }
  }
  Range r{std::isnan(fixedLo) ? d.lo : fixedLo, std::isnan(fixedHi) ? d.hi : fixedHi};
  if (!(r.hi > r.lo)) { // one limit fixed beyond the data: keep the data's span
    if (std::isnan(fixedHi))
      r.hi = r.lo + d.span();
    else
      r.lo = r.hi - d.span();
  }
  return r;
}

// Scientific notation when fixed-point labels would be long or all zeros.
bool useScientific(const Ticks &ticks) {
  double largest = 0;
  for (double v : ticks.values) largest = std::max(largest, std::fabs(v));
  return largest >= 1e6 || (ticks.step < 1e-4 && largest < 1e-3);
}

int decimalExponent(double v) {
  return static_cast<int>(std::floor(std::log10(std::fabs(v)) + 1e-9));
}

// "1.5e-05" -> "1.5e-5", "2e+06" -> "2e6".
std::string tidyExponent(const std::string &s) {
  const std::size_t e = s.find('e');
  if (e == std::string::npos) return s;
  std::string mantissa = s.substr(0, e), exponent = s.substr(e + 1);
  std::string sign;
  if (!exponent.empty() && (exponent[0] == '+' || exponent[0] == '-')) {
    if (exponent[0] == '-') sign = "-";
    exponent.erase(0, 1);
  }
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return mantissa + "e" + sign + exponent;
}

std::string formatNumber(const char *format, int digits, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, digits, v);
  return buffer;
}

// ---------------------------------------------------------------------------
// Figure layout

// Sizes in pixels for text scale s (font pixels per glyph pixel).
struct Metrics {
  int scale, pad, tick, gap;
  double lineHalfWidth; // >= 1 at scale 2, so a line fully covers the row through its centre
  explicit Metrics(int s)
      : scale(s), pad(6 * s), tick(3 * s), gap(2 * s), lineHalfWidth(s == 1 ? 0.7 : 1.1) {}
};

int textScaleFor(int width, int height) { return width >= 600 && height >= 400 ? 2 : 1; }

struct Geometry {
  PlotLayout layout;
  Metrics m{2};
  std::vector<std::string> xLabels, yLabels, titleLines;
  Rect area() const { return {layout.left, layout.top, layout.width, layout.height}; }
  Point toPixel(double x, double y) const {
    const PlotLayout &l = layout;
    return {l.left + 0.5 + (x - l.xMin) / (l.xMax - l.xMin) * (l.width - 1),
            l.top + 0.5 + (l.yMax - y) / (l.yMax - l.yMin) * (l.height - 1)};
  }
};

void validate(const Figure &fig) {
  if (fig.width < 240 || fig.height < 180 || fig.width > 16384 || fig.height > 16384)
    throw std::invalid_argument(
        "a figure must be between 240 x 180 and 16384 x 16384 pixels, not " +
        std::to_string(fig.width) + " x " + std::to_string(fig.height) + ".");
  for (const Series &s : fig.series) {
    const std::string name = s.label.empty() ? "an unlabelled series" : "series '" + s.label + "'";
    if (s.x.size() != s.y.size())
      throw std::invalid_argument(name + " has " + std::to_string(s.x.size()) + " x values but " +
                                  std::to_string(s.y.size()) + " y values.");
    if (s.yLow.size() != s.yHigh.size() || (!s.yLow.empty() && s.yLow.size() != s.x.size()))
      throw std::invalid_argument(name + " needs yLow and yHigh both empty or both with one value "
                                         "per x value.");
  }
  const auto checkLimits = [](double lo, double hi, const char *axis) {
    if (std::isinf(lo) || std::isinf(hi) || (!std::isnan(lo) && !std::isnan(hi) && !(lo < hi)))
      throw std::invalid_argument(std::string("the ") + axis +
                                  " limits of a figure must be finite with min < max.");
  };
  checkLimits(fig.xMin, fig.xMax, "x");
  checkLimits(fig.yMin, fig.yMax, "y");
}

Range xRangeOf(const Figure &fig) {
  Extent e;
  for (const Series &s : fig.series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      const bool band = !s.yLow.empty() && std::isfinite(s.yLow[i]) && std::isfinite(s.yHigh[i]);
      if (std::isfinite(s.y[i]) || band) e.add(s.x[i]);
    }
  return resolveRange(e, 0.0, fig.xMin, fig.xMax);
}

// Only points inside the x range count, so that a fixed x window scales y to
// what is visible.
Range yRangeOf(const Figure &fig, const Range &x) {
  Extent e;
  for (const Series &s : fig.series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!(s.x[i] >= x.lo && s.x[i] <= x.hi)) continue;
      e.add(s.y[i]);
      if (!s.yLow.empty()) {
        e.add(s.yLow[i]);
        e.add(s.yHigh[i]);
      }
    }
  return resolveRange(e, 0.05, fig.yMin, fig.yMax);
}

int widestLabel(const std::vector<std::string> &labels, const TextStyle &style) {
  int w = 0;
  for (const std::string &l : labels) w = std::max(w, textWidth(l, style));
  return w;
}

// The most x ticks whose labels still leave a gap between neighbours.
Ticks fittingXTicks(const Range &x, int plotWidth, const TextStyle &style, int minGap) {
  const int charWidth = font::kAdvance * style.scale;
  for (int maxTicks = std::max(2, plotWidth / (3 * charWidth)); maxTicks > 2; --maxTicks) {
    const Ticks t = niceTicks(x.lo, x.hi, maxTicks);
    const double spacing = t.step / x.span() * (plotWidth - 1);
    if (spacing >= widestLabel(tickLabels(t), style) + minGap) return t;
  }
  return niceTicks(x.lo, x.hi, 2);
}

Geometry computeGeometry(const Figure &fig) {
  validate(fig);
  Geometry g;
  g.m = Metrics(textScaleFor(fig.width, fig.height));
  const Metrics &m = g.m;
  const int s = m.scale;
  const TextStyle label{s};
  PlotLayout &l = g.layout;

  const Range x = xRangeOf(fig), y = yRangeOf(fig, x);
  l.xMin = x.lo;
  l.xMax = x.hi;
  l.yMin = y.lo;
  l.yMax = y.hi;

  g.titleLines = wrapText(fig.title, fig.width - 2 * m.pad, TextStyle{s, kText, true}, 3);
  const int titleBlock = titleBlockHeight(g.titleLines, s);
  const int xLabelBlock = fig.xLabel.empty() ? 0 : textHeight(s) + 3 * s;
  const int yLabelBlock = fig.yLabel.empty() ? 0 : textHeight(s) + 4 * s;

  // Vertical: title, half a tick label above the top tick, the plot, x ticks
  // and their labels, the x label.
  l.top = m.pad + titleBlock + capHeight(s) / 2 + 1;
  const int bottomMargin = 1 + m.tick + m.gap + capHeight(s) + xLabelBlock + m.pad;
  l.height = fig.height - l.top - bottomMargin;

  l.yTicks = niceTicks(y.lo, y.hi, std::max(2, l.height / (3 * capHeight(s))));
  g.yLabels = tickLabels(l.yTicks);

  // Horizontal: y label, y tick labels, the plot, room for half the last x
  // tick label.  The right margin depends on the x ticks, which depend on
  // the plot width, so settle it in two passes.
  l.left = m.pad + yLabelBlock + widestLabel(g.yLabels, label) + m.gap + m.tick + 1;
  int rightMargin = m.pad + 2 * font::kAdvance * s;
  for (int pass = 0; pass < 2; ++pass) {
    l.width = fig.width - l.left - rightMargin;
    l.xTicks = fittingXTicks(x, l.width, label, 4 * font::kAdvance * s / 2);
    g.xLabels = tickLabels(l.xTicks);
    if (l.xTicks.values.empty()) break;
    const double lastX = l.left + 0.5 + (l.xTicks.values.back() - x.lo) / x.span() * (l.width - 1);
    const int overhang =
        static_cast<int>(std::ceil(lastX + textWidth(g.xLabels.back(), label) / 2.0)) -
        (l.left + l.width);
    if (overhang + m.pad <= rightMargin) break;
    rightMargin = overhang + m.pad;
  }
  if (l.width < 40 || l.height < 40)
    throw std::invalid_argument("the figure is too small for its labels.");
  return g;
}

// ---------------------------------------------------------------------------
// Figure drawing

// Pixel column / row of an axis value, kept inside the plot area.
int tickColumn(const Geometry &g, double v) {
  const PlotLayout &l = g.layout;
  return std::clamp(static_cast<int>(std::floor(g.toPixel(v, l.yMin).x)), l.left,
                    l.left + l.width - 1);
}
int tickRow(const Geometry &g, double v) {
  const PlotLayout &l = g.layout;
  return std::clamp(static_cast<int>(std::floor(g.toPixel(l.xMin, v).y)), l.top,
                    l.top + l.height - 1);
}

void drawGrid(Canvas &canvas, const Geometry &g) {
  const Rect a = g.area();
  for (double v : g.layout.xTicks.values) {
    const int c = tickColumn(g, v);
    if (c > a.left && c < a.right() - 1) canvas.fillRect({c, a.top, 1, a.height}, kGrid);
  }
  for (double v : g.layout.yTicks.values) {
    const int r = tickRow(g, v);
    if (r > a.top && r < a.bottom() - 1) canvas.fillRect({a.left, r, a.width, 1}, kGrid);
  }
}

void drawAxes(Canvas &canvas, const Geometry &g) {
  const Rect a = g.area();
  const Metrics &m = g.m;
  const TextStyle style{m.scale};
  canvas.outline(a, kFrame);
  const int capH = capHeight(m.scale);
  for (std::size_t i = 0; i < g.layout.xTicks.values.size(); ++i) {
    const int c = tickColumn(g, g.layout.xTicks.values[i]);
    canvas.fillRect({c, a.bottom() + 1, 1, m.tick}, kFrame);
    const int w = textWidth(g.xLabels[i], style);
    drawText(canvas, c - (w - 1) / 2, a.bottom() + 1 + m.tick + m.gap, g.xLabels[i], style);
  }
  for (std::size_t i = 0; i < g.layout.yTicks.values.size(); ++i) {
    const int r = tickRow(g, g.layout.yTicks.values[i]);
    canvas.fillRect({a.left - 1 - m.tick, r, m.tick, 1}, kFrame);
    const int w = textWidth(g.yLabels[i], style);
    drawText(canvas, a.left - 1 - m.tick - m.gap - w, r - (capH - 1) / 2, g.yLabels[i], style);
  }
}

// Where a text of width w centred on cx goes, kept inside the image if it fits.
int centredLeft(int cx, int w, int imageWidth, int pad) {
  const int x = cx - w / 2;
  if (w + 2 * pad > imageWidth) return pad;
  return std::clamp(x, pad, imageWidth - pad - w);
}

void drawTitleLines(Canvas &canvas, const std::vector<std::string> &lines, int centreX,
                    const Metrics &m) {
  const TextStyle bold{m.scale, kText, true};
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int w = textWidth(lines[i], bold);
    drawText(canvas, centredLeft(centreX, w, canvas.width(), m.pad),
             m.pad + static_cast<int>(i) * (textHeight(m.scale) + 2 * m.scale), lines[i], bold);
  }
}

void drawTitles(Canvas &canvas, const Figure &fig, const Geometry &g) {
  const Metrics &m = g.m;
  const Rect a = g.area();
  const int s = m.scale;
  drawTitleLines(canvas, g.titleLines, a.left + a.width / 2, m);
  const TextStyle style{s};
  if (!fig.xLabel.empty()) {
    const int w = textWidth(fig.xLabel, style);
    const int top = a.bottom() + 1 + m.tick + m.gap + capHeight(s) + 3 * s;
    drawText(canvas, centredLeft(a.left + a.width / 2, w, canvas.width(), m.pad), top, fig.xLabel,
             style);
  }
  if (!fig.yLabel.empty()) {
    const int w = textWidth(fig.yLabel, style);
    const int bottom =
        w + 2 * m.pad > canvas.height()
            ? canvas.height() - m.pad
            : std::clamp(a.top + a.height / 2 + w / 2, m.pad + w, canvas.height() - m.pad);
    drawTextUp(canvas, m.pad, bottom, fig.yLabel, style);
  }
}

void rasterBand(Mask &mask, const Series &s, const Geometry &g) {
  for (std::size_t i = 0; i + 1 < s.x.size(); ++i)
    fillBandPiece(mask, g.toPixel(s.x[i], s.yLow[i]), g.toPixel(s.x[i], s.yHigh[i]),
                  g.toPixel(s.x[i + 1], s.yLow[i + 1]), g.toPixel(s.x[i + 1], s.yHigh[i + 1]));
}

void rasterLine(Mask &mask, const Series &s, const Geometry &g) {
  const double hw = g.m.lineHalfWidth;
  const std::size_t n = s.x.size();
  const auto valid = [&](std::size_t i) { return std::isfinite(s.x[i]) && std::isfinite(s.y[i]); };
  for (std::size_t i = 0; i < n; ++i) {
    if (!valid(i)) continue;
    const Point p = g.toPixel(s.x[i], s.y[i]);
    const bool next = i + 1 < n && valid(i + 1);
    const bool previous = i > 0 && valid(i - 1);
    if (next)
      strokeSegment(mask, p, g.toPixel(s.x[i + 1], s.y[i + 1]), hw);
    else if (!previous) // isolated point: a dot, or it would be invisible
      strokeSegment(mask, p, p, hw + 1.5);
  }
}

struct LegendBox {
  Rect rect;
  int rowHeight = 0, swatch = 0, inner = 0, gap = 0;
};

LegendBox legendBoxFor(const Figure &fig, const Geometry &g, const std::vector<int> &entries) {
  const int s = g.m.scale;
  LegendBox box;
  box.inner = 4 * s;
  box.swatch = 12 * s;
  box.gap = 4 * s;
  box.rowHeight = textHeight(s) + 2 * s;
  int widest = 0;
  for (int i : entries) widest = std::max(widest, textWidth(fig.series[i].label, TextStyle{s}));
  box.rect.width = 2 * box.inner + box.swatch + box.gap + widest;
  box.rect.height = 2 * box.inner + static_cast<int>(entries.size()) * box.rowHeight - 2 * s;
  return box;
}

// Where in the plot area the legend hides the least ink.  Candidates form a
// 5 x 5 grid spanning the area; corners are preferred (top right first),
// then edges, so the legend moves inwards only to uncover much more data.
void placeLegend(LegendBox &box, const Geometry &g, const std::vector<float> &ink) {
  const Rect a = g.area();
  const Rect &r = box.rect;
  const int inset = 4 * g.m.scale;
  const int x0 = a.left + inset, x1 = a.right() - inset - r.width;
  const int y0 = a.top + inset, y1 = a.bottom() - inset - r.height;
  constexpr int kSteps = 4;
  const double biasPerEdge = 0.03 * r.width * r.height;
  double best = HUGE_VAL;
  for (int j = 0; j <= kSteps; ++j)
    for (int ii = 0; ii <= kSteps; ++ii) {
      const int i = kSteps - ii; // right to left, so ties go to the right
      const int left = x0 + (x1 - x0) * i / kSteps, top = y0 + (y1 - y0) * j / kSteps;
      const int inner = (i % kSteps != 0) + (j % kSteps != 0);
      double covered = biasPerEdge * inner;
      for (int y = std::max(top, a.top); y < std::min(top + r.height, a.bottom()); ++y)
        for (int x = std::max(left, a.left); x < std::min(left + r.width, a.right()); ++x)
          covered += ink[std::size_t(y - a.top) * a.width + (x - a.left)];
      if (covered < best - 1e-6) {
        best = covered;
        box.rect.left = left;
        box.rect.top = top;
      }
    }
}

void drawLegend(Canvas &canvas, const Figure &fig, const Geometry &g,
                const std::vector<float> &ink) {
  std::vector<int> entries;
  for (std::size_t i = 0; i < fig.series.size(); ++i)
    if (!fig.series[i].label.empty()) entries.push_back(static_cast<int>(i));
  if (entries.empty()) return;
  LegendBox box = legendBoxFor(fig, g, entries);
  placeLegend(box, g, ink);
  canvas.fillRect(box.rect, kWhite, 0.9);
  canvas.outline({box.rect.left + 1, box.rect.top + 1, box.rect.width - 2, box.rect.height - 2},
                 kLegendBorder);
  const int s = g.m.scale;
  const int lineWidth = std::max(1, static_cast<int>(std::lround(2 * g.m.lineHalfWidth)));
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const Series &series = fig.series[entries[k]];
    const Rgb color = seriesColor(entries[k]);
    const int rowTop = box.rect.top + box.inner + static_cast<int>(k) * box.rowHeight;
    const int x = box.rect.left + box.inner;
    const int middle = rowTop + capHeight(s) / 2;
    if (!series.yLow.empty())
      canvas.fillRect({x, middle - 3 * s, box.swatch, 6 * s + 1}, color, kBandAlpha);
    const bool hasLine =
        std::any_of(series.y.begin(), series.y.end(), [](double v) { return std::isfinite(v); });
    if (hasLine) canvas.fillRect({x, middle - lineWidth / 2, box.swatch, lineWidth}, color);
    drawText(canvas, x + box.swatch + box.gap, rowTop, series.label, TextStyle{s});
  }
}

// ---------------------------------------------------------------------------
// Heat maps

// A colour scale of my own: dark blue through teal and green to yellow,
// brightening steadily so that it also reads in grey.
Rgb scaleColor(double t) {
  static constexpr std::array<std::array<double, 3>, 5> kStops = {
      {{24, 18, 64}, {38, 82, 158}, {28, 148, 146}, {118, 196, 84}, {248, 228, 64}}};
  t = std::clamp(t, 0.0, 1.0) * (kStops.size() - 1);
  const std::size_t i = std::min(static_cast<std::size_t>(t), kStops.size() - 2);
  const double f = t - i;
  const auto channel = [&](int c) {
    return static_cast<std::uint8_t>(
        std::lround(kStops[i][c] + f * (kStops[i + 1][c] - kStops[i][c])));
  };
  return {channel(0), channel(1), channel(2)};
}

// How matrix cells along one axis map to pixels: each cell `cell` pixels
// wide, or (when the matrix is large) each pixel the mean of `block` cells.
struct AxisSampling {
  int block = 1, cell = 1;
  int pixels(int n) const { return (n + block - 1) / block * cell; }
  int firstCell(int pixel) const { return pixel / cell * block; }
  int endCell(int pixel, int n) const { return std::min(n, firstCell(pixel) + block); }
};

// Square cells sized so the longer side fills at most kMaxSide pixels, but
// the shorter side stretched to at least kMinSide pixels, so that a very
// oblong matrix still gets a readable area and colour bar.
AxisSampling sampleAxis(int n, int longest) {
  constexpr int kMaxSide = 512, kMinSide = 200;
  double pixelsPerCell = double(kMaxSide) / longest;
  if (n * pixelsPerCell < kMinSide) pixelsPerCell = std::ceil(double(kMinSide) / n);
  AxisSampling a;
  if (pixelsPerCell >= 1)
    a.cell = static_cast<int>(pixelsPerCell);
  else
    a.block = static_cast<int>(std::ceil(1 / pixelsPerCell));
  return a;
}

struct HeatGeometry {
  Metrics m{2};
  AxisSampling rowSampling, colSampling;
  Rect area, bar;
  Range values;
  Ticks rowTicks, colTicks, barTicks;
  std::vector<std::string> rowLabels, colLabels, barLabels, titleLines;
  int width = 0, height = 0;
  int originX = 0; // left edge of the content (y label), > 0 when centred under a wide title
};

// Ticks at whole indices 0..n-1.
Ticks indexTicks(int n, int maxTicks) {
  if (n <= 1) return {1, {0}};
  Ticks t = niceTicks(0, n - 1, maxTicks);
  if (t.step < 1) {
    t = {1, {}};
    for (int i = 0; i < n; ++i) t.values.push_back(i);
  }
  return t;
}

HeatGeometry computeHeatGeometry(const Heatmap &map) {
  if (map.rows <= 0 || map.cols <= 0)
    throw std::invalid_argument("a heat map needs at least one row and one column.");
  if (map.values.size() != std::size_t(map.rows) * std::size_t(map.cols))
    throw std::invalid_argument("a " + std::to_string(map.rows) + " x " + std::to_string(map.cols) +
                                " heat map needs " +
                                std::to_string(std::size_t(map.rows) * std::size_t(map.cols)) +
                                " values, not " + std::to_string(map.values.size()) + ".");
  if (std::isinf(map.vMin) || std::isinf(map.vMax) ||
      (!std::isnan(map.vMin) && !std::isnan(map.vMax) && !(map.vMin < map.vMax)))
    throw std::invalid_argument("the colour limits of a heat map must be finite with min < max.");

  HeatGeometry g;
  const Metrics &m = g.m;
  const int s = m.scale;
  const TextStyle style{s};
  const int longest = std::max(map.rows, map.cols);
  g.rowSampling = sampleAxis(map.rows, longest);
  g.colSampling = sampleAxis(map.cols, longest);

  Extent e;
  for (double v : map.values) e.add(v);
  g.values = resolveRange(e, 0.0, map.vMin, map.vMax);

  const int capH = capHeight(s);
  g.area.width = g.colSampling.pixels(map.cols);
  g.area.height = g.rowSampling.pixels(map.rows);
  g.rowTicks = indexTicks(map.rows, std::max(2, g.area.height / (3 * capH)));
  g.rowLabels = tickLabels(g.rowTicks);
  const int colLabelWidth = textWidth(std::to_string(map.cols - 1), style);
  g.colTicks =
      indexTicks(map.cols, std::max(2, g.area.width / (colLabelWidth + 2 * font::kAdvance * s)));
  g.colLabels = tickLabels(g.colTicks);
  g.barTicks = niceTicks(g.values.lo, g.values.hi, std::max(2, g.area.height / (3 * capH)));
  g.barLabels = tickLabels(g.barTicks);

  // Horizontally: y label, row labels, the cells, the colour bar and its
  // labels; the image is widened for a long title, up to a point, beyond
  // which the title wraps.
  const int xLabelBlock = map.xLabel.empty() ? 0 : textHeight(s) + 3 * s;
  const int yLabelBlock = map.yLabel.empty() ? 0 : textHeight(s) + 4 * s;
  g.area.left = m.pad + yLabelBlock + widestLabel(g.rowLabels, style) + m.gap + m.tick + 1;
  const int barGap = 8 * s, barWidth = 8 * s;
  const int barLeft = g.area.right() + barGap;
  const int right =
      barLeft + barWidth + 1 + m.tick + m.gap + widestLabel(g.barLabels, style) + m.pad;
  const int xLabelRight = g.area.left + textWidth(map.xLabel, style) + m.pad;
  const int titleWidth = textWidth(map.title, TextStyle{s, kText, true}) + 2 * m.pad;
  g.width = std::max({right, xLabelRight, std::min(titleWidth, 900), 240});
  // Centre the content when the image was widened for the title.
  g.originX = (g.width - std::max(right, xLabelRight)) / 2;
  g.area.left += g.originX;
  g.titleLines = wrapText(map.title, g.width - 2 * m.pad, TextStyle{s, kText, true}, 3);

  g.area.top = m.pad + titleBlockHeight(g.titleLines, s) + capH / 2 + 1;
  g.bar = {g.area.right() + barGap, g.area.top, barWidth, g.area.height};
  g.height = g.area.bottom() + 1 + m.tick + m.gap + capH + xLabelBlock + m.pad;
  const int yLabelHeight = textWidth(map.yLabel, style) + 2 * m.pad;
  g.height = std::max({g.height, yLabelHeight, 180});
  return g;
}

// The value shown at area pixel (px, py): its cell, or the mean of the
// finite cells of its block when the matrix is larger than the area; NaN
// when there is none.
double cellValue(const Heatmap &map, const HeatGeometry &g, int px, int py) {
  const AxisSampling &rs = g.rowSampling, &cs = g.colSampling;
  double sum = 0;
  int count = 0;
  for (int r = rs.firstCell(py); r < rs.endCell(py, map.rows); ++r)
    for (int c = cs.firstCell(px); c < cs.endCell(px, map.cols); ++c) {
      const double v = map.values[std::size_t(r) * map.cols + c];
      if (std::isfinite(v)) {
        sum += v;
        ++count;
      }
    }
  return count > 0 ? sum / count : std::nan("");
}

void drawHeatCells(Canvas &canvas, const Heatmap &map, const HeatGeometry &g) {
  for (int py = 0; py < g.area.height; ++py)
    for (int px = 0; px < g.area.width; ++px) {
      const double v = cellValue(map, g, px, py);
      const Rgb c =
          std::isfinite(v) ? scaleColor((v - g.values.lo) / g.values.span()) : kMissingCell;
      canvas.blend(g.area.left + px, g.area.top + py, c, 1.0);
    }
  for (int py = 0; py < g.bar.height; ++py) {
    const double t = 1.0 - (py + 0.5) / g.bar.height;
    canvas.fillRect({g.bar.left, g.bar.top + py, g.bar.width, 1}, scaleColor(t));
  }
  canvas.outline(g.area, kFrame);
  canvas.outline(g.bar, kFrame);
}

void drawHeatAxes(Canvas &canvas, const Heatmap &map, const HeatGeometry &g) {
  const Metrics &m = g.m;
  const int s = m.scale, capH = capHeight(s);
  const TextStyle style{s};
  const Rect &a = g.area;
  for (std::size_t i = 0; i < g.colTicks.values.size(); ++i) {
    const int c = a.left + static_cast<int>((g.colTicks.values[i] + 0.5) * a.width / map.cols);
    canvas.fillRect({c, a.bottom() + 1, 1, m.tick}, kFrame);
    const int w = textWidth(g.colLabels[i], style);
    drawText(canvas, c - (w - 1) / 2, a.bottom() + 1 + m.tick + m.gap, g.colLabels[i], style);
  }
  for (std::size_t i = 0; i < g.rowTicks.values.size(); ++i) {
    const int r = a.top + static_cast<int>((g.rowTicks.values[i] + 0.5) * a.height / map.rows);
    canvas.fillRect({a.left - 1 - m.tick, r, m.tick, 1}, kFrame);
    const int w = textWidth(g.rowLabels[i], style);
    drawText(canvas, a.left - 1 - m.tick - m.gap - w, r - (capH - 1) / 2, g.rowLabels[i], style);
  }
  const Rect &b = g.bar;
  for (std::size_t i = 0; i < g.barTicks.values.size(); ++i) {
    const double t = (g.values.hi - g.barTicks.values[i]) / g.values.span();
    const int r =
        std::clamp(b.top + static_cast<int>(t * (b.height - 1) + 0.5), b.top, b.bottom() - 1);
    canvas.fillRect({b.right() + 1, r, m.tick, 1}, kFrame);
    drawText(canvas, b.right() + 1 + m.tick + m.gap, r - (capH - 1) / 2, g.barLabels[i], style);
  }
  drawTitleLines(canvas, g.titleLines, a.left + a.width / 2, m);
  if (!map.xLabel.empty()) {
    const int w = textWidth(map.xLabel, style);
    drawText(canvas, centredLeft(a.left + a.width / 2, w, canvas.width(), m.pad),
             a.bottom() + 1 + m.tick + m.gap + capH + 3 * s, map.xLabel, style);
  }
  if (!map.yLabel.empty()) {
    const int w = textWidth(map.yLabel, style);
    const int bottom = std::clamp(a.top + a.height / 2 + w / 2, m.pad + w, canvas.height() - m.pad);
    drawTextUp(canvas, g.originX + m.pad, bottom, map.yLabel, style);
  }
}

// ---------------------------------------------------------------------------
// PNG and files

void appendU32(std::vector<std::uint8_t> &out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

void appendChunk(std::vector<std::uint8_t> &out, const char (&type)[5],
                 const std::vector<std::uint8_t> &data) {
  appendU32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  // The CRC covers the chunk type and data, not the length.
  const uLong crc =
      crc32(crc32(0L, Z_NULL, 0), out.data() + start, static_cast<uInt>(4 + data.size()));
  appendU32(out, static_cast<std::uint32_t>(crc));
}

void writeFileAtomically(const std::string &path, const std::vector<std::uint8_t> &bytes) {
  const std::string tmp = path + ".tmp";
  const auto fail = [&](const std::string &why) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write the PNG file '" + path + "': " + why + ".");
  };
  std::FILE *f = std::fopen(tmp.c_str(), "wb");
  if (!f) fail(std::string("cannot create '") + tmp + "' (" + std::strerror(errno) + ")");
  const std::size_t written = std::fwrite(bytes.data(), 1, bytes.size(), f);
  const int writeErrno = errno;
  if (std::fclose(f) != 0 || written != bytes.size())
    fail(std::string("writing '") + tmp + "' failed (" + std::strerror(writeErrno) + ")");
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    fail(std::string("cannot rename '") + tmp + "' to it (" + std::strerror(errno) + ")");
}

// ---------------------------------------------------------------------------
// CSV

std::string trim(const std::string &s) {
  const std::size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string> splitFields(const std::string &line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

} // namespace

// ---------------------------------------------------------------------------
// Public functions

Rgb seriesColor(int index) {
  static constexpr std::array<Rgb, 10> kPalette = {{{28, 92, 178},
                                                    {226, 112, 18},
                                                    {36, 148, 72},
                                                    {200, 36, 48},
                                                    {122, 78, 172},
                                                    {138, 92, 56},
                                                    {212, 84, 168},
                                                    {96, 96, 96},
                                                    {164, 160, 28},
                                                    {20, 160, 184}}};
  const int n = static_cast<int>(kPalette.size());
  return kPalette[((index % n) + n) % n];
}

Ticks niceTicks(double lo, double hi, int maxTicks) {
  Ticks t;
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi)) return t;
  maxTicks = std::max(maxTicks, 2);
  const auto count = [&](double step) {
    const double eps = 1e-9 * step;
    return std::floor((hi + eps) / step) - std::ceil((lo - eps) / step) + 1;
  };
  // Walk up the 1-2-5 sequence from below span / (maxTicks + 1), which has
  // too many ticks, to the first step with few enough; the walk ends by
  // span / (maxTicks - 1), which always qualifies.
  int exponent = static_cast<int>(std::floor(std::log10((hi - lo) / (maxTicks + 1))));
  int mantissa = 1;
  for (t.step = std::pow(10.0, exponent); count(t.step) > maxTicks;) {
    mantissa = mantissa == 1 ? 2 : mantissa == 2 ? 5 : 1;
    if (mantissa == 1) ++exponent;
    t.step = mantissa * std::pow(10.0, exponent); // not a running product: no drift
  }
  const double eps = 1e-9 * t.step;
  const double first = std::ceil((lo - eps) / t.step), last = std::floor((hi + eps) / t.step);
  // The cap only matters when |lo| / step exceeds double precision.
  for (double k = first; k <= last && static_cast<int>(t.values.size()) < maxTicks; ++k) {
    const double v = k * t.step;
    t.values.push_back(std::fabs(v) < eps ? 0.0 : v);
  }
  return t;
}

std::vector<std::string> tickLabels(const Ticks &ticks) {
  std::vector<std::string> labels;
  if (ticks.values.empty()) return labels;
  const bool scientific = useScientific(ticks);
  const int stepExponent = decimalExponent(ticks.step);
  // Scientific labels share one mantissa precision, enough for the largest
  // tick to show the step ("5.0e-6" next to "1.5e-5", not "5e-6").
  double largest = 0;
  for (double v : ticks.values) largest = std::max(largest, std::fabs(v));
  const int mantissaDigits = std::max(0, decimalExponent(largest) - stepExponent);
  for (double v : ticks.values) {
    if (v == 0 && scientific) {
      labels.push_back("0");
    } else if (scientific) {
      labels.push_back(tidyExponent(formatNumber("%.*e", mantissaDigits, v)));
    } else {
      labels.push_back(formatNumber("%.*f", std::max(0, -stepExponent), v));
    }
  }
  return labels;
}

PlotLayout layoutFigure(const Figure &figure) { return computeGeometry(figure).layout; }

std::vector<std::uint8_t> renderRgb(const Figure &figure, int *width, int *height) {
  const Geometry g = computeGeometry(figure);
  const Rect area = g.area();
  Canvas canvas(figure.width, figure.height, kWhite);
  drawGrid(canvas, g);
  std::vector<float> ink(std::size_t(area.width) * area.height, 0.0f);
  // Bands first, so every line stays visible on top of every band.
  for (std::size_t i = 0; i < figure.series.size(); ++i) {
    if (figure.series[i].yLow.empty()) continue;
    Mask band(area);
    rasterBand(band, figure.series[i], g);
    band.compositeOnto(canvas, seriesColor(static_cast<int>(i)), kBandAlpha);
    band.accumulateInto(ink, 0.3f);
  }
  for (std::size_t i = 0; i < figure.series.size(); ++i) {
    Mask line(area);
    rasterLine(line, figure.series[i], g);
    line.compositeOnto(canvas, seriesColor(static_cast<int>(i)), 1.0);
    line.accumulateInto(ink, 1.0f);
  }
  drawAxes(canvas, g);
  drawLegend(canvas, figure, g, ink);
  drawTitles(canvas, figure, g);
  if (width) *width = canvas.width();
  if (height) *height = canvas.height();
  return canvas.take();
}

void writePng(const std::string &path, const Figure &figure) {
  int w = 0, h = 0;
  const std::vector<std::uint8_t> rgb = renderRgb(figure, &w, &h);
  writeRgbPng(path, rgb, w, h);
}

std::vector<std::uint8_t> renderHeatmapRgb(const Heatmap &map, int *width, int *height) {
  const HeatGeometry g = computeHeatGeometry(map);
  Canvas canvas(g.width, g.height, kWhite);
  drawHeatCells(canvas, map, g);
  drawHeatAxes(canvas, map, g);
  if (width) *width = canvas.width();
  if (height) *height = canvas.height();
  return canvas.take();
}

void writeHeatmapPng(const std::string &path, const Heatmap &map) {
  int w = 0, h = 0;
  const std::vector<std::uint8_t> rgb = renderHeatmapRgb(map, &w, &h);
  writeRgbPng(path, rgb, w, h);
}

void writeHeatmapPng(const std::string &path, const std::vector<double> &rowMajor, int rows,
                     int cols, const std::string &title) {
  Heatmap map;
  map.values = rowMajor;
  map.rows = rows;
  map.cols = cols;
  map.title = title;
  writeHeatmapPng(path, map);
}

std::vector<std::uint8_t> encodePng(const std::vector<std::uint8_t> &rgb, int width, int height) {
  if (width <= 0 || height <= 0 || rgb.size() != std::size_t(width) * height * 3)
    throw std::invalid_argument("encodePng needs width * height * 3 bytes of RGB data.");
  // Scanlines, each led by its filter type; 0 (none) compresses plots well
  // since they are mostly long runs of one colour.
  const std::size_t rowBytes = std::size_t(width) * 3;
  std::vector<std::uint8_t> raw;
  raw.reserve((rowBytes + 1) * height);
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);
    raw.insert(raw.end(), rgb.begin() + y * rowBytes, rgb.begin() + (y + 1) * rowBytes);
  }
  uLongf packedSize = compressBound(static_cast<uLong>(raw.size()));
  std::vector<std::uint8_t> packed(packedSize);
  if (compress2(packed.data(), &packedSize, raw.data(), static_cast<uLong>(raw.size()),
                Z_BEST_COMPRESSION) != Z_OK)
    throw std::runtime_error("zlib could not compress the PNG image data.");
  packed.resize(packedSize);

  std::vector<std::uint8_t> header;
  appendU32(header, static_cast<std::uint32_t>(width));
  appendU32(header, static_cast<std::uint32_t>(height));
  header.insert(header.end(), {8, 2, 0, 0, 0}); // 8-bit, RGB, deflate, no filter set, no interlace

  std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  appendChunk(png, "IHDR", header);
  appendChunk(png, "IDAT", packed);
  appendChunk(png, "IEND", {});
  return png;
}

void writeRgbPng(const std::string &path, const std::vector<std::uint8_t> &rgb, int width,
                 int height) {
  writeFileAtomically(path, encodePng(rgb, width, height));
}

int CsvTable::find(const std::string &name) const {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return static_cast<int>(i);
  return -1;
}

const std::vector<double> &CsvTable::column(const std::string &name) const {
  const int i = find(name);
  if (i < 0) {
    std::string names;
    for (const std::string &h : header) names += (names.empty() ? "" : ", ") + h;
    throw std::runtime_error("the CSV file '" + path + "' has no column '" + name +
                             "' (it has: " + names + ").");
  }
  return columns[i];
}

CsvTable readCsv(const std::string &path) {
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot open the CSV file '" + path + "' (" + std::strerror(errno) +
                             ").");
  CsvTable table;
  table.path = path;
  std::string line;
  bool haveHeader = false;
  for (int lineNo = 1; std::getline(in, line); ++lineNo) {
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    std::vector<std::string> fields = splitFields(text);
    if (!haveHeader) {
      table.header = std::move(fields);
      table.columns.assign(table.header.size(), {});
      haveHeader = true;
      continue;
    }
    const std::string where = path + ":" + std::to_string(lineNo) + ": ";
    if (fields.size() != table.header.size())
      throw std::runtime_error(where + "expected " + std::to_string(table.header.size()) +
                               " comma-separated fields but found " +
                               std::to_string(fields.size()) + ".");
    for (std::size_t c = 0; c < fields.size(); ++c) {
      double v = std::nan("");
      if (!fields[c].empty()) {
        char *end = nullptr;
        v = std::strtod(fields[c].c_str(), &end);
        if (end != fields[c].c_str() + fields[c].size())
          throw std::runtime_error(where + "'" + fields[c] + "' in column '" + table.header[c] +
                                   "' is not a number.");
      }
      table.columns[c].push_back(v);
    }
  }
  if (in.bad()) throw std::runtime_error("reading the CSV file '" + path + "' failed.");
  if (!haveHeader) throw std::runtime_error("the CSV file '" + path + "' has no header line.");
  return table;
}

} // namespace rcfd::plot
