#include "refraster/textbook/wu_line.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "refraster/assert.hpp"

namespace refraster::textbook {

WuResult wu_line(Point2 a, Point2 b, int width, int height, Trace* trace) {
    REFRASTER_ASSERT(std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(b.x) &&
                         std::isfinite(b.y) && std::fabs(a.x) < 1e9 && std::fabs(a.y) < 1e9 &&
                         std::fabs(b.x) < 1e9 && std::fabs(b.y) < 1e9,
                     "line endpoints within int range");
    WuResult out{{}, Raster(width, height)};
    if (trace != nullptr) {
        trace->algorithm = "Wu antialiased line";
        set_pseudo_code(trace,
                        {"swap x and y if the line is steep; order the endpoints; gradient = dv "
                         "/ du",
                         "for each column c from the first endpoint's to the last's:",
                         "    minor = the line's height at the column's centre; frac = its "
                         "fraction",
                         "    the pixel below gets (1 - frac) x the column's length, the one "
                         "above frac x it"});
        trace->input.push_back({a.x, a.y, b.x, b.y, "line"});
        begin_part(trace, "segment");
    }
    // The centre lattice: pixel centres at the integers.
    double u0 = a.x - 0.5;
    double v0 = a.y - 0.5;
    double u1 = b.x - 0.5;
    double v1 = b.y - 0.5;
    const bool steep = std::fabs(v1 - v0) > std::fabs(u1 - u0);
    if (steep) {
        std::swap(u0, v0);
        std::swap(u1, v1);
    }
    if (u0 > u1) {
        std::swap(u0, u1);
        std::swap(v0, v1);
    }
    const double du = u1 - u0;
    const double dv = v1 - v0;
    const double gradient = du == 0.0 ? 0.0 : dv / du;
    const int first = static_cast<int>(std::floor(u0 + 0.5));
    const int last = static_cast<int>(std::floor(u1 + 0.5));
    if (trace != nullptr) {
        Step& step = add_step(
            *trace, std::string(steep ? "steep: y is the major axis" : "x is the major axis") +
                        ", gradient " + format_number(gradient));
        step.line = 1;
        step.state.push_back({"gradient", format_number(gradient)});
        step.state.push_back({"first column", std::to_string(first)});
        step.state.push_back({"last column", std::to_string(last)});
    }
    double minor = v0 + gradient * (first - u0);
    for (int c = first; c <= last; ++c) {
        double length = 1.0;
        if (first == last) {
            length = du;
        } else if (c == first) {
            length = (c + 0.5) - u0;
        } else if (c == last) {
            length = u1 - (c - 0.5);
        }
        const double row_floor = std::floor(minor);
        const double frac = minor - row_floor;
        const int row = static_cast<int>(row_floor);
        WuColumn col;
        col.length = length;
        col.minor = minor;
        col.weight_low = (1.0 - frac) * length;
        col.weight_high = frac * length;
        if (steep) {
            col.x_low = row;
            col.y_low = c;
            col.x_high = row + 1;
            col.y_high = c;
        } else {
            col.x_low = c;
            col.y_low = row;
            col.x_high = c;
            col.y_high = row + 1;
        }
        out.raster.add(col.x_low, col.y_low, col.weight_low);
        out.raster.add(col.x_high, col.y_high, col.weight_high);
        if (trace != nullptr) {
            Step& step =
                add_step(*trace, std::string(steep ? "y = " : "x = ") + std::to_string(c) + ": " +
                                     (steep ? "x" : "y") + " = " + format_number(minor + 0.5) +
                                     " at the centre, " + format_pixel(col.x_low, col.y_low) +
                                     " gets " + format_number(col.weight_low) + ", " +
                                     format_pixel(col.x_high, col.y_high) + " gets " +
                                     format_number(col.weight_high));
            step.line = 4;
            step.state.push_back({"column length", format_number(length)});
            step.state.push_back({"frac", format_number(frac)});
            step.pixels.push_back({col.x_low, col.y_low, col.weight_low});
            step.pixels.push_back({col.x_high, col.y_high, col.weight_high});
        }
        out.columns.push_back(col);
        minor += gradient;
    }
    return out;
}

}  // namespace refraster::textbook
