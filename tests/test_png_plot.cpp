// PNG line plots and heat maps: file structure (signature, chunk CRCs,
// decompressed scanlines), tick choice, pixel placement, clipping, robustness
// to degenerate data, and the CSV reader.
#include "check.hpp"
#include "plot/bitmap_font.hpp"
#include "plot/png_plot.hpp"

#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace rcfd::plot;

namespace {

const double kNaN = std::nan("");

std::uint32_t readU32(const std::vector<std::uint8_t> &b, std::size_t at) {
  return (std::uint32_t(b[at]) << 24) | (std::uint32_t(b[at + 1]) << 16) |
         (std::uint32_t(b[at + 2]) << 8) | std::uint32_t(b[at + 3]);
}

std::vector<std::uint8_t> readFile(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool exists(const std::string &path) { return static_cast<bool>(std::ifstream(path)); }

int paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
}

// A minimal PNG reader for 8-bit RGB, written independently of the encoder:
// checks the signature, every chunk's CRC and the IHDR fields, inflates the
// IDAT data and undoes all five scanline filters.  Empty result on failure.
std::vector<std::uint8_t> decodePng(const std::vector<std::uint8_t> &png, int *w, int *h) {
  const std::uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  RCFD_CHECK(png.size() > 8 && std::equal(signature, signature + 8, png.begin()));
  std::vector<std::uint8_t> idat;
  std::vector<std::string> order;
  std::size_t at = 8;
  *w = *h = 0;
  while (at + 12 <= png.size()) {
    const std::uint32_t length = readU32(png, at);
    const std::string type(png.begin() + at + 4, png.begin() + at + 8);
    RCFD_CHECK(at + 12 + length <= png.size());
    if (at + 12 + length > png.size()) return {};
    const uLong crc = crc32(crc32(0L, Z_NULL, 0), &png[at + 4], 4 + length);
    RCFD_CHECK(crc == readU32(png, at + 8 + length));
    order.push_back(type);
    if (type == "IHDR") {
      RCFD_CHECK(length == 13);
      *w = static_cast<int>(readU32(png, at + 8));
      *h = static_cast<int>(readU32(png, at + 12));
      RCFD_CHECK(png[at + 16] == 8); // bit depth
      RCFD_CHECK(png[at + 17] == 2); // colour type RGB
      RCFD_CHECK(png[at + 18] == 0 && png[at + 19] == 0 && png[at + 20] == 0);
    } else if (type == "IDAT") {
      idat.insert(idat.end(), png.begin() + at + 8, png.begin() + at + 8 + length);
    }
    at += 12 + length;
  }
  RCFD_CHECK(at == png.size());
  RCFD_CHECK(!order.empty() && order.front() == "IHDR" && order.back() == "IEND");
  if (*w <= 0 || *h <= 0) return {};

  const std::size_t stride = std::size_t(*w) * 3;
  std::vector<std::uint8_t> raw((stride + 1) * *h);
  uLongf rawSize = raw.size();
  RCFD_CHECK(uncompress(raw.data(), &rawSize, idat.data(), idat.size()) == Z_OK);
  RCFD_CHECK(rawSize == raw.size());
  std::vector<std::uint8_t> rgb(stride * *h);
  for (int y = 0; y < *h; ++y) {
    const int filter = raw[y * (stride + 1)];
    RCFD_CHECK(filter >= 0 && filter <= 4);
    for (std::size_t i = 0; i < stride; ++i) {
      const int x = raw[y * (stride + 1) + 1 + i];
      const int a = i >= 3 ? rgb[y * stride + i - 3] : 0;
      const int b = y > 0 ? rgb[(y - 1) * stride + i] : 0;
      const int c = i >= 3 && y > 0 ? rgb[(y - 1) * stride + i - 3] : 0;
      const int predictor[5] = {0, a, b, (a + b) / 2, paeth(a, b, c)};
      rgb[y * stride + i] = static_cast<std::uint8_t>(x + predictor[filter > 4 ? 0 : filter]);
    }
  }
  return rgb;
}

Rgb pixelAt(const std::vector<std::uint8_t> &rgb, int width, int x, int y) {
  const std::size_t i = (std::size_t(y) * width + x) * 3;
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

template <typename F> bool throwsContaining(F &&f, const std::string &text) {
  try {
    f();
  } catch (const std::exception &e) {
    if (std::string(e.what()).find(text) != std::string::npos) return true;
    std::fprintf(stderr, "message was: %s\n", e.what());
    return false;
  }
  return false;
}

void testTicks() {
  const Ticks unit = niceTicks(0, 1, 6);
  RCFD_CHECK_CLOSE(unit.step, 0.2, 1e-15);
  RCFD_CHECK(unit.values.size() == 6);
  RCFD_CHECK(unit.values.front() == 0.0);
  RCFD_CHECK_CLOSE(unit.values.back(), 1.0, 1e-15);

  const Ticks time = niceTicks(0, 37.3, 8);
  RCFD_CHECK_CLOSE(time.step, 5.0, 1e-15);
  RCFD_CHECK(time.values.size() == 8);
  RCFD_CHECK_CLOSE(time.values.back(), 35.0, 1e-15);

  const Ticks signedTicks = niceTicks(-0.013, 0.021, 5);
  RCFD_CHECK_CLOSE(signedTicks.step, 0.01, 1e-15);
  RCFD_CHECK(signedTicks.values.size() == 4);
  RCFD_CHECK(signedTicks.values[1] == 0.0); // exactly zero, so no "-0" label

  const std::vector<std::string> labels = tickLabels(signedTicks);
  RCFD_CHECK(labels.size() == 4 && labels[0] == "-0.01" && labels[1] == "0.00" &&
             labels[2] == "0.01" && labels[3] == "0.02");
  const std::vector<std::string> unitLabels = tickLabels(unit);
  RCFD_CHECK(unitLabels[0] == "0.0" && unitLabels[1] == "0.2" && unitLabels[5] == "1.0");
  RCFD_CHECK(tickLabels(niceTicks(0, 40, 5))[1] == "10");
  const std::vector<std::string> tiny = tickLabels(niceTicks(0, 4e-6, 5));
  RCFD_CHECK(tiny.size() == 5 && tiny[0] == "0" && tiny[1] == "1e-6");
  const std::vector<std::string> huge = tickLabels(niceTicks(0, 3e7, 4));
  RCFD_CHECK(huge.size() == 4 && huge[1] == "1e7");

  // Properties over many ranges: 1-2-5 steps, ticks inside [lo, hi] and
  // covering it (no room for another tick at either end), at most maxTicks,
  // and at least two once maxTicks >= 6.
  std::srand(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, std::rand() % 13 - 6);
    const double lo = (std::rand() / double(RAND_MAX) - 0.5) * 10 * scale;
    const double hi = lo + (0.01 + std::rand() / double(RAND_MAX)) * scale;
    const int maxTicks = 2 + std::rand() % 12;
    const Ticks t = niceTicks(lo, hi, maxTicks);
    const double mantissa = t.step / std::pow(10.0, std::floor(std::log10(t.step) + 1e-9));
    RCFD_CHECK(std::fabs(mantissa - 1) < 1e-9 || std::fabs(mantissa - 2) < 1e-9 ||
               std::fabs(mantissa - 5) < 1e-9);
    RCFD_CHECK(static_cast<int>(t.values.size()) <= maxTicks);
    if (maxTicks >= 6) RCFD_CHECK(t.values.size() >= 2);
    if (t.values.empty()) continue;
    const double eps = 1e-9 * t.step;
    RCFD_CHECK(t.values.front() >= lo - eps && t.values.back() <= hi + eps);
    RCFD_CHECK(t.values.front() - t.step < lo + eps && t.values.back() + t.step > hi - eps);
    for (std::size_t i = 1; i < t.values.size(); ++i)
      RCFD_CHECK_CLOSE(t.values[i] - t.values[i - 1], t.step, 1e-6);
  }
  RCFD_CHECK(niceTicks(1, 1, 5).values.empty());
  RCFD_CHECK(niceTicks(0, kNaN, 5).values.empty());
}

void testFont() {
  std::set<std::vector<int>> distinct;
  for (char32_t c = 32; c <= 126; ++c) {
    RCFD_CHECK(font::hasGlyph(c));
    const font::Glyph &g = font::glyph(c);
    int ink = 0;
    for (auto row : g) {
      RCFD_CHECK(row < 32);
      ink += row != 0;
    }
    RCFD_CHECK((c == ' ') == (ink == 0));
    distinct.insert(std::vector<int>(g.begin(), g.end()));
  }
  // No two printable characters look alike, except O and 0 (a plain zero
  // reads better in tick labels than a slashed one).
  RCFD_CHECK(distinct.size() == 94);
  RCFD_CHECK(font::glyph('O') == font::glyph('0'));
  RCFD_CHECK(!font::hasGlyph(U'\u00E9'));
  RCFD_CHECK(font::decodeUtf8("d = 2 \xC2\xB5m") == U"d = 2 \u00B5m");
  RCFD_CHECK(font::decodeUtf8("a\xFF").size() == 2);
  const std::string mixed = "a\xC2\xB5\xCE\x94\xE2\x82\xAC\xF0\x9F\x98\x80z";
  RCFD_CHECK(font::decodeUtf8(mixed).size() == 6);
  RCFD_CHECK(font::encodeUtf8(font::decodeUtf8(mixed)) == mixed);
}

Figure horizontalLine() {
  Figure fig;
  fig.xMin = 0;
  fig.xMax = 1;
  fig.yMin = 0;
  fig.yMax = 1;
  Series s;
  s.x = {0, 1};
  s.y = {0.5, 0.5};
  fig.series.push_back(s);
  return fig;
}

void testPngStructure() {
  Figure fig = horizontalLine();
  fig.title = "Centre of gravity";
  fig.xLabel = "time t [s]";
  fig.yLabel = "z [m]";
  fig.series[0].label = "bed";
  int w = 0, h = 0;
  const std::vector<std::uint8_t> rgb = renderRgb(fig, &w, &h);
  RCFD_CHECK(w == 900 && h == 560);
  RCFD_CHECK(rgb.size() == std::size_t(w) * h * 3);
  const std::vector<std::uint8_t> png = encodePng(rgb, w, h);
  int dw = 0, dh = 0;
  const std::vector<std::uint8_t> decoded = decodePng(png, &dw, &dh);
  RCFD_CHECK(dw == w && dh == h);
  RCFD_CHECK(decoded == rgb);
  RCFD_CHECK(png.size() < rgb.size() / 10); // a plot is mostly flat colour
  RCFD_CHECK(throwsContaining([] { encodePng({1, 2, 3}, 2, 1); }, "RGB"));
}

void testKnownPixels() {
  const Figure fig = horizontalLine();
  const PlotLayout l = layoutFigure(fig);
  RCFD_CHECK(l.xMin == 0 && l.xMax == 1 && l.yMin == 0 && l.yMax == 1);
  RCFD_CHECK(l.left > 0 && l.top > 0 && l.left + l.width < fig.width &&
             l.top + l.height < fig.height);
  int w = 0, h = 0;
  const std::vector<std::uint8_t> rgb = renderRgb(fig, &w, &h);
  const int row = static_cast<int>(std::floor(l.top + 0.5 + 0.5 * (l.height - 1)));
  const Rgb blue = seriesColor(0);
  for (int x : {l.left + 3, l.left + l.width / 3, l.left + l.width - 4})
    RCFD_CHECK(pixelAt(rgb, w, x, row) == blue);
  RCFD_CHECK(pixelAt(rgb, w, l.left + l.width / 3, row - 12) != blue);
  RCFD_CHECK(pixelAt(rgb, w, l.left + l.width / 3, row + 12) != blue);
  RCFD_CHECK(pixelAt(rgb, w, 1, 1) == (Rgb{255, 255, 255}));

  // The colours of different series differ.
  std::set<std::vector<int>> colours;
  for (int i = 0; i < 10; ++i)
    colours.insert({seriesColor(i).r, seriesColor(i).g, seriesColor(i).b});
  RCFD_CHECK(colours.size() == 10);
}

void testClippingAndGaps() {
  // A steep line leaving the fixed range must not paint outside the plot area.
  Figure fig = horizontalLine();
  fig.series[0].x = {0, 0.5, 1};
  fig.series[0].y = {-3, 4, -3};
  const PlotLayout l = layoutFigure(fig);
  int w = 0, h = 0;
  std::vector<std::uint8_t> rgb = renderRgb(fig, &w, &h);
  const Rgb blue = seriesColor(0);
  int inside = 0, outside = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool in = x >= l.left && x < l.left + l.width && y >= l.top && y < l.top + l.height;
      const Rgb p = pixelAt(rgb, w, x, y);
      if (p == blue) (in ? inside : outside)++;
    }
  RCFD_CHECK(inside > 100);
  RCFD_CHECK(outside == 0);

  // A NaN breaks the line: nothing between the neighbours of the gap.
  fig = horizontalLine();
  fig.series[0].x = {0, 0.25, 0.5, 0.75, 1};
  fig.series[0].y = {0.5, 0.5, kNaN, 0.5, 0.5};
  rgb = renderRgb(fig, &w, &h);
  const int row = static_cast<int>(std::floor(l.top + 0.5 + 0.5 * (l.height - 1)));
  RCFD_CHECK(pixelAt(rgb, w, l.left + l.width / 8, row) == blue);
  RCFD_CHECK(pixelAt(rgb, w, l.left + l.width * 3 / 8, row) != blue);
  RCFD_CHECK(pixelAt(rgb, w, l.left + l.width * 5 / 8, row) != blue);
  RCFD_CHECK(pixelAt(rgb, w, l.left + l.width * 7 / 8, row) == blue);
}

void testBand() {
  Figure fig = horizontalLine();
  fig.series[0].yLow = {0.2, 0.2};
  fig.series[0].yHigh = {0.8, 0.8};
  const PlotLayout l = layoutFigure(fig);
  int w = 0, h = 0;
  const std::vector<std::uint8_t> rgb = renderRgb(fig, &w, &h);
  const Rgb blue = seriesColor(0);
  // Between line and band edge: a tint of the series colour, lighter than it.
  const int x = l.left + l.width / 3;
  const int y = static_cast<int>(l.top + 0.5 + 0.35 * (l.height - 1));
  const Rgb p = pixelAt(rgb, w, x, y);
  RCFD_CHECK(p != blue && p != (Rgb{255, 255, 255}));
  RCFD_CHECK(p.b > p.r && p.r > blue.r);
  // Outside the band: background.
  const Rgb out = pixelAt(rgb, w, x, static_cast<int>(l.top + 0.5 + 0.07 * (l.height - 1)));
  RCFD_CHECK(out == (Rgb{255, 255, 255}));
}

void testDegenerateInput() {
  int w = 0, h = 0;
  Figure empty;
  RCFD_CHECK(renderRgb(empty, &w, &h).size() == std::size_t(900) * 560 * 3);

  Figure fig;
  fig.title = "degenerate";
  Series none;
  none.label = "empty";
  Series allNaN;
  allNaN.label = "all NaN";
  allNaN.x = {kNaN, 1, kNaN};
  allNaN.y = {1, kNaN, kNaN};
  Series single;
  single.label = "single point";
  single.x = {3};
  single.y = {7};
  fig.series = {none, allNaN, single};
  const PlotLayout l = layoutFigure(fig);
  RCFD_CHECK(l.xMin < 3 && l.xMax > 3 && l.yMin < 7 && l.yMax > 7);
  const std::vector<std::uint8_t> rgb = renderRgb(fig, &w, &h);
  // The single point is drawn as a dot in the colour of series 2.
  const int cx = static_cast<int>(l.left + 0.5 + (3 - l.xMin) / (l.xMax - l.xMin) * (l.width - 1));
  const int cy = static_cast<int>(l.top + 0.5 + (l.yMax - 7) / (l.yMax - l.yMin) * (l.height - 1));
  RCFD_CHECK(pixelAt(rgb, w, cx, cy) == seriesColor(2));

  Series constant;
  constant.x = {0, 1, 2};
  constant.y = {0, 0, 0};
  fig.series = {constant};
  RCFD_CHECK(layoutFigure(fig).yMax > layoutFigure(fig).yMin);

  Series huge;
  huge.x = {0, 1e-300, 1e300};
  huge.y = {-1e300, 5, 1e300};
  fig.series = {huge};
  RCFD_CHECK(renderRgb(fig, &w, &h).size() == std::size_t(w) * h * 3);

  // A title too long for one line wraps, pushing the plot down.
  fig.series = {horizontalLine().series[0]};
  fig.title = "short";
  const int oneLine = layoutFigure(fig).top;
  fig.title.clear();
  for (int i = 0; i < 40; ++i) fig.title += "word" + std::to_string(i) + " ";
  const int wrapped = layoutFigure(fig).top;
  RCFD_CHECK(wrapped > oneLine);
  RCFD_CHECK(renderRgb(fig, &w, &h).size() == std::size_t(900) * 560 * 3);
  fig.title = std::string(500, 'x'); // one unbreakable word, cut after three lines
  RCFD_CHECK(layoutFigure(fig).top == wrapped);
  fig.title = std::string(50000, 'x');
  RCFD_CHECK(layoutFigure(fig).top == wrapped);

  fig.width = 300;
  fig.height = 200;
  RCFD_CHECK(renderRgb(fig, &w, &h).size() == std::size_t(300) * 200 * 3);

  Series bad;
  bad.label = "bad";
  bad.x = {1, 2};
  bad.y = {1};
  fig.series = {bad};
  RCFD_CHECK(throwsContaining([&] { renderRgb(fig, &w, &h); }, "series 'bad' has 2 x values"));
  bad.y = {1, 2};
  bad.yLow = {0, 0};
  fig.series = {bad};
  RCFD_CHECK(throwsContaining([&] { renderRgb(fig, &w, &h); }, "yLow and yHigh"));
  fig.series.clear();
  fig.yMin = 2;
  fig.yMax = 1;
  RCFD_CHECK(throwsContaining([&] { layoutFigure(fig); }, "y limits"));
  fig.yMin = kAuto;
  fig.width = 10;
  RCFD_CHECK(throwsContaining([&] { layoutFigure(fig); }, "pixels"));
}

void testFiles() {
  const std::filesystem::path tmp = std::filesystem::temp_directory_path() / "rcfd_test_png_plot";
  std::filesystem::remove_all(tmp);
  std::filesystem::create_directories(tmp);
  const std::string dir = tmp.string();
  const std::string path = dir + "/line.png";
  Figure fig = horizontalLine();
  writePng(path, fig);
  RCFD_CHECK(exists(path) && !exists(path + ".tmp"));
  int w = 0, h = 0;
  const std::vector<std::uint8_t> decoded = decodePng(readFile(path), &w, &h);
  RCFD_CHECK(w == 900 && h == 560);
  RCFD_CHECK(decoded == renderRgb(fig, nullptr, nullptr));

  const std::string missing = dir + "/no/such/dir/line.png";
  RCFD_CHECK(throwsContaining([&] { writePng(missing, fig); }, "'" + missing + "'"));

  // Heat map: a 40 x 40 "recurrence matrix" |i - j| / 39 with a NaN cell.
  const int k = 40;
  std::vector<double> m(k * k);
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) m[i * k + j] = std::abs(i - j) / double(k - 1);
  m[5] = kNaN;
  const std::string heat = dir + "/heat.png";
  writeHeatmapPng(heat, m, k, k, "recurrence matrix");
  const std::vector<std::uint8_t> heatRgb = decodePng(readFile(heat), &w, &h);
  RCFD_CHECK(w > 40 && h > 40 && heatRgb.size() == std::size_t(w) * h * 3);
  Heatmap big;
  big.rows = big.cols = 1100; // larger than the drawing area: block means
  big.values.assign(std::size_t(big.rows) * big.cols, 0.25);
  big.vMin = 0;
  big.vMax = 1;
  RCFD_CHECK(renderHeatmapRgb(big, &w, &h).size() == std::size_t(w) * h * 3);
  Heatmap single;
  single.rows = single.cols = 1;
  single.values = {kNaN};
  RCFD_CHECK(renderHeatmapRgb(single, &w, &h).size() == std::size_t(w) * h * 3);
  RCFD_CHECK(throwsContaining(
      [] {
        writeHeatmapPng("/tmp/x.png", {1, 2, 3}, 2, 2, "");
      },
      "4 values"));

  // CSV round trip with comments, blank lines, spaces, NaN and an empty field.
  const std::string csv = dir + "/cog.csv";
  {
    std::ofstream out(csv);
    out << "# written by a test\n\ntime_s, z_m ,mass\n0,0.15,1\n0.5, 0.1525 ,nan\n"
        << "# a comment in between\n1,-2.5e-3,\n";
  }
  const CsvTable t = readCsv(csv);
  RCFD_CHECK(t.header.size() == 3 && t.header[1] == "z_m");
  RCFD_CHECK(t.columns.size() == 3 && t.columns[0].size() == 3);
  RCFD_CHECK_CLOSE(t.column("z_m")[1], 0.1525, 1e-15);
  RCFD_CHECK_CLOSE(t.column("z_m")[2], -2.5e-3, 1e-15);
  RCFD_CHECK(std::isnan(t.column("mass")[1]) && std::isnan(t.column("mass")[2]));
  RCFD_CHECK(t.find("nope") == -1);
  RCFD_CHECK(throwsContaining([&] { t.column("nope"); }, "has no column 'nope'"));

  {
    std::ofstream out(csv);
    out << "# header follows\na,b\n1,2\n3,4x\n";
  }
  RCFD_CHECK(throwsContaining([&] { readCsv(csv); }, csv + ":4: '4x' in column 'b'"));
  {
    std::ofstream out(csv);
    out << "a,b\n1,2,3\n";
  }
  RCFD_CHECK(throwsContaining([&] { readCsv(csv); }, csv + ":2: expected 2"));
  {
    std::ofstream out(csv);
    out << "# only comments\n";
  }
  RCFD_CHECK(throwsContaining([&] { readCsv(csv); }, "no header"));
  RCFD_CHECK(throwsContaining([&] { readCsv(dir + "/absent.csv"); }, "absent.csv"));

  std::filesystem::remove_all(tmp);
}

} // namespace

int main() {
  testTicks();
  testFont();
  testPngStructure();
  testKnownPixels();
  testClippingAndGaps();
  testBand();
  testDegenerateInput();
  testFiles();
  return RCFD_TEST_RESULT();
}
