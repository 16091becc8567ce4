#include "refraster/textbook/circle.hpp"

#include <array>
#include <string>

#include "refraster/assert.hpp"

namespace refraster::textbook {

namespace {

std::array<PixelIndex, 8> mirrors(PixelIndex c, int x, int y) {
    return {{{c.x + x, c.y + y},
             {c.x + y, c.y + x},
             {c.x + y, c.y - x},
             {c.x + x, c.y - y},
             {c.x - x, c.y - y},
             {c.x - y, c.y - x},
             {c.x - y, c.y + x},
             {c.x - x, c.y + y}}};
}

}  // namespace

CircleResult midpoint_circle(PixelIndex centre, int radius, int width, int height, Trace* trace) {
    REFRASTER_ASSERT(radius >= 0 && radius < (1 << 28), "a non-negative radius below 2^28");
    CircleResult out{{}, {}, Raster(width, height)};
    if (trace != nullptr) {
        trace->algorithm = "midpoint circle";
        set_pseudo_code(
            trace, {"x = 0, y = R, d = 1 - R; plot (0, R) and its seven mirrors", "while y > x:",
                    ("    if d >= 0: M is outside, choose SE: d += 2 (x - y) + 5, y = "
                     "y - 1"),
                    "    else: M is inside, choose E: d += 2 x + 3",
                    "    x = x + 1; plot (x, y) and its seven mirrors"});
        trace->input.push_back(
            {centre.x + 0.5, centre.y + 0.5, centre.x + 0.5 + radius, centre.y + 0.5, "circle"});
        begin_part(trace, "circle");
    }
    const auto plot = [&](int x, int y, int line, std::string title,
                          std::vector<std::pair<std::string, std::string>> state) {
        out.octant.push_back({x, y});
        const auto points = mirrors(centre, x, y);
        for (const PixelIndex& p : points) out.raster.set(p.x, p.y, 1.0);
        if (trace == nullptr) return;
        Step& step = add_step(*trace, std::move(title));
        step.line = line;
        step.state = std::move(state);
        for (const PixelIndex& p : points) step.pixels.push_back({p.x, p.y, 1.0});
    };
    int x = 0;
    int y = radius;
    long long d = 1 - static_cast<long long>(radius);
    plot(x, y, 1, "x = 0: start at (0, R)", {{"d", std::to_string(d)}});
    while (y > x) {
        const long long before = d;
        out.decisions.push_back(d);
        const bool south_east = d >= 0;
        if (south_east) {
            d += 2 * (static_cast<long long>(x) - y) + 5;
            --y;
        } else {
            d += 2 * static_cast<long long>(x) + 3;
        }
        ++x;
        std::string title;
        if (trace != nullptr) {
            title = "x = " + std::to_string(x) + ": d = " + std::to_string(before) +
                    (south_east ? " >= 0, F(M) > 0: M outside, choose SE, y = "
                                : " < 0, F(M) < 0: M inside, choose E, y = ") +
                    std::to_string(y);
        }
        plot(x, y, south_east ? 3 : 4, std::move(title),
             {{"d", std::to_string(before)},
              {"M", "(" + std::to_string(x) + ", " + std::to_string(y + (south_east ? 1 : 0)) +
                        " - 1/2)"},
              {"next d", std::to_string(d)}});
    }
    return out;
}

}  // namespace refraster::textbook
