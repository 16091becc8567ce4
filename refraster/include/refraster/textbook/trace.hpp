// trace.hpp: what the textbook algorithms produce, and the step-by-step record of how.
//
// Implements: Raster, a width x height image of coverage weights in GL window coordinates
// (pixel (x, y) covers [x, x+1] x [y, y+1], row 0 at the bottom); Trace, a list of Steps, one
// per decision a lecture would show, each with a one-line title, the named values at that
// point, the pixels it decides and the geometry it points at. Every algorithm of
// refraster::textbook takes an optional Trace* and appends to it; a null Trace* costs nothing
// but the test.
//
// A Trace may be bounded: once it holds max_steps steps, or max_pixels pixel marks, or
// max_segments overlay segments in them, it stops recording; add_step then hands out a scratch
// step that the next call clears, and `omitted` counts the steps not kept. Each kept step is cut
// to max_values values of at most max_value_chars characters (trim_step) when the next one is
// added. So an algorithm run on a large input keeps its first steps and the count of the rest,
// in memory of the bounds' size plus one step. An algorithm that builds an expensive state for a
// step may ask recording() first.
//
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace refraster::textbook {

// A point in window coordinates (pixels, origin bottom-left).
struct Point2 {
    double x = 0.0;
    double y = 0.0;
    friend bool operator==(const Point2&, const Point2&) = default;
};

// One pixel a step decides. weight 1 is lit, a weight in (0, 1) is antialiased coverage, 0 is
// a pixel the step considered and rejected (shown, not drawn).
struct PixelMark {
    int x = 0;
    int y = 0;
    double weight = 1.0;
};

// Geometry a step shows, in window coordinates. role names what it is: "edge", "line",
// "diagonal", "ear", "trapezoid", "span", "scanline", "clip", "circle", ...
struct Segment {
    double x0 = 0.0;
    double y0 = 0.0;
    double x1 = 0.0;
    double y1 = 0.0;
    std::string role;
};

struct Step {
    std::string title;  // "x = 3: d = -2 < 0, keep y = 1"
    // The part of the input the step works on ("segment 2", "polygon 1"), so that a reader can
    // step a part at a time; empty when the algorithm has no parts.
    std::string group;
    // The line of the algorithm's pseudo-code (Trace::pseudo_code, counted from 1) that the step
    // carries out; 0 when none.
    int line = 0;
    std::vector<std::pair<std::string, std::string>> state;  // {"d", "-2"}, {"AEL", "[...]"}
    std::vector<PixelMark> pixels;
    std::vector<Segment> overlay;
};

struct Trace {
    std::string algorithm;  // "Bresenham line", set by the algorithm that fills the trace
    // The algorithm in a few lines of pseudo-code, as a lecture would write it; each step names
    // the line it carries out (Step::line).
    std::vector<std::string> pseudo_code;
    std::vector<Segment> input;  // the input geometry, drawn under every step
    std::vector<Step> steps;
    // The bounds: the most steps kept, and the most pixel marks and overlay segments in them
    // (checked when a step is added, so the last step kept may pass them by its own); the most
    // values a kept step shows, and the most characters of each.
    std::size_t max_steps = std::numeric_limits<std::size_t>::max();
    std::size_t max_pixels = std::numeric_limits<std::size_t>::max();
    std::size_t max_segments = std::numeric_limits<std::size_t>::max();
    std::size_t max_values = std::numeric_limits<std::size_t>::max();
    std::size_t max_value_chars = std::numeric_limits<std::size_t>::max();
    std::size_t omitted = 0;  // steps added past a bound, not kept
    // The part the next steps belong to (begin_part), copied into each step, and the number
    // of parts begun.
    std::string group;
    std::size_t parts = 0;
    // Whether the next add_step is kept.
    bool recording() const;

    // add_step's scratch step past a bound, and the pixel marks and segments of the kept steps
    // before the last one.
    Step discarded;
    std::size_t pixels_before_last = 0;
    std::size_t segments_before_last = 0;
};

class Raster {
  public:
    Raster() = default;
    Raster(int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
    // The weight of pixel (x, y); 0 outside the raster.
    double at(int x, int y) const;
    // Sets, or adds to, the weight of (x, y); pixels outside the raster are dropped.
    void set(int x, int y, double weight);
    void add(int x, int y, double weight);
    // Row-major weights, row 0 at the bottom.
    const std::vector<double>& weights() const { return weight_; }
    // The number of pixels with a weight other than 0.
    int count_nonzero() const;
    friend bool operator==(const Raster&, const Raster&) = default;

  private:
    int width_ = 0;
    int height_ = 0;
    std::vector<double> weight_;
};

// Helpers for the algorithms that write traces: the shortest decimal that reads back as v
// ("0.25", "-3", "1e+20"), and a step appended to a trace if there is one (or, past the
// trace's bounds, a scratch step counted in `omitted`).
std::string format_number(double v);
std::string format_number(long long v);
std::string format_pixel(int x, int y);  // "(3, 4)"
Step& add_step(Trace& trace, std::string title);
// Sets the trace's pseudo-code (Trace::pseudo_code); does nothing without a trace.
void set_pseudo_code(Trace* trace, std::vector<std::string> lines);
// Starts the next part of the input (a segment, a polygon): the steps from here on belong to
// "<kind> <n>", n counting the parts from 1. Does nothing without a trace.
void begin_part(Trace* trace, std::string_view kind);
// Cuts `step` to `max_values` values (the last one kept says how many more there were) of at most
// `max_value_chars` characters each (a cut value says how many characters it lost).
void trim_step(Step& step, std::size_t max_values, std::size_t max_value_chars);
// Appends the closed outline of `polygon` (point k to point k + 1, the last back to the first)
// to `into` as segments of `role`.
void add_outline(std::vector<Segment>& into, const std::vector<Point2>& polygon,
                 const std::string& role = "edge");

}  // namespace refraster::textbook
