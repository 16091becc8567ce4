// plot.hpp: the figures and tables of `refraster study`: SVG charts, the Pareto front, CSV.
//
// Implements: a self-contained SVG (no scripts, no external fonts or files) of one or more
// chart panels side by side, each a scatter of labelled points or a set of curves, on linear or
// logarithmic axes with ticks at round values; zero (and negative) values on a logarithmic axis
// drawn on a separate "0" row/column below the smallest decade, so that an exact variant's
// error of 0 stays visible; a point's measured spread in x (a run time's range over
// rounds) as a whisker; the Pareto front of points minimising both coordinates, where a point
// beats another on x only beyond their spreads, marked and joined; one colour and marker per
// series name in every panel of a figure; figures no wider than a page (kMaxFigureWidth), the
// panels stacked when side by side they would not fit; CSV text with RFC 4180 quoting.
//
// Deliberately does not: lay out text with real font metrics (labels use an estimated width
// and are nudged apart vertically), or read data from files.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace harness::study {

// The widest figure, in pixels: a page of documentation shows it at about its own size, so
// that its 10-11 px text stays readable.
constexpr double kMaxFigureWidth = 1000.0;

struct PlotPoint {
    double x = 0.0;
    double y = 0.0;
    std::string label;  // drawn beside the point in scatter panels; may be empty
    // The range x was measured in (the range of repeated runs, x their median),
    // drawn as a whisker; NaN when x is exact. x_low <= x <= x_high.
    double x_low = std::numeric_limits<double>::quiet_NaN();
    double x_high = std::numeric_limits<double>::quiet_NaN();
};

struct PlotSeries {
    // In the panel's legend; series of one name share a colour and marker in every panel of
    // the figure.
    std::string name;
    std::vector<PlotPoint> points;
    bool line = false;  // join the points in order (a curve), otherwise a scatter
};

struct PlotPanel {
    std::string title;
    std::string x_label;
    std::string y_label;
    bool log_x = false;
    bool log_y = false;
    std::vector<PlotSeries> series;
    // Mark the Pareto front over all points of all series (minimising x and y): ringed points
    // joined by a dashed staircase, listed in the legend as "Pareto front".
    bool pareto = false;
    // Optional vertical reference lines (x, label), e.g. "z24 step".
    std::vector<std::pair<double, std::string>> x_marks;
};

// Where a figure's legend goes: right of each panel (its own series), or once under the title
// for every series name of the figure (for panels that show the same variants).
enum class Legend { PerPanel, Shared };

// The figure: a title, then the panels in a grid of at most `columns` columns, fewer when the
// figure would be wider than kMaxFigureWidth.
std::string svg_figure(const std::string& title, const std::vector<PlotPanel>& panels,
                       int columns = 2, Legend legend = Legend::PerPanel);

// Indices of the points on the Pareto front minimising (x, y), ordered by x. A point q beats p
// when q.y <= p.y, q is not slower beyond the spread (q's x range starts at or below the end of
// p's), and q is better in one of them: q.y < p.y, or q is faster beyond the spread (q's range
// ends below the start of p's). A point is on the front when no other beats it. Without a
// spread (x_low, x_high NaN) a range is the point x itself, and this is the usual definition:
// q.x <= p.x and q.y <= p.y with one strictly smaller. Equal points are all on the front, and
// so are points of equal y whose ranges overlap: the measurement cannot tell them apart.
std::vector<std::size_t> pareto_front(const std::vector<PlotPoint>& points);

// CSV: a table built row by row; each cell is quoted when it holds a comma, quote or newline.
class CsvTable {
  public:
    explicit CsvTable(std::vector<std::string> columns);
    // Values in column order; a row of the wrong length is a programming error (asserted).
    void add_row(std::vector<std::string> cells);
    std::string text() const;  // header line, then rows, each ending in "\n"
    std::size_t rows() const { return rows_.size(); }

  private:
    std::vector<std::string> columns_;
    std::vector<std::vector<std::string>> rows_;
};

// Shortest round-trip text of a double ("0.1", "1e-07", "nan" never: NaN is asserted against);
// integers without a decimal point.
std::string csv_number(double v);

}  // namespace harness::study
