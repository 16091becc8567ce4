// plot.cpp: the figures and tables of `refraster study` (plot.hpp).
//
// Implements: the figure's layout (a title, then a grid of cells as wide as the widest panel of
// their column, each a panel: a title, the plot area with its frame, grid, ticks and axis
// labels, and a legend to the right of it, in more columns when it is long); axes that map a
// value to a pixel, linear with ticks every 1, 2 or 5 x 10^k, or logarithmic with ticks at
// decades and a "0" row or column in a band of its own beyond an axis break; scatter points
// with their labels placed greedily where they overlap nothing drawn before them and are not
// nearer another point; curves broken at non-finite values; the Pareto front; vertical
// reference lines; CSV text.
//
// Deliberately does not: measure text (widths are estimated from the number of characters),
// clip (every range is computed to hold everything drawn in it), or draw minor grid lines.
#include "study/plot.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string_view>
#include <utility>

#include "harness/markup.hpp"
#include "refraster/assert.hpp"

namespace harness::study {

namespace {

// Sizes in pixels. The plot area is the same in every panel so that panels read alike.
constexpr double kPlotWidth = 400.0;
constexpr double kPlotHeight = 290.0;
constexpr double kPanelTop = 34.0;     // the panel's title above the plot area
constexpr double kPanelBottom = 48.0;  // tick labels and the x axis label
constexpr double kYLabelSpace = 24.0;  // the rotated y axis label left of the tick labels
constexpr double kLegendGap = 18.0;    // between the plot area and the legend
constexpr double kCellPadding = 12.0;  // right of the legend
constexpr double kFigureTitle = 40.0;  // the figure's title above the grid
constexpr double kZeroBand = 30.0;     // a logarithmic axis's "0" row or column and its break
constexpr double kZeroOffset = 11.0;   // the "0" position, from the plot area's edge
constexpr double kTickFont = 10.5;
constexpr double kLabelFont = 10.0;  // point labels
constexpr double kLabelGap = 10.0;   // from a point to its label, clear of a front's ring
constexpr double kRing = 7.5;        // the radius of a front's ring
constexpr double kLegendFont = 11.0;
constexpr double kLegendRow = 17.0;
constexpr double kCharWidth = 0.6;  // an estimate of sans-serif advance per character, in ems

constexpr const char* kGridStyle = "stroke=\"#e6e6e6\" stroke-width=\"1\"";
constexpr const char* kAxisStyle = "stroke=\"#555555\" stroke-width=\"1\"";
constexpr const char* kMinorStyle = "stroke=\"#777777\" stroke-width=\"0.8\"";
constexpr const char* kTextStyle = "fill=\"#333333\"";

// Ten colours that stay apart for most colour vision and on white (the Tableau 10 set).
constexpr std::array<const char*, 10> kPalette = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2",
                                                  "#59a14f", "#edc948", "#b07aa1", "#ff9da7",
                                                  "#9c755f", "#bab0ac"};

enum class Marker { Circle, Square, Triangle, Diamond };
constexpr std::array<Marker, 4> kMarkers = {Marker::Circle, Marker::Square, Marker::Triangle,
                                            Marker::Diamond};

// A series' style is its name's place among the figure's series names (in order of first
// appearance), so that one name has one colour and marker in every panel.
const char* colour_of(std::size_t style) {
    return kPalette[style % kPalette.size()];
}

// The marker changes only once the colours have all been used, so that two series never share
// both.
Marker marker_of(std::size_t style) {
    return kMarkers[(style / kPalette.size()) % kMarkers.size()];
}

using StyleOf = std::vector<std::size_t>;  // per series of a panel, its style

// A coordinate or length: at most two decimals, no trailing zeros, never "-0", and never
// "nan" or "inf" (a non-finite value here would be a layout bug; 0 keeps the document valid).
std::string num(double v) {
    if (!std::isfinite(v)) return "0";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    std::string s = buf;
    if (s.find('.') != std::string::npos) {
        while (s.back() == '0') s.pop_back();
        if (s.back() == '.') s.pop_back();
    }
    if (s == "-0") s = "0";
    return s;
}

double text_width(std::string_view s, double font) {
    // UTF-8 continuation bytes do not start a character.
    std::size_t chars = 0;
    for (char c : s) {
        if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) ++chars;
    }
    return static_cast<double>(chars) * font * kCharWidth;
}

// "%g"'s exponent without its plus sign and leading zeros: "1e+06" -> "1e6", "2e-07" -> "2e-7".
std::string tidy_exponent(std::string s) {
    const std::size_t e = s.find('e');
    if (e == std::string::npos) return s;
    std::string mantissa = s.substr(0, e);
    std::string exponent = s.substr(e + 1);
    bool negative = false;
    if (!exponent.empty() && (exponent[0] == '+' || exponent[0] == '-')) {
        negative = exponent[0] == '-';
        exponent.erase(0, 1);
    }
    while (exponent.size() > 1 && exponent[0] == '0') exponent.erase(0, 1);
    return mantissa + "e" + (negative ? "-" : "") + exponent;
}

// A tick label on a linear axis: `v` is a multiple of `step` (1, 2 or 5 x 10^k), printed with
// exactly the decimals the step needs, or with an exponent when that would be long.
std::string linear_tick_text(double v, double step, double largest) {
    if (std::fabs(v) < step * 1e-6) return "0";
    const int step_exp = static_cast<int>(std::floor(std::log10(step) + 1e-9));
    char buf[64];
    if (step_exp >= -4 && largest < 1e6) {
        std::snprintf(buf, sizeof buf, "%.*f", std::max(0, -step_exp), v);
        return buf;
    }
    const int v_exp = static_cast<int>(std::floor(std::log10(std::fabs(v)) + 1e-9));
    const int digits = std::clamp(v_exp - step_exp + 1, 1, 15);
    std::snprintf(buf, sizeof buf, "%.*e", digits - 1, v);
    std::string s = buf;
    // Drop the mantissa's trailing zeros: "2.50e-07" -> "2.5e-07".
    const std::size_t e = s.find('e');
    std::string mantissa = s.substr(0, e);
    if (mantissa.find('.') != std::string::npos) {
        while (mantissa.back() == '0') mantissa.pop_back();
        if (mantissa.back() == '.') mantissa.pop_back();
    }
    return tidy_exponent(mantissa + s.substr(e));
}

// A tick label on a logarithmic axis, m x 10^k with m in 1 to 9: plain from 0.001 to 9000,
// where plain is about as short as the exponent form, otherwise "1e-6", "5e4".
std::string log_tick_text(int mantissa, int exponent) {
    if (exponent >= -3 && exponent <= 3) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.*f", std::max(0, -exponent),
                      mantissa * std::pow(10.0, exponent));
        return buf;
    }
    return std::to_string(mantissa) + "e" + std::to_string(exponent);
}

// Whether `v` can be placed on an axis: finite, and on a linear axis small enough that a range
// padded around it stays finite.
bool drawable(double v, bool log) {
    return std::isfinite(v) && (log || std::fabs(v) <= 1e300);
}

struct Tick {
    double value;  // in data units
    std::string text;
    bool major;  // a grid line and a label; otherwise a short mark only
};

// One axis: data values to pixels along the plot area, from `p_low` (the pixel of the low end)
// to `p_high`. On a logarithmic axis with values <= 0 the low end holds a band of its own for
// them: "0" at `p_zero`, then a gap with the break mark, then the decades.
class Axis {
  public:
    Axis(bool log, const std::vector<double>& values, double p_low, double p_high)
        : log_(log), p_low_(p_low), p_high_(p_high) {
        std::vector<double> finite;
        for (double v : values) {
            if (!drawable(v, log_)) continue;
            if (log_ && v <= 0.0) {
                zero_ = true;
                negative_ = negative_ || v < 0.0;
                continue;
            }
            finite.push_back(log_ ? std::log10(v) : v);
        }
        if (finite.empty()) {
            lo_ = 0.0;
            hi_ = 1.0;
        } else {
            const auto [mn, mx] = std::minmax_element(finite.begin(), finite.end());
            lo_ = *mn;
            hi_ = *mx;
            const double span = hi_ - lo_;
            // A span too small to divide into ticks (one point, equal values) gets a width
            // proportional to its magnitude, so that its ticks are round numbers near it.
            if (span <= std::max(std::fabs(lo_), std::fabs(hi_)) * 1e-9 || span == 0.0) {
                const double half =
                    log_ ? 0.5 : (lo_ == 0.0 ? 1.0 : std::max(std::fabs(lo_) * 0.1, 1e-300));
                lo_ -= half;
                hi_ += half;
            } else {
                const double pad = span * (log_ ? 0.06 : 0.05);
                lo_ -= pad;
                hi_ += pad;
            }
        }
        const double sign = p_high_ >= p_low_ ? 1.0 : -1.0;
        p_zero_ = p_low_ + sign * kZeroOffset;
        p_main_ = zero_ ? p_low_ + sign * kZeroBand : p_low_;
        make_ticks();
    }

    // The pixel of `v`, or nothing for a value that cannot be drawn (inf, NaN).
    std::optional<double> map(double v) const {
        if (!drawable(v, log_)) return std::nullopt;
        double t = v;
        if (log_) {
            if (v <= 0.0) return p_zero_;
            t = std::log10(v);
        }
        const double p = p_main_ + (t - lo_) / (hi_ - lo_) * (p_high_ - p_main_);
        if (!std::isfinite(p)) return std::nullopt;
        return p;
    }

    // Whether `v` falls in the "0" band rather than the main range.
    bool in_zero_band(double v) const { return log_ && v <= 0.0; }

    const std::vector<Tick>& ticks() const { return ticks_; }
    bool has_zero_band() const { return zero_; }
    double zero_pixel() const { return p_zero_; }
    double break_pixel() const { return p_zero_ + (p_main_ - p_zero_) * 0.6; }
    // "0", or "≤0" (in UTF-8) when negative values share the row.
    std::string zero_text() const { return negative_ ? "\xE2\x89\xA4\x30" : "0"; }

  private:
    void make_ticks() {
        if (log_) {
            make_log_ticks();
        } else {
            make_linear_ticks();
        }
    }

    void make_linear_ticks() { add_linear_ticks(lo_, hi_, 5.0); }

    // Ticks every 1, 2 or 5 x 10^k from `lo` to `hi` (data values), about `count` of them.
    void add_linear_ticks(double lo, double hi, double count) {
        const double raw = (hi - lo) / count;
        const double step = markup::tick_step(raw, 0.999);
        const double largest = std::max(std::fabs(lo), std::fabs(hi));
        // Multiples of the step counted in integers, so that 0.1 * 3 is printed as 0.3.
        for (const double v : markup::linear_ticks(lo, hi, step)) {
            ticks_.push_back({v, linear_tick_text(v, step, largest), true});
        }
    }

    void make_log_ticks() {
        const int first = static_cast<int>(std::ceil(lo_ - 1e-9));
        const int last = static_cast<int>(std::floor(hi_ + 1e-9));
        const int decades = last - first + 1;
        // Eight labelled decades at most; the others get a mark.
        const int every = std::max(1, (decades + 7) / 8);
        for (const markup::DecadeTick& d : markup::decade_ticks(first, last).major) {
            const bool labelled = (d.exponent - first) % every == 0;
            ticks_.push_back(
                {d.value, labelled ? log_tick_text(1, d.exponent) : std::string(), labelled});
        }
        // Within a decade or two, 2 and 5 are labelled too (and within half a decade every
        // multiple), so that a short range has ticks to read; over a few decades, 2 to 9 are
        // marks that show the scale is logarithmic.
        const double span = hi_ - lo_;
        const bool label_minor = decades < 2 || span < 1.5;
        const bool mark_minor = span <= 6.0;
        if (label_minor || mark_minor) {
            // The decades that hold lo_ and hi_, the top one's marks included.
            const markup::DecadeTicks decades_around = markup::decade_ticks(
                static_cast<int>(std::floor(lo_)), static_cast<int>(std::ceil(hi_)) + 1);
            for (const markup::DecadeTick& d : decades_around.minor) {
                const int m = d.mantissa;
                const double t = std::log10(m) + d.exponent;
                if (t < lo_ || t > hi_) continue;
                const bool labelled = label_minor && (span < 0.5 || m == 2 || m == 5);
                ticks_.push_back(
                    {d.value, labelled ? log_tick_text(m, d.exponent) : std::string(), labelled});
            }
        }
        // A range narrower than the gap between two of those is nearly linear: it gets a
        // linear axis's round ticks instead.
        const auto labelled =
            std::count_if(ticks_.begin(), ticks_.end(), [](const Tick& t) { return t.major; });
        if (labelled < 2) {
            ticks_.clear();
            add_linear_ticks(std::pow(10.0, lo_), std::pow(10.0, hi_), 4.0);
        }
    }

    bool log_;
    double p_low_;
    double p_high_;
    double p_zero_ = 0.0;
    double p_main_ = 0.0;
    double lo_ = 0.0;  // the main range, log10 of the values on a logarithmic axis
    double hi_ = 1.0;
    bool zero_ = false;
    bool negative_ = false;
    std::vector<Tick> ticks_;
};

// The SVG text of a marker centred at (x, y), `r` its half size.
std::string marker_svg(Marker m, double x, double y, double r, const char* colour) {
    const std::string fill =
        std::string("fill=\"") + colour + "\" stroke=\"#ffffff\" " + "stroke-width=\"0.8\"";
    switch (m) {
        case Marker::Circle:
            return "<circle cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"" + num(r) + "\" " +
                   fill + "/>";
        case Marker::Square:
            return "<rect x=\"" + num(x - r * 0.9) + "\" y=\"" + num(y - r * 0.9) + "\" width=\"" +
                   num(r * 1.8) + "\" height=\"" + num(r * 1.8) + "\" " + fill + "/>";
        case Marker::Triangle:
            return "<polygon points=\"" + num(x) + "," + num(y - r * 1.15) + " " +
                   num(x + r * 1.1) + "," + num(y + r * 0.75) + " " + num(x - r * 1.1) + "," +
                   num(y + r * 0.75) + "\" " + fill + "/>";
        case Marker::Diamond:
            return "<polygon points=\"" + num(x) + "," + num(y - r * 1.25) + " " +
                   num(x + r * 1.05) + "," + num(y) + " " + num(x) + "," + num(y + r * 1.25) + " " +
                   num(x - r * 1.05) + "," + num(y) + "\" " + fill + "/>";
    }
    return {};
}

std::string text_svg(double x, double y, std::string_view text, double font,
                     std::string_view anchor = "start", std::string_view extra = {}) {
    std::string s =
        "<text x=\"" + num(x) + "\" y=\"" + num(y) + "\" font-size=\"" + num(font) + "\"";
    if (anchor != "start") s += " text-anchor=\"" + std::string(anchor) + "\"";
    if (!extra.empty()) s += " " + std::string(extra);
    return s + ">" + markup::escape(text) + "</text>\n";
}

std::string line_svg(double x1, double y1, double x2, double y2, std::string_view style) {
    return "<line x1=\"" + num(x1) + "\" y1=\"" + num(y1) + "\" x2=\"" + num(x2) + "\" y2=\"" +
           num(y2) + "\" " + std::string(style) + "/>\n";
}

struct Box {
    double x0, y0, x1, y1;
    bool overlaps(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

// A point as drawn: its pixel and the point.
struct Drawn {
    double px;
    double py;
    const PlotPoint* point;
};

// The legend: a column of entries (a sample, then the name) as tall as the plot area, and as
// many more columns beside it as the entries need.
struct LegendLayout {
    std::size_t per_column;
    double column_width;
    std::size_t columns;
    double width() const { return static_cast<double>(columns) * column_width; }
};

LegendLayout legend_layout(const PlotPanel& panel) {
    double widest = text_width("Pareto front", kLegendFont);
    for (const PlotSeries& s : panel.series) {
        widest = std::max(widest, text_width(s.name, kLegendFont));
    }
    const std::size_t entries = panel.series.size() + (panel.pareto ? 1 : 0);
    const auto per_column = static_cast<std::size_t>(kPlotHeight / kLegendRow);
    return {per_column, 30.0 + widest + 12.0,
            std::max<std::size_t>(1, (entries + per_column - 1) / per_column)};
}

double tick_label_width(const Axis& axis) {
    double widest = axis.has_zero_band() ? text_width(axis.zero_text(), kTickFont) : 0.0;
    for (const Tick& t : axis.ticks()) widest = std::max(widest, text_width(t.text, kTickFont));
    return widest;
}

struct PanelAxes {
    Axis x;
    Axis y;
};

PanelAxes axes_of(const PlotPanel& panel) {
    std::vector<double> xs;
    std::vector<double> ys;
    for (const PlotSeries& s : panel.series) {
        for (const PlotPoint& p : s.points) {
            // A point is drawn only when both coordinates are; the other must not stretch
            // the range of an axis it is not on.
            if (!drawable(p.x, panel.log_x) || !drawable(p.y, panel.log_y)) continue;
            xs.push_back(p.x);
            ys.push_back(p.y);
            for (double x : {p.x_low, p.x_high})
                if (drawable(x, panel.log_x)) xs.push_back(x);
        }
    }
    // Reference lines are there to be seen next to the data, so the range holds them.
    for (const auto& [x, label] : panel.x_marks) xs.push_back(x);
    // Pixel coordinates relative to the plot area's top left corner.
    return {Axis(panel.log_x, xs, 0.0, kPlotWidth), Axis(panel.log_y, ys, kPlotHeight, 0.0)};
}

// The break mark across an axis line: two short parallel slashes at `at` along it.
std::string break_mark(bool vertical_axis, double axis_pos, double at) {
    std::string s;
    for (double d : {-2.5, 2.5}) {
        if (vertical_axis) {
            // Drawn over a white gap on the y axis line.
            s += line_svg(axis_pos - 5.0, at + d + 2.0, axis_pos + 5.0, at + d - 2.0, kAxisStyle);
        } else {
            s += line_svg(at + d - 2.0, axis_pos + 5.0, at + d + 2.0, axis_pos - 5.0, kAxisStyle);
        }
    }
    return s;
}

// The scatter labels, placed greedily from the top point down (so that a column of points gets
// a column of labels): each at the nearest of a set of places beside its point (right of it
// preferred, then left, then further up, down or out) that overlaps nothing in `taken` (the
// front's rings and staircase), no marker and no label placed before it, and that is nearer its
// own point than any other point, so that it is not read as another's. A label that is not
// right beside its point is tied to it by a thin line.
std::string place_labels(const std::vector<Drawn>& drawn, std::vector<Box> taken) {
    for (const Drawn& d : drawn) taken.push_back({d.px - 5.0, d.py - 5.0, d.px + 5.0, d.py + 5.0});
    std::vector<const Drawn*> order;
    for (const Drawn& d : drawn) {
        if (!d.point->label.empty()) order.push_back(&d);
    }
    std::stable_sort(order.begin(), order.end(), [](const Drawn* a, const Drawn* b) {
        return a->py < b->py || (a->py == b->py && a->px < b->px);
    });

    // Displacements from the label's place right of its point, cheapest first: a row up or
    // down costs about as much as a step sideways, changing sides a little more.
    struct Place {
        bool left;
        double dx;  // away from the point
        double dy;
        double cost;
    };
    const double row = kLabelFont * 1.15;
    std::vector<Place> places;
    for (int side = 0; side < 2; ++side) {
        for (int h = 0; h <= 8; ++h) {
            // Half rows, so that labels of points a few pixels apart can stack row on row.
            for (int v = -40; v <= 40; ++v) {
                const double dx = 12.0 * h;
                const double dy = row * 0.5 * v;
                places.push_back({side == 1, dx, dy, std::fabs(dy) + dx + side * 6.0});
            }
        }
    }
    std::stable_sort(places.begin(), places.end(),
                     [](const Place& a, const Place& b) { return a.cost < b.cost; });

    std::string out;
    auto box_at = [](double x0, double w, double baseline) {
        return Box{x0, baseline - kLabelFont * 0.8, x0 + w, baseline + kLabelFont * 0.2};
    };
    auto distance = [](const Box& b, double x, double y) {
        return std::hypot(x - std::clamp(x, b.x0, b.x1), y - std::clamp(y, b.y0, b.y1));
    };
    for (const Drawn* d : order) {
        const double w = text_width(d->point->label, kLabelFont);
        const double home = d->py + kLabelFont * 0.35;
        double x0 = d->px + kLabelGap;
        if (x0 + w > kPlotWidth) x0 = d->px - kLabelGap - w;
        double baseline = home;
        bool moved = false;  // to a place nearer another point
        // In a tight cluster every place is nearer some other point; then the nearest free
        // place will do, and its leader tells whose label it is.
        bool found = false;
        for (int pass = 0; pass < 2 && !found; ++pass) {
            for (const Place& p : places) {
                const double x = p.left ? d->px - kLabelGap - p.dx - w : d->px + kLabelGap + p.dx;
                const double b = home + p.dy;
                // Inside the plot area, where nothing but data is drawn.
                if (x < 0.0 || x + w > kPlotWidth || b - kLabelFont < 0.0 || b > kPlotHeight) {
                    continue;
                }
                const Box box = box_at(x, w, b);
                if (std::any_of(taken.begin(), taken.end(),
                                [&](const Box& t) { return t.overlaps(box); })) {
                    continue;
                }
                const double own = distance(box, d->px, d->py);
                if (pass == 0 && std::any_of(drawn.begin(), drawn.end(), [&](const Drawn& o) {
                        return &o != d && distance(box, o.px, o.py) < own;
                    })) {
                    continue;
                }
                x0 = x;
                baseline = b;
                moved = pass == 1;
                found = true;
                break;
            }
        }
        const Box box = box_at(x0, w, baseline);
        taken.push_back(box);
        // The leader runs from the marker's edge to the nearest point of the label's box.
        const double tx = std::clamp(d->px, box.x0 - 1.0, box.x1 + 1.0);
        const double ty = std::clamp(d->py, box.y0, box.y1);
        const double dist = std::hypot(tx - d->px, ty - d->py);
        if (dist > 6.0 && (moved || dist > kLabelGap + 2.0)) {
            const double sx = d->px + (tx - d->px) / dist * 5.0;
            const double sy = d->py + (ty - d->py) / dist * 5.0;
            out += line_svg(sx, sy, tx, ty, "stroke=\"#999999\" stroke-width=\"0.6\"");
        }
        out += text_svg(x0, baseline, d->point->label, kLabelFont, "start", kTextStyle);
    }
    return out;
}

// One panel, drawn with (0, 0) at the plot area's top left corner.
std::string panel_svg(const PlotPanel& panel, const PanelAxes& axes, double left_margin,
                      const StyleOf& style, bool own_legend) {
    const Axis& ax = axes.x;
    const Axis& ay = axes.y;
    std::string s;

    // The title, centred over the plot area.
    s += text_svg(kPlotWidth / 2.0, -kPanelTop + 20.0, panel.title, 13.0, "middle",
                  "font-weight=\"bold\"");

    // Grid and ticks.
    s += "<g>\n";
    for (const Tick& t : ax.ticks()) {
        const auto px = ax.map(t.value);
        if (!px) continue;
        if (t.major) {
            s += line_svg(*px, 0.0, *px, kPlotHeight, kGridStyle);
            s += line_svg(*px, kPlotHeight, *px, kPlotHeight + 5.0, kAxisStyle);
            s += text_svg(*px, kPlotHeight + 18.0, t.text, kTickFont, "middle", kTextStyle);
        } else {
            s += line_svg(*px, kPlotHeight, *px, kPlotHeight + 3.0, kMinorStyle);
        }
    }
    for (const Tick& t : ay.ticks()) {
        const auto py = ay.map(t.value);
        if (!py) continue;
        if (t.major) {
            s += line_svg(0.0, *py, kPlotWidth, *py, kGridStyle);
            s += line_svg(-5.0, *py, 0.0, *py, kAxisStyle);
            s += text_svg(-8.0, *py + kTickFont * 0.35, t.text, kTickFont, "end", kTextStyle);
        } else {
            s += line_svg(-3.0, *py, 0.0, *py, kMinorStyle);
        }
    }
    // The "0" row and column: a grid line and label like a tick's, set apart by a break.
    if (ax.has_zero_band()) {
        const double p = ax.zero_pixel();
        s += line_svg(p, 0.0, p, kPlotHeight, kGridStyle);
        s += line_svg(p, kPlotHeight, p, kPlotHeight + 5.0, kAxisStyle);
        s += text_svg(p, kPlotHeight + 18.0, ax.zero_text(), kTickFont, "middle", kTextStyle);
    }
    if (ay.has_zero_band()) {
        const double p = ay.zero_pixel();
        s += line_svg(0.0, p, kPlotWidth, p, kGridStyle);
        s += line_svg(-5.0, p, 0.0, p, kAxisStyle);
        s += text_svg(-8.0, p + kTickFont * 0.35, ay.zero_text(), kTickFont, "end", kTextStyle);
    }
    s += "</g>\n";

    // The frame, then the breaks over it: a white gap in the axis line and the slashes, and a
    // dotted line across the plot area where the "0" band ends.
    s += "<rect x=\"0\" y=\"0\" width=\"" + num(kPlotWidth) + "\" height=\"" + num(kPlotHeight) +
         "\" fill=\"none\" stroke=\"#555555\" stroke-width=\"1\"/>\n";
    if (ax.has_zero_band()) {
        const double b = ax.break_pixel();
        s += line_svg(b, 1.0, b, kPlotHeight - 1.0,
                      "stroke=\"#bbbbbb\" stroke-width=\"0.8\" stroke-dasharray=\"1,3\"");
        s += line_svg(b - 3.0, kPlotHeight, b + 3.0, kPlotHeight,
                      "stroke=\"#ffffff\" stroke-width=\"3\"");
        s += break_mark(false, kPlotHeight, b);
    }
    if (ay.has_zero_band()) {
        const double b = ay.break_pixel();
        s += line_svg(1.0, b, kPlotWidth - 1.0, b,
                      "stroke=\"#bbbbbb\" stroke-width=\"0.8\" stroke-dasharray=\"1,3\"");
        s += line_svg(0.0, b - 3.0, 0.0, b + 3.0, "stroke=\"#ffffff\" stroke-width=\"3\"");
        s += break_mark(true, 0.0, b);
    }

    // Axis labels.
    s += text_svg(kPlotWidth / 2.0, kPlotHeight + 38.0, panel.x_label, 11.5, "middle");
    const double ylx = -left_margin + kYLabelSpace - 8.0;
    s += "<text x=\"" + num(ylx) + "\" y=\"" + num(kPlotHeight / 2.0) +
         "\" font-size=\"11.5\" text-anchor=\"middle\" transform=\"rotate(-90 " + num(ylx) + " " +
         num(kPlotHeight / 2.0) + ")\">" + markup::escape(panel.y_label) + "</text>\n";

    // Labels keep off the reference lines' labels, the whiskers and the front.
    std::vector<Box> front_boxes;
    // Reference lines, under the data.
    for (const auto& [x, label] : panel.x_marks) {
        const auto px = ax.map(x);
        if (!px) continue;
        s += line_svg(*px, 0.0, *px, kPlotHeight,
                      "stroke=\"#888888\" stroke-width=\"1\" stroke-dasharray=\"4,3\"");
        if (!label.empty()) {
            // Right of the line, else left of it, else wherever inside the plot area it fits
            // best: never over the tick labels outside it.
            const double w = text_width(label, 9.0);
            double x0 = *px + 3.0;
            if (x0 + w > kPlotWidth) x0 = *px - 3.0 - w;
            if (x0 < 0.0) x0 = std::clamp(*px - w / 2.0, 0.0, std::max(0.0, kPlotWidth - w));
            s += text_svg(x0, 11.0, label, 9.0, "start", "fill=\"#666666\"");
            front_boxes.push_back({x0, 2.0, x0 + w, 14.0});
        }
    }

    // The data: curves first, then every marker, then the labels over them.
    std::vector<Drawn> drawn;
    std::vector<Drawn> scatter;
    std::string curves;
    std::string markers;
    for (std::size_t si = 0; si < panel.series.size(); ++si) {
        const PlotSeries& series = panel.series[si];
        const char* colour = colour_of(style[si]);
        std::vector<std::pair<double, double>> run;
        auto flush = [&]() {
            if (run.size() >= 2) {
                curves += "<polyline fill=\"none\" stroke=\"" + std::string(colour) +
                          "\" stroke-width=\"1.8\" stroke-linejoin=\"round\" points=\"";
                for (std::size_t i = 0; i < run.size(); ++i) {
                    if (i > 0) curves += ' ';
                    curves += num(run[i].first) + "," + num(run[i].second);
                }
                curves += "\"/>\n";
            }
            run.clear();
        };
        const PlotPoint* previous = nullptr;
        for (const PlotPoint& p : series.points) {
            const auto px = ax.map(p.x);
            const auto py = ay.map(p.y);
            if (!px || !py) {
                // A value that cannot be drawn breaks the curve.
                flush();
                previous = nullptr;
                continue;
            }
            if (series.line && previous != nullptr) {
                // A step into or out of the "0" band crosses the break: dotted, since the
                // distance drawn there means nothing.
                const bool was_zero = ax.in_zero_band(previous->x) || ay.in_zero_band(previous->y);
                const bool is_zero = ax.in_zero_band(p.x) || ay.in_zero_band(p.y);
                if (was_zero != is_zero) {
                    const std::pair<double, double> last = run.back();
                    flush();
                    curves += line_svg(last.first, last.second, *px, *py,
                                       "stroke=\"" + std::string(colour) +
                                           "\" stroke-width=\"1.2\" stroke-dasharray=\"2,2\"");
                }
            }
            if (series.line) run.emplace_back(*px, *py);
            previous = &p;
            const Drawn d{*px, *py, &p};
            drawn.push_back(d);
            if (!series.line) scatter.push_back(d);
            // The spread: a whisker with end caps from the fastest to the slowest round.
            const auto lo = ax.map(p.x_low);
            const auto hi = ax.map(p.x_high);
            if (lo && hi && *hi - *lo >= 1.0) {
                const std::string whisker =
                    "stroke=\"" + std::string(colour) + "\" stroke-width=\"1.1\"";
                curves += line_svg(*lo, *py, *hi, *py, whisker);
                curves += line_svg(*lo, *py - 3.5, *lo, *py + 3.5, whisker);
                curves += line_svg(*hi, *py - 3.5, *hi, *py + 3.5, whisker);
                front_boxes.push_back({*lo - 1.0, *py - 4.0, *hi + 1.0, *py + 4.0});
            }
            markers +=
                marker_svg(marker_of(style[si]), *px, *py, series.line ? 3.0 : 4.5, colour) + "\n";
        }
        flush();
    }

    // The Pareto front over all points of the panel, on the values (not the pixels), so that
    // an error of 0 is below every positive one whatever the axis.
    std::vector<PlotPoint> all;
    std::vector<std::pair<double, double>> pixels;
    for (const Drawn& d : drawn) {
        all.push_back({d.point->x, d.point->y, {}, d.point->x_low, d.point->x_high});
        pixels.emplace_back(d.px, d.py);
    }
    std::string front_svg;
    bool front_drawn = false;
    if (panel.pareto) {
        const std::vector<std::size_t> front = pareto_front(all);
        if (!front.empty()) {
            front_drawn = true;
            // A staircase: from each point right to the next one's x, then down to it, the
            // boundary of the region the front dominates.
            std::string path =
                "M" + num(pixels[front[0]].first) + "," + num(pixels[front[0]].second);
            for (std::size_t i = 1; i < front.size(); ++i) {
                const auto [x0, y0] = pixels[front[i - 1]];
                const auto [x, y] = pixels[front[i]];
                path += " H" + num(x) + " V" + num(y);
                // Labels keep off the staircase's lines.
                front_boxes.push_back({std::min(x0, x), y0 - 1.5, std::max(x0, x), y0 + 1.5});
                front_boxes.push_back({x - 1.5, std::min(y0, y), x + 1.5, std::max(y0, y)});
            }
            front_svg += "<path d=\"" + path +
                         "\" fill=\"none\" stroke=\"#222222\" stroke-width=\"1.2\" "
                         "stroke-dasharray=\"5,3\"/>\n";
            for (std::size_t i : front) {
                const auto [x, y] = pixels[i];
                front_svg += "<circle cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"" +
                             num(kRing) +
                             "\" fill=\"none\" stroke=\"#222222\" stroke-width=\"1.3\"/>\n";
                front_boxes.push_back(
                    {x - kRing - 1.0, y - kRing - 1.0, x + kRing + 1.0, y + kRing + 1.0});
            }
        }
    }

    s += "<g>\n" + curves + front_svg + markers + "</g>\n";
    if (drawn.empty()) {
        s += text_svg(kPlotWidth / 2.0, kPlotHeight / 2.0 + 5.0, "no data", 14.0, "middle",
                      "fill=\"#999999\"");
    }
    s += "<g>\n" + place_labels(scatter, front_boxes) + "</g>\n";

    if (!own_legend) return s;
    // The legend, right of the plot area: one row per series, then the front.
    const LegendLayout legend = legend_layout(panel);
    double lx = kPlotWidth + kLegendGap;
    double ly = 6.0;
    std::size_t in_column = 0;
    auto next_entry = [&]() {
        ly += kLegendRow;
        if (++in_column == legend.per_column) {
            in_column = 0;
            ly = 6.0;
            lx += legend.column_width;
        }
    };
    s += "<g>\n";
    for (std::size_t si = 0; si < panel.series.size(); ++si) {
        const PlotSeries& series = panel.series[si];
        const char* colour = colour_of(style[si]);
        if (series.line) {
            s += line_svg(lx, ly, lx + 20.0, ly,
                          "stroke=\"" + std::string(colour) + "\" stroke-width=\"1.8\"");
        }
        s +=
            marker_svg(marker_of(style[si]), lx + 10.0, ly, series.line ? 3.0 : 4.5, colour) + "\n";
        s += text_svg(lx + 27.0, ly + kLegendFont * 0.35, series.name, kLegendFont);
        next_entry();
    }
    if (front_drawn) {
        s += line_svg(lx, ly, lx + 20.0, ly,
                      "stroke=\"#222222\" stroke-width=\"1.2\" stroke-dasharray=\"5,3\"");
        s += "<circle cx=\"" + num(lx + 10.0) + "\" cy=\"" + num(ly) +
             "\" r=\"6\" fill=\"#ffffff\" stroke=\"#222222\" stroke-width=\"1.3\"/>\n";
        s += text_svg(lx + 27.0, ly + kLegendFont * 0.35, "Pareto front", kLegendFont);
    }
    s += "</g>\n";
    return s;
}

}  // namespace

std::string svg_figure(const std::string& title, const std::vector<PlotPanel>& panels, int columns,
                       Legend legend) {
    const bool shared = legend == Legend::Shared;
    // One style per series name, in order of first appearance over the panels.
    std::vector<std::string> names;
    std::vector<StyleOf> styles;
    for (const PlotPanel& panel : panels) {
        StyleOf style;
        for (const PlotSeries& series : panel.series) {
            const auto it = std::find(names.begin(), names.end(), series.name);
            style.push_back(static_cast<std::size_t>(it - names.begin()));
            if (it == names.end()) names.push_back(series.name);
        }
        styles.push_back(std::move(style));
    }

    std::vector<PanelAxes> axes;
    for (const PlotPanel& panel : panels) axes.push_back(axes_of(panel));
    // The cells of a grid column have the width of its widest panel: the tick labels on a
    // panel's left and its legend on its right vary, the plot area does not.
    struct Grid {
        std::size_t cols, rows;
        std::vector<double> left, right, cell_x;
    };
    const auto grid_of = [&](std::size_t cols) {
        Grid g{cols, std::max<std::size_t>(1, (panels.size() + cols - 1) / cols),
               std::vector<double>(cols, 60.0), std::vector<double>(cols, shared ? 0.0 : 110.0),
               std::vector<double>(cols + 1, 0.0)};
        for (std::size_t i = 0; i < panels.size(); ++i) {
            const std::size_t c = i % cols;
            g.left[c] = std::max(g.left[c], kYLabelSpace + tick_label_width(axes[i].y) + 14.0);
            if (!shared) g.right[c] = std::max(g.right[c], legend_layout(panels[i]).width());
        }
        for (std::size_t c = 0; c < cols; ++c) {
            g.cell_x[c + 1] = g.cell_x[c] + g.left[c] + kPlotWidth +
                              (shared ? 0.0 : kLegendGap + g.right[c]) + kCellPadding;
        }
        return g;
    };
    std::size_t cols = std::clamp<std::size_t>(static_cast<std::size_t>(std::max(columns, 1)), 1,
                                               std::max<std::size_t>(panels.size(), 1));
    Grid grid = grid_of(cols);
    while (cols > 1 && grid.cell_x[cols] > kMaxFigureWidth) grid = grid_of(--cols);
    const std::size_t rows = grid.rows;
    const std::vector<double>& left = grid.left;
    const std::vector<double>& cell_x = grid.cell_x;
    const double cell_height = kPanelTop + kPlotHeight + kPanelBottom;
    const double width = std::max(cell_x[cols], text_width(title, 16.0) + 40.0);

    // The shared legend: entries in rows under the title, each a sample and the name.
    struct Entry {
        std::string name;
        std::size_t style;  // or SIZE_MAX for the front
        bool line;
        double x, y;
    };
    std::vector<Entry> entries;
    double legend_height = 0.0;
    if (shared) {
        for (std::size_t n = 0; n < names.size(); ++n) {
            bool line = false;
            for (const PlotPanel& panel : panels)
                for (const PlotSeries& series : panel.series)
                    line = line || (series.name == names[n] && series.line);
            entries.push_back({names[n], n, line, 0.0, 0.0});
        }
        if (std::any_of(panels.begin(), panels.end(), [](const PlotPanel& p) { return p.pareto; }))
            entries.push_back({"Pareto front", static_cast<std::size_t>(-1), true, 0.0, 0.0});
        double x = 20.0, y = kFigureTitle + 4.0;
        for (Entry& e : entries) {
            const double w = 27.0 + text_width(e.name, kLegendFont) + 18.0;
            if (x > 20.0 && x + w > width - 10.0) {
                x = 20.0;
                y += kLegendRow;
            }
            e.x = x;
            e.y = y;
            x += w;
        }
        if (!entries.empty()) legend_height = y - kFigureTitle + kLegendRow;
    }
    const double grid_top = kFigureTitle + legend_height;
    const double height = grid_top + cell_height * static_cast<double>(rows) + 8.0;

    std::string s;
    s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    s += markup::svg_open({{"version", "1.1"},
                           {"width", num(width)},
                           {"height", num(height)},
                           {"viewBox", "0 0 " + num(width) + " " + num(height)},
                           {"font-family", "sans-serif"}}) +
         "\n";
    s += "<title>" + markup::escape(title) + "</title>\n";
    s += "<rect x=\"0\" y=\"0\" width=\"" + num(width) + "\" height=\"" + num(height) +
         "\" fill=\"#ffffff\"/>\n";
    s += text_svg(width / 2.0, 27.0, title, 16.0, "middle", "font-weight=\"bold\"");
    if (panels.empty()) {
        s += text_svg(width / 2.0, kFigureTitle + cell_height / 2.0, "no data", 14.0, "middle",
                      "fill=\"#999999\"");
    }
    if (!entries.empty()) {
        s += "<g>\n";
        for (const Entry& e : entries) {
            if (e.style == static_cast<std::size_t>(-1)) {
                s += line_svg(e.x, e.y, e.x + 20.0, e.y,
                              "stroke=\"#222222\" stroke-width=\"1.2\" stroke-dasharray=\"5,3\"");
                s += "<circle cx=\"" + num(e.x + 10.0) + "\" cy=\"" + num(e.y) +
                     "\" r=\"6\" fill=\"#ffffff\" stroke=\"#222222\" stroke-width=\"1.3\"/>\n";
            } else {
                const char* colour = colour_of(e.style);
                if (e.line) {
                    s += line_svg(e.x, e.y, e.x + 20.0, e.y,
                                  "stroke=\"" + std::string(colour) + "\" stroke-width=\"1.8\"");
                }
                s += marker_svg(marker_of(e.style), e.x + 10.0, e.y, e.line ? 3.0 : 4.5, colour) +
                     "\n";
            }
            s += text_svg(e.x + 27.0, e.y + kLegendFont * 0.35, e.name, kLegendFont);
        }
        s += "</g>\n";
    }
    for (std::size_t i = 0; i < panels.size(); ++i) {
        const std::size_t c = i % cols;
        const double ox = cell_x[c] + left[c];
        const double oy = grid_top + cell_height * static_cast<double>(i / cols) + kPanelTop;
        s += "<g transform=\"translate(" + num(ox) + "," + num(oy) + ")\">\n";
        s += panel_svg(panels[i], axes[i], left[c], styles[i], !shared);
        s += "</g>\n";
    }
    s += markup::svg_close() + "\n";
    return s;
}

std::vector<std::size_t> pareto_front(const std::vector<PlotPoint>& points) {
    // Quadratic, which is plenty for the few dozen variants of a study, and plainly the
    // definition in plot.hpp.
    const auto low = [](const PlotPoint& p) { return std::isfinite(p.x_low) ? p.x_low : p.x; };
    const auto high = [](const PlotPoint& p) { return std::isfinite(p.x_high) ? p.x_high : p.x; };
    const auto beats = [&](const PlotPoint& q, const PlotPoint& p) {
        const bool not_slower = low(q) <= high(p);
        const bool faster = high(q) < low(p);
        return q.y <= p.y && not_slower && (q.y < p.y || faster);
    };
    std::vector<std::size_t> front;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const PlotPoint& p = points[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
        bool beaten = false;
        for (std::size_t j = 0; j < points.size() && !beaten; ++j) {
            const PlotPoint& q = points[j];
            if (j == i || !std::isfinite(q.x) || !std::isfinite(q.y)) continue;
            beaten = beats(q, p);
        }
        if (!beaten) front.push_back(i);
    }
    std::stable_sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) {
        if (points[a].x != points[b].x) return points[a].x < points[b].x;
        return points[a].y < points[b].y;
    });
    return front;
}

CsvTable::CsvTable(std::vector<std::string> columns) : columns_(std::move(columns)) {}

void CsvTable::add_row(std::vector<std::string> cells) {
    REFRASTER_ASSERT(cells.size() == columns_.size(), "a CSV row has one cell per column");
    rows_.push_back(std::move(cells));
}

namespace {

// RFC 4180: a cell holding a comma, a quote or a line break is quoted, its quotes doubled.
void append_cell(std::string& out, const std::string& cell) {
    if (cell.find_first_of(",\"\r\n") == std::string::npos) {
        out += cell;
        return;
    }
    out += '"';
    for (char c : cell) {
        if (c == '"') out += '"';
        out += c;
    }
    out += '"';
}

void append_line(std::string& out, const std::vector<std::string>& cells) {
    for (std::size_t i = 0; i < cells.size(); ++i) {
        if (i > 0) out += ',';
        append_cell(out, cells[i]);
    }
    out += '\n';
}

}  // namespace

std::string CsvTable::text() const {
    std::string out;
    append_line(out, columns_);
    for (const std::vector<std::string>& row : rows_) append_line(out, row);
    return out;
}

std::string csv_number(double v) {
    REFRASTER_ASSERT(!std::isnan(v), "a CSV number is not NaN");
    if (std::isinf(v)) return v > 0.0 ? "inf" : "-inf";
    // Whole numbers a double holds exactly print as integers ("12345", not "12345.0" or
    // "1.2345e+04"); -0 prints as 0, which reads back equal.
    constexpr double kExactIntegers = 9007199254740992.0;  // 2^53
    if (v == std::trunc(v) && std::fabs(v) < kExactIntegers) {
        return std::to_string(static_cast<long long>(v));
    }
    char buf[64];
    const auto result = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, result.ptr);
}

}  // namespace harness::study
