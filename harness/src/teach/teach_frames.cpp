// teach_frames.cpp: a teaching run's steps as SVG and raster frames (teach_frames.hpp), drawn
// with the teaching page's colours and sizes (teach_page.cpp's drawBase: the grid's two
// weights, the input's role colours, the step's outlines and construction).
#include "harness/teach_frames.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "harness/markup.hpp"
#include "refraster/assert.hpp"

namespace harness {

namespace {

namespace tb = refraster::textbook;

struct Rgba {
    std::uint8_t r = 0, g = 0, b = 0, a = 255;
};

// The page's colours (teach_page.cpp): input roles in order of first appearance, the step's
// construction, its pixels' outlines.
constexpr std::array<const char*, 6> kRoleColours = {"#00e676", "#40c4ff", "#eeff41",
                                                     "#ea80fc", "#ffab40", "#a7ffeb"};
constexpr const char* kOverlayColour = "#ff4081";
constexpr const char* kLitOutline = "#ffd600";
constexpr const char* kRejectedOutline = "#ff1744";

Rgba from_hex(const char* hex) {
    unsigned r = 0, g = 0, b = 0;
    std::sscanf(hex, "#%02x%02x%02x", &r, &g, &b);
    return {static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g),
            static_cast<std::uint8_t>(b), 255};
}

// A pixel's colour in step mode: undecided dark, rejected dark red, decided as bright as its
// weight.
Rgba cell_colour(double w) {
    if (w < 0.0) return {24, 24, 24, 255};
    if (w == 0.0) return {112, 30, 30, 255};
    const auto v = static_cast<std::uint8_t>(std::lround(24.0 + 231.0 * std::min(1.0, w)));
    return {v, v, v, 255};
}

std::string hex(Rgba c) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
    return buf;
}

// Two decimals at most, no trailing zeros: SVG coordinates.
std::string num(double v) {
    if (!std::isfinite(v)) return "0";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    std::string s = buf;
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
    return s == "-0" ? "0" : s;
}

// Pixels of `fb` (row 0 at the bottom) are unit squares; (X + 0.5, Y + 0.5) is a centre.
void blend(refraster::Framebuffer& fb, int x, int y, Rgba c) {
    if (x < 0 || y < 0 || x >= static_cast<int>(fb.width) || y >= static_cast<int>(fb.height))
        return;
    const std::size_t i =
        4 * fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    const double a = c.a / 255.0;
    const std::array<std::uint8_t, 3> src = {c.r, c.g, c.b};
    for (std::size_t k = 0; k < 3; ++k) {
        const double v = src[k] * a + fb.color8[i + k] * (1.0 - a);
        fb.color8[i + k] = static_cast<std::uint8_t>(std::lround(v));
    }
    // Colours over a transparent layer stay premultiplied by its alpha (the underlay).
    const double da = fb.color8[i + 3] / 255.0;
    fb.color8[i + 3] = static_cast<std::uint8_t>(std::lround(255.0 * (a + da * (1.0 - a))));
}

// A line of `width` pixels from (x0, y0) to (x1, y1), in `fb`'s pixel units: every pixel whose
// centre lies within width / 2 of the segment.
void draw_line(refraster::Framebuffer& fb, double x0, double y0, double x1, double y1, double width,
               Rgba c) {
    const double h = std::max(0.5, width / 2.0);
    const int xa = static_cast<int>(std::floor(std::min(x0, x1) - h));
    const int xb = static_cast<int>(std::ceil(std::max(x0, x1) + h));
    const int ya = static_cast<int>(std::floor(std::min(y0, y1) - h));
    const int yb = static_cast<int>(std::ceil(std::max(y0, y1) + h));
    const double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
    for (int y = std::max(ya, 0); y <= std::min(yb, static_cast<int>(fb.height) - 1); ++y) {
        for (int x = std::max(xa, 0); x <= std::min(xb, static_cast<int>(fb.width) - 1); ++x) {
            const double px = x + 0.5 - x0, py = y + 0.5 - y0;
            const double t = len2 > 0.0 ? std::clamp((px * dx + py * dy) / len2, 0.0, 1.0) : 0.0;
            if (std::hypot(px - t * dx, py - t * dy) <= h) blend(fb, x, y, c);
        }
    }
}

// The outline of pixel (x, y) at `zoom`: a square inset by `inset`, `width` pixels wide.
void draw_outline(refraster::Framebuffer& fb, int x, int y, int zoom, double inset, double width,
                  Rgba c) {
    const double x0 = x * zoom + inset, x1 = (x + 1) * zoom - inset;
    const double y0 = y * zoom + inset, y1 = (y + 1) * zoom - inset;
    draw_line(fb, x0, y0, x1, y0, width, c);
    draw_line(fb, x1, y0, x1, y1, width, c);
    draw_line(fb, x1, y1, x0, y1, width, c);
    draw_line(fb, x0, y1, x0, y0, width, c);
}

std::size_t role_index(const std::vector<std::string>& roles, const std::string& role) {
    const auto it = std::find(roles.begin(), roles.end(), role);
    return it == roles.end() ? 0 : static_cast<std::size_t>(it - roles.begin());
}

// The step's title cut into lines of at most `chars` characters, at spaces where it can be.
std::vector<std::string> wrap(const std::string& text, std::size_t chars) {
    std::vector<std::string> lines;
    std::string rest = text;
    while (rest.size() > chars) {
        std::size_t cut = rest.rfind(' ', chars);
        if (cut == std::string::npos || cut == 0) cut = chars;
        lines.push_back(rest.substr(0, cut));
        rest = rest.substr(cut == chars ? cut : cut + 1);
    }
    lines.push_back(rest);
    return lines;
}

}  // namespace

TeachFrames::TeachFrames(const TeachResult& r, int zoom)
    : r_(r),
      steps_(r.steps),
      zoom_(std::clamp(zoom, 1, 64)),
      state_(static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height), -1.0),
      underlay_(static_cast<std::uint32_t>(r.width * zoom_),
                static_cast<std::uint32_t>(r.height * zoom_), refraster::ColorFormat::Rgba8,
                refraster::DepthFormat::None, 1) {
    for (const tb::Segment& s : r.input)
        if (std::find(roles_.begin(), roles_.end(), s.role) == roles_.end())
            roles_.push_back(s.role);
    std::fill(underlay_.color8.begin(), underlay_.color8.end(), std::uint8_t{0});
    const int w = r.width, h = r.height, z = zoom_;
    if (z >= 4) {
        // The grid: every pixel faint, every eighth brighter (the page's two weights).
        for (const auto& [every, colour] :
             {std::pair{1, Rgba{128, 128, 128, 115}}, std::pair{8, Rgba{170, 170, 170, 230}}}) {
            for (int i = 0; i <= w; i += every) {
                const int x = std::min(i * z, w * z - 1);
                for (int y = 0; y < h * z; ++y) blend(underlay_, x, y, colour);
            }
            for (int j = 0; j <= h; j += every) {
                const int y = std::min(j * z, h * z - 1);
                for (int x = 0; x < w * z; ++x) blend(underlay_, x, y, colour);
            }
        }
    }
    for (const tb::Segment& s : r.input)
        draw_line(underlay_, s.x0 * z, s.y0 * z, s.x1 * z, s.y1 * z, 1.5,
                  from_hex(kRoleColours[role_index(roles_, s.role) % kRoleColours.size()]));
}

void TeachFrames::seek(std::size_t k) {
    REFRASTER_ASSERT(k < steps_.size(), "a frame of a recorded step");
    if (!started_ || k < at_) {
        std::fill(state_.begin(), state_.end(), -1.0);
        at_ = 0;
        started_ = false;
    }
    const auto apply = [&](std::size_t s) {
        for (const tb::PixelMark& p : steps_[s].pixels) {
            if (p.x < 0 || p.y < 0 || p.x >= r_.width || p.y >= r_.height) continue;
            state_[static_cast<std::size_t>(p.y) * static_cast<std::size_t>(r_.width) +
                   static_cast<std::size_t>(p.x)] = p.weight;
        }
    };
    if (!started_) {
        apply(0);
        started_ = true;
    }
    while (at_ < k) apply(++at_);
}

refraster::Framebuffer TeachFrames::image() const {
    refraster::Framebuffer fb = underlay_;
    const int w = r_.width, h = r_.height, z = zoom_;
    // The cells under the underlay (premultiplied): out = underlay + cell (1 - its alpha).
    for (int y = 0; y < h * z; ++y) {
        for (int x = 0; x < w * z; ++x) {
            const Rgba cell =
                cell_colour(state_[static_cast<std::size_t>(y / z) * static_cast<std::size_t>(w) +
                                   static_cast<std::size_t>(x / z)]);
            const std::size_t i =
                4 * fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
            const double keep = 1.0 - fb.color8[i + 3] / 255.0;
            const std::array<std::uint8_t, 3> c = {cell.r, cell.g, cell.b};
            for (std::size_t k = 0; k < 3; ++k)
                fb.color8[i + k] = static_cast<std::uint8_t>(
                    std::min(255L, std::lround(fb.color8[i + k] + c[k] * keep)));
            fb.color8[i + 3] = 255;
        }
    }
    if (steps_.empty()) return fb;
    const tb::Step& s = steps_[at_];
    const double inset = z >= 6 ? 1.5 : 0.5, width = z >= 6 ? 2.0 : 1.0;
    for (const tb::PixelMark& p : s.pixels) {
        if (p.x < 0 || p.y < 0 || p.x >= w || p.y >= h) continue;
        draw_outline(fb, p.x, p.y, z, inset, width,
                     from_hex(p.weight > 0.0 ? kLitOutline : kRejectedOutline));
    }
    for (const tb::Segment& o : s.overlay)
        draw_line(fb, o.x0 * z, o.y0 * z, o.x1 * z, o.y1 * z, 2.5, from_hex(kOverlayColour));
    return fb;
}

std::string TeachFrames::svg() const {
    const int w = r_.width, h = r_.height, z = zoom_;
    const double pw = w * z, ph = h * z;
    const double width = std::max(pw, 480.0);
    const std::size_t chars = static_cast<std::size_t>(width / (13.0 * 0.56));
    std::vector<std::string> caption;
    if (!steps_.empty()) {
        caption = wrap("Step " + std::to_string(at_ + 1) + " of " + std::to_string(steps_.size()) +
                           ": " + steps_[at_].title,
                       chars);
        // The part, unless the title already starts with it ("segment 3: ...").
        const std::string& group = steps_[at_].group;
        if (!group.empty() && steps_[at_].title.rfind(group, 0) != 0)
            caption.insert(caption.begin(), group);
    }
    const double height = ph + 10.0 + 17.0 * static_cast<double>(caption.size()) + 6.0;
    const auto sy = [&](double y) { return ph - y * z; };  // window y (up) to SVG y (down)
    std::string s = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    s += markup::svg_open({{"version", "1.1"},
                           {"width", num(width)},
                           {"height", num(height)},
                           {"viewBox", "0 0 " + num(width) + " " + num(height)},
                           {"font-family", "sans-serif"}}) +
         "\n";
    s += "<title>" + markup::escape(r_.title) + "</title>\n";
    s += "<rect width=\"" + num(width) + "\" height=\"" + num(height) + "\" fill=\"#ffffff\"/>\n";
    // The cells, a run of one colour along a row as one rectangle.
    s += "<g shape-rendering=\"crispEdges\">\n";
    s += "<rect width=\"" + num(pw) + "\" height=\"" + num(ph) + "\" fill=\"" +
         hex(cell_colour(-1.0)) + "\"/>\n";
    for (int y = 0; y < h; ++y) {
        int x = 0;
        while (x < w) {
            const double v = state_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                    static_cast<std::size_t>(x)];
            int end = x + 1;
            while (end < w && state_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                     static_cast<std::size_t>(end)] == v)
                ++end;
            if (v >= 0.0)
                s += "<rect x=\"" + num(x * z) + "\" y=\"" + num(sy(y + 1)) + "\" width=\"" +
                     num((end - x) * z) + "\" height=\"" + num(z) + "\" fill=\"" +
                     hex(cell_colour(v)) + "\"/>\n";
            x = end;
        }
    }
    s += "</g>\n";
    if (z >= 4) {
        for (const auto& [every, style] :
             {std::pair{1, "stroke=\"#808080\" stroke-opacity=\"0.45\""},
              std::pair{8, "stroke=\"#aaaaaa\" stroke-opacity=\"0.9\""}}) {
            std::string d;
            for (int i = 0; i <= w; i += every) d += "M" + num(i * z) + " 0V" + num(ph);
            for (int j = 0; j <= h; j += every) d += "M0 " + num(sy(j)) + "H" + num(pw);
            s += "<path d=\"" + d + "\" " + style + " stroke-width=\"1\" fill=\"none\"/>\n";
        }
    }
    for (const tb::Segment& g : r_.input)
        s += "<line x1=\"" + num(g.x0 * z) + "\" y1=\"" + num(sy(g.y0)) + "\" x2=\"" +
             num(g.x1 * z) + "\" y2=\"" + num(sy(g.y1)) + "\" stroke=\"" +
             kRoleColours[role_index(roles_, g.role) % kRoleColours.size()] +
             "\" stroke-width=\"1.5\"/>\n";
    if (!steps_.empty()) {
        const tb::Step& st = steps_[at_];
        const double inset = z >= 6 ? 1.5 : 0.5, lw = z >= 6 ? 2.0 : 1.0;
        for (const tb::PixelMark& p : st.pixels) {
            if (p.x < 0 || p.y < 0 || p.x >= w || p.y >= h) continue;
            s += "<rect x=\"" + num(p.x * z + inset) + "\" y=\"" + num(sy(p.y + 1) + inset) +
                 "\" width=\"" + num(z - 2 * inset) + "\" height=\"" + num(z - 2 * inset) +
                 "\" fill=\"none\" stroke=\"" + (p.weight > 0.0 ? kLitOutline : kRejectedOutline) +
                 "\" stroke-width=\"" + num(lw) + "\"" +
                 (p.weight > 0.0 ? "" : " stroke-dasharray=\"3,2\"") + "/>\n";
        }
        for (const tb::Segment& o : st.overlay)
            s += "<line x1=\"" + num(o.x0 * z) + "\" y1=\"" + num(sy(o.y0)) + "\" x2=\"" +
                 num(o.x1 * z) + "\" y2=\"" + num(sy(o.y1)) + "\" stroke=\"" + kOverlayColour +
                 "\" stroke-width=\"2.5\"/>\n";
    }
    for (std::size_t i = 0; i < caption.size(); ++i)
        s += "<text x=\"4\" y=\"" + num(ph + 10.0 + 13.0 + 17.0 * static_cast<double>(i)) +
             "\" font-size=\"13\" fill=\"#222222\"" +
             (i == 0 && caption[0].rfind("Step ", 0) != 0 ? " font-weight=\"bold\"" : "") + ">" +
             markup::escape(caption[i]) + "</text>\n";
    s += markup::svg_close() + "\n";
    return s;
}

}  // namespace harness
