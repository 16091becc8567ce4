#include "refraster/textbook/lines.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include "refraster/assert.hpp"

namespace refraster::textbook {

namespace {

// The geometry every line algorithm starts from: its pixel endpoints and which axis is major.
struct LineSetup {
    PixelIndex from;
    PixelIndex to;
    bool x_major = true;
    int major_length = 0;  // |major delta|
    int minor_length = 0;  // |minor delta|
    int major_sign = 1;
    int minor_sign = 1;  // +1 when the minor delta is 0
};

LineSetup setup_line(Point2 a, Point2 b) {
    LineSetup s;
    s.from = pixel_containing(a);
    s.to = pixel_containing(b);
    const int dx = s.to.x - s.from.x;
    const int dy = s.to.y - s.from.y;
    s.x_major = std::abs(dx) >= std::abs(dy);
    const int major = s.x_major ? dx : dy;
    const int minor = s.x_major ? dy : dx;
    s.major_length = std::abs(major);
    s.minor_length = std::abs(minor);
    s.major_sign = major < 0 ? -1 : 1;
    s.minor_sign = minor < 0 ? -1 : 1;
    return s;
}

const char* major_name(const LineSetup& s) {
    return s.x_major ? "x" : "y";
}
const char* minor_name(const LineSetup& s) {
    return s.x_major ? "y" : "x";
}

// The first step of a line's trace (valid until the next add_step), or null without a trace.
Step* begin_trace(Trace* trace, const char* algorithm, std::vector<std::string> code, Point2 a,
                  Point2 b, const LineSetup& s) {
    if (trace == nullptr) return nullptr;
    trace->algorithm = algorithm;
    set_pseudo_code(trace, std::move(code));
    trace->input.push_back({a.x, a.y, b.x, b.y, "line"});
    begin_part(trace, "segment");
    Step& step =
        add_step(*trace, "endpoints to pixels: " + format_pixel(s.from.x, s.from.y) + " to " +
                             format_pixel(s.to.x, s.to.y) + ", " + major_name(s) + " major");
    step.line = 1;
    step.state.push_back({"dx", std::to_string(s.to.x - s.from.x)});
    step.state.push_back({"dy", std::to_string(s.to.y - s.from.y)});
    step.overlay.push_back({s.from.x + 0.5, s.from.y + 0.5, s.to.x + 0.5, s.to.y + 0.5, "line"});
    return &step;
}

// Appends a path pixel and its step.
void emit(LineResult& out, Trace* trace, PixelIndex p, int line, std::string title,
          std::vector<std::pair<std::string, std::string>> state) {
    out.path.push_back(p);
    out.raster.set(p.x, p.y, 1.0);
    if (trace == nullptr) return;
    Step& step = add_step(*trace, std::move(title));
    step.line = line;
    step.state = std::move(state);
    step.pixels.push_back({p.x, p.y, 1.0});
}

PixelIndex at_offsets(const LineSetup& s, int major_offset, int minor_offset) {
    const int major = s.major_sign * major_offset;
    const int minor = s.minor_sign * minor_offset;
    return s.x_major ? PixelIndex{s.from.x + major, s.from.y + minor}
                     : PixelIndex{s.from.x + minor, s.from.y + major};
}

std::string coordinate_title(const LineSetup& s, PixelIndex p) {
    return std::string(major_name(s)) + " = " + std::to_string(s.x_major ? p.x : p.y);
}

int minor_of(const LineSetup& s, PixelIndex p) {
    return s.x_major ? p.y : p.x;
}

}  // namespace

PixelIndex pixel_containing(Point2 p) {
    REFRASTER_ASSERT(
        std::isfinite(p.x) && std::isfinite(p.y) && std::fabs(p.x) < 1e9 && std::fabs(p.y) < 1e9,
        "a line endpoint within int range");
    return {static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y))};
}

bool tie_takes_step(MinorTie tie, int minor_sign) {
    switch (tie) {
        case MinorTie::Keep:
            return false;
        case MinorTie::Step:
            return true;
        case MinorTie::TowardNegative:
            return minor_sign < 0;
        case MinorTie::TowardPositive:
            return minor_sign > 0;
    }
    return false;
}

LineResult dda_line(Point2 a, Point2 b, int width, int height, Trace* trace) {
    const LineSetup s = setup_line(a, b);
    Step* const first =
        begin_trace(trace, "DDA line",
                    {("round both endpoints to pixels; the axis of the larger "
                      "extent is the major one"),
                     "slope = d(minor) / d(major); minor = the first pixel's",
                     "for each pixel along the major axis:", "    plot (major, round(minor))",
                     "    minor = minor + slope"},
                    a, b, s);
    LineResult out{{}, Raster(width, height)};
    // The minor coordinate as the pixel index of the major axis' start plus the running sum
    // of slope increments, in double: the textbook's float accumulation.
    const int minor_start = s.x_major ? s.from.y : s.from.x;
    const double slope = s.major_length == 0
                             ? 0.0
                             : static_cast<double>(s.minor_sign * s.minor_length) / s.major_length;
    if (first != nullptr) first->state.push_back({"slope", format_number(slope)});
    double minor = minor_start;
    for (int i = 0; i <= s.major_length; ++i) {
        const int rounded = static_cast<int>(std::floor(minor + 0.5));
        const int major = (s.x_major ? s.from.x : s.from.y) + s.major_sign * i;
        const PixelIndex p = s.x_major ? PixelIndex{major, rounded} : PixelIndex{rounded, major};
        std::string title;
        if (trace != nullptr) {
            title = std::string(major_name(s)) + " = " + std::to_string(major) + ": " +
                    minor_name(s) + " = " + format_number(minor) + ", rounds to " +
                    std::to_string(rounded);
        }
        emit(out, trace, p, 4, std::move(title), {{minor_name(s), format_number(minor)}});
        minor += slope;
    }
    return out;
}

LineResult bresenham_line(Point2 a, Point2 b, int width, int height, MinorTie tie, Trace* trace) {
    const LineSetup s = setup_line(a, b);
    begin_trace(trace, "Bresenham line",
                {"round both endpoints to pixels; the axis of the larger extent is the major one",
                 "nabla = 2 d(minor) - d(major); plot the first endpoint",
                 "for each step along the major axis:",
                 ("    if nabla > 0 (or = 0 and ties step): step the minor axis, nabla += 2 "
                  "d(minor) - 2 d(major)"),
                 "    else: keep the minor coordinate, nabla += 2 d(minor)", "    plot the pixel"},
                a, b, s);
    LineResult out{{}, Raster(width, height)};
    const bool step_on_tie = tie_takes_step(tie, s.minor_sign);
    // nabla_i = 2*b*i - 2*a*k - a: twice the major length times (exact minor offset at step i
    // minus the current offset k minus 1/2). |nabla| <= 3 * 2^31 fits in int64.
    const std::int64_t two_b = 2 * std::int64_t{s.minor_length};
    const std::int64_t two_a = 2 * std::int64_t{s.major_length};
    std::int64_t nabla = two_b - s.major_length;
    PixelIndex p = s.from;
    emit(out, trace, p, 2, coordinate_title(s, p) + ": the first endpoint",
         {{"nabla", std::to_string(nabla)}});
    const int major_step = s.major_sign;
    const int minor_step = s.minor_sign;
    for (int i = 1; i <= s.major_length; ++i) {
        const bool step = nabla > 0 || (nabla == 0 && step_on_tie);
        const std::int64_t before = nabla;
        if (s.x_major) {
            p.x += major_step;
            if (step) p.y += minor_step;
        } else {
            p.y += major_step;
            if (step) p.x += minor_step;
        }
        nabla += step ? two_b - two_a : two_b;
        std::string title;
        if (trace != nullptr) {
            const char* relation = before > 0 ? " > 0" : (before == 0 ? " = 0 (a tie)" : " < 0");
            title = coordinate_title(s, p) + ": nabla = " + std::to_string(before) + relation +
                    (step ? ", step " : ", keep ") + minor_name(s) + " = " +
                    std::to_string(minor_of(s, p));
        }
        emit(out, trace, p, step ? 4 : 5, std::move(title),
             {{"nabla", std::to_string(before)}, {"next nabla", std::to_string(nabla)}});
    }
    return out;
}

LineResult midpoint_line(Point2 a, Point2 b, int width, int height, MinorTie tie, Trace* trace) {
    const LineSetup s = setup_line(a, b);
    begin_trace(trace, "midpoint line",
                {("round both endpoints to pixels; reflect the line into the first octant (u "
                  "major, v minor)"),
                 "d = 2 F(1, 1/2) = 2 dv - du; plot the first endpoint", "while u < du:",
                 "    if d > 0 (or = 0 and ties choose NE): v = v + 1 (NE), d += 2 (dv - du)",
                 "    else: (E) d += 2 dv", "    u = u + 1; plot (u, v)"},
                a, b, s);
    LineResult out{{}, Raster(width, height)};
    const bool step_on_tie = tie_takes_step(tie, s.minor_sign);
    // In the reflected frame (u along the major axis, v along the minor, both increasing) the
    // line runs from (0, 0) to (du, dv) with 0 <= dv <= du. F(u, v) = dv*u - du*v is positive
    // below the line; d = 2 F(u + 1, v + 1/2) decides between E (v stays) and NE (v + 1).
    const std::int64_t du = s.major_length;
    const std::int64_t dv = s.minor_length;
    std::int64_t d = 2 * dv - du;
    const std::int64_t increment_e = 2 * dv;
    const std::int64_t increment_ne = 2 * (dv - du);
    int u = 0;
    int v = 0;
    emit(out, trace, at_offsets(s, u, v), 2,
         coordinate_title(s, at_offsets(s, u, v)) + ": the first endpoint",
         {{"d", std::to_string(d)}});
    while (u < s.major_length) {
        const bool north_east = d > 0 || (d == 0 && step_on_tie);
        const std::int64_t before = d;
        ++u;
        if (north_east) {
            ++v;
            d += increment_ne;
        } else {
            d += increment_e;
        }
        const PixelIndex p = at_offsets(s, u, v);
        std::string title;
        if (trace != nullptr) {
            const char* relation = before > 0 ? " > 0: M below the line"
                                              : (before == 0 ? " = 0: M on the line (a tie)"
                                                             : " < 0: M above the line");
            title = coordinate_title(s, p) + ": d = 2F(M) = " + std::to_string(before) + relation +
                    (north_east ? ", choose NE" : ", choose E");
        }
        emit(out, trace, p, north_east ? 4 : 5, std::move(title),
             {{"d", std::to_string(before)},
              {"M (reflected)",
               "(" + std::to_string(u) + ", " + std::to_string(v - (north_east ? 1 : 0)) + ".5)"}});
    }
    return out;
}

}  // namespace refraster::textbook
