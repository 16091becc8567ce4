// plot.hpp: the figures and tables of `refraster study`: SVG charts, the Pareto front, CSV.
//
// Implements: a self-contained SVG (no scripts, no external fonts or files) of one or more
// chart panels side by side, each a scatter of labelled points or a set of curves, on linear or
// logarithmic axes with ticks at round values; zero (and negative) values on a logarithmic axis
// drawn on a separate "0" row/column below the smallest decade, so that an exact variant's
// error of 0 stays visible; the Pareto front of points minimising both coordinates, marked
// and joined; CSV text with RFC 4180 quoting.
//
// Deliberately does not: lay out text with real font metrics (labels use an estimated width
// and are nudged apart vertically), or read data from files.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace harness::study {

struct PlotPoint {
    double x = 0.0;
    double y = 0.0;
    std::string label;  // drawn beside the point in scatter panels; may be empty
};

struct PlotSeries {
    std::string name;  // in the panel's legend
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

// The figure: a title, then the panels in a grid of `columns` columns.
std::string svg_figure(const std::string& title, const std::vector<PlotPanel>& panels,
                       int columns = 2);

// Indices of the points on the Pareto front minimising (x, y): a point is on it if no other
// point has x <= its x and y <= its y with one of them strictly smaller. Ordered by x.
// Equal points are all on the front.
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
