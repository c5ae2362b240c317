// PNG line plots and heat maps with no plotting tool installed: a small
// software rasteriser (antialiased lines, shaded bands, bitmap text) and a
// PNG encoder on top of zlib.  Also a tiny CSV reader, so that the command
// line can plot the time series rcfd writes.  Independent of PETSc and MPI.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace rcfd::plot {

/// "Choose from the data" for the axis limits of Figure and Heatmap.
inline constexpr double kAuto = std::numeric_limits<double>::quiet_NaN();

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb &o) const { return r == o.r && g == o.g && b == o.b; }
  bool operator!=(const Rgb &o) const { return !(*this == o); }
};

/// One curve.  x and y have equal length; a NaN in either breaks the line (a
/// point with no finite neighbour is drawn as a dot).  yLow and yHigh are
/// either both empty or both as long as x: a shaded band (e.g. the spread of
/// an ensemble) drawn under the line, broken by NaNs in the same way.
struct Series {
  std::string label; ///< legend text; series with an empty label are left out of the legend
  std::vector<double> x, y;
  std::vector<double> yLow, yHigh;
};

struct Figure {
  std::string title, xLabel, yLabel; ///< UTF-8; characters the font lacks show as boxes
  std::vector<Series> series;        ///< colours follow seriesColor(index)
  int width = 900, height = 560;     ///< pixels, at least 240 x 180
  /// Axis limits; kAuto (NaN) takes the data range (y with a 5 % margin).
  double xMin = kAuto, xMax = kAuto, yMin = kAuto, yMax = kAuto;
};

/// Colour of the index-th series: ten distinct colours, then repeating.
Rgb seriesColor(int index);

/// Tick values at multiples of a "nice" step (1, 2 or 5 times a power of
/// ten), the smallest such step giving at most maxTicks ticks in [lo, hi].
/// Returns no ticks unless lo < hi, both finite.
struct Ticks {
  double step = 0;
  std::vector<double> values;
};
Ticks niceTicks(double lo, double hi, int maxTicks);

/// Labels for ticks, all in one notation with as many decimals as the step
/// needs ("0.15", "20", "-0.005", "2.5e-6"); never "-0".
std::vector<std::string> tickLabels(const Ticks &ticks);

/// Where renderRgb() puts the data: the plot area in pixels (data are
/// clipped to it), the axis limits, and the ticks.  The value v maps to the
/// pixel coordinate left + 0.5 + (v - xMin) / (xMax - xMin) * (width - 1),
/// i.e. the limits fall on the centres of the outermost pixel columns (rows
/// likewise, with yMax at the top).
struct PlotLayout {
  int left = 0, top = 0, width = 0, height = 0;
  double xMin = 0, xMax = 1, yMin = 0, yMax = 1;
  Ticks xTicks, yTicks;
};
/// Throws std::invalid_argument for an inconsistent figure (series lengths,
/// limits with min >= max, too small an image).
PlotLayout layoutFigure(const Figure &figure);

/// The figure as 8-bit RGB pixels, row by row from the top; width and height
/// (either may be null) receive the image size.  Throws like layoutFigure().
std::vector<std::uint8_t> renderRgb(const Figure &figure, int *width, int *height);

/// Renders the figure into an RGB PNG file, written to path + ".tmp" and
/// renamed to path, so a reader never sees half a file.  Throws
/// std::runtime_error naming the file when it cannot be written.
void writePng(const std::string &path, const Figure &figure);

/// A matrix drawn as coloured cells, row 0 at the top, with a colour bar.
/// Matrices larger than the drawing area are shown block-averaged.
struct Heatmap {
  std::vector<double> values; ///< rows * cols, row-major; NaN cells are grey
  int rows = 0, cols = 0;
  std::string title, xLabel = "column", yLabel = "row";
  /// Colour scale limits; kAuto takes the finite data range.
  double vMin = kAuto, vMax = kAuto;
};
/// Throws std::invalid_argument for an empty matrix or a size mismatch.
std::vector<std::uint8_t> renderHeatmapRgb(const Heatmap &map, int *width, int *height);
void writeHeatmapPng(const std::string &path, const Heatmap &map);
/// Shorthand for a matrix with automatic colour scale and default labels,
/// e.g. a K x K recurrence matrix.
void writeHeatmapPng(const std::string &path, const std::vector<double> &rowMajor, int rows,
                     int cols, const std::string &title);

/// The bytes of an 8-bit RGB PNG (IHDR, one zlib-compressed IDAT, IEND) of
/// width * height pixels given row by row; throws std::invalid_argument when
/// rgb has the wrong size.
std::vector<std::uint8_t> encodePng(const std::vector<std::uint8_t> &rgb, int width, int height);
/// encodePng() written atomically to path (see writePng()).
void writeRgbPng(const std::string &path, const std::vector<std::uint8_t> &rgb, int width,
                 int height);

/// A numeric CSV file: the header's column names and the values by column.
struct CsvTable {
  std::string path; ///< where it was read from, for messages
  std::vector<std::string> header;
  std::vector<std::vector<double>> columns;

  /// Index of the column named name, or -1.
  int find(const std::string &name) const;
  /// The column named name; throws std::runtime_error naming the file and
  /// the available columns when there is none.
  const std::vector<double> &column(const std::string &name) const;
};

/// Reads a comma-separated file whose first line (after blank lines and
/// lines starting with '#') names the columns and whose other lines hold
/// numbers; an empty field reads as NaN, and so do "nan" and "inf" as strtod
/// understands them.  Throws std::runtime_error with "path:line: ..." for a
/// malformed number or a wrong number of fields, and naming the file when it
/// cannot be read or has no header.
CsvTable readCsv(const std::string &path);

} // namespace rcfd::plot
