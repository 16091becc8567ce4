// explain_draw.cpp: an explanation drawn as SVG (explanation_svg).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "explain_shared.hpp"
#include "harness/explain.hpp"
#include "harness/markup.hpp"
#include "harness/profile_io.hpp"
#include "refraster/renderer.hpp"

namespace harness {

using explain_detail::color_at;
using explain_detail::color_text;
using explain_detail::kSampleOffsets;
using explain_detail::where;

namespace {

constexpr int kTexelCell = 40;  // screen pixels per texel
constexpr int kTexelPanelWidth = 8 * kTexelCell + 320;
constexpr int kTexelPanelHeight = 8 * kTexelCell + 60;

// The teaching view of a textured fragment: the level's texels (rows bottom to top, as the
// texture is addressed), the sampled point, the texels the filter read with their weights,
// and the pixel's footprint (the quad's derivatives as a parallelogram in texels).
std::string texel_panel_svg(const Explanation::TexelWindow& w, int top) {
    std::ostringstream s;
    const auto& t = w.sample;
    const int C = kTexelCell;
    const int rows = w.rows;
    const auto tx = [&](double u) { return 10 + (u - w.x0) * C; };  // texel units to screen
    const auto ty = [&](double v) { return top + 30 + (w.y0 + rows - v) * C; };
    s << "<text x=\"4\" y=\"" << top + 16
      << "\" font-family=\"sans-serif\" font-size=\"12\">texels of level " << t.level0 << " ("
      << w.level_width << "x" << w.level_height << "), " << (t.linear ? "bilinear" : "nearest")
      << ", " << (t.aos ? "8-bit path" : "float path") << "</text>\n";
    for (int y = 0; y < rows; ++y) {
        for (int x = 0; x < w.columns; ++x) {
            const auto& c = w.texels[static_cast<std::size_t>(y * w.columns + x)];
            char fill[8];
            std::snprintf(fill, sizeof fill, "#%02x%02x%02x", c[0], c[1], c[2]);
            s << "<rect x=\"" << tx(w.x0 + x) << "\" y=\"" << ty(w.y0 + y + 1) << "\" width=\"" << C
              << "\" height=\"" << C << "\" fill=\"" << fill
              << "\" stroke=\"#888\" stroke-width=\"1\"><title>texel (" << w.x0 + x << ", "
              << w.y0 + y << "): " << int{c[0]} << "," << int{c[1]} << "," << int{c[2]} << ","
              << int{c[3]} << "</title></rect>\n";
        }
    }
    // The texels read (level 0 of the sample), outlined.
    const auto& r = t.texels[0];
    const auto outline = [&](int x, int y, const char* colour) {
        if (x < w.x0 || y < w.y0 || x >= w.x0 + w.columns || y >= w.y0 + rows) return;
        s << "<rect x=\"" << tx(x) + 2 << "\" y=\"" << ty(y + 1) + 2 << "\" width=\"" << C - 4
          << "\" height=\"" << C - 4 << "\" fill=\"none\" stroke=\"" << colour
          << "\" stroke-width=\"3\"/>\n";
    };
    outline(r[0], r[2], "#ff00ff");
    if (t.linear) {
        outline(r[1], r[2], "#ff00ff");
        outline(r[0], r[3], "#ff00ff");
        outline(r[1], r[3], "#ff00ff");
    }
    // The sampled point and the footprint: the quad's steps along x and y, in texels of this
    // level (the derivatives are in base-level texels).
    const double scale = std::ldexp(1.0, -static_cast<int>(t.level0));
    const double u = static_cast<double>(t.coord[0]) * w.level_width;
    const double v = static_cast<double>(t.coord[1]) * w.level_height;
    const double ax = double{t.rho_terms[0]} * scale, ay = double{t.rho_terms[1]} * scale;
    const double bx = double{t.rho_terms[2]} * scale, by = double{t.rho_terms[3]} * scale;
    s << "<polygon fill=\"#00c85333\" stroke=\"#00c853\" stroke-width=\"2\" points=\"" << tx(u)
      << "," << ty(v) << " " << tx(u + ax) << "," << ty(v + ay) << " " << tx(u + ax + bx) << ","
      << ty(v + ay + by) << " " << tx(u + bx) << "," << ty(v + by)
      << "\"><title>the pixel's footprint: one pixel step along x and along y</title></polygon>\n";
    s << "<circle cx=\"" << tx(u) << "\" cy=\"" << ty(v)
      << "\" r=\"4\" fill=\"#ff00ff\"><title>sampled at (" << u << ", " << v
      << ") texels</title></circle>\n";
    // The numbers beside the grid.
    std::ostringstream lines;
    lines.precision(6);
    lines << "s, t = " << t.coord[0] << ", " << t.coord[1] << "|rho^2 = " << t.rho2
          << (t.minified ? " (minified)" : " (magnified)") << "|levels " << t.level0;
    if (t.level1 != t.level0) lines << " and " << t.level1 << ", weight " << t.level_weight;
    lines << "|texels x " << r[0] << (t.linear ? ", " + std::to_string(r[1]) : "") << " y " << r[2]
          << (t.linear ? ", " + std::to_string(r[3]) : "");
    if (t.linear) {
        lines << "|weights " << t.weights[0][0] << (t.aos ? "/256" : "") << ", " << t.weights[0][1]
              << (t.aos ? "/256" : "");
    }
    lines << "|colour " << t.color[0] << ", " << t.color[1] << ", " << t.color[2] << ", "
          << t.color[3];
    std::string text = lines.str();
    int line = 0;
    std::size_t start = 0;
    while (start <= text.size()) {
        const auto bar = text.find('|', start);
        const std::string part =
            text.substr(start, bar == std::string::npos ? std::string::npos : bar - start);
        s << "<text x=\"" << 20 + 8 * C << "\" y=\"" << top + 50 + 18 * line
          << "\" font-family=\"sans-serif\" font-size=\"12\">" << part << "</text>\n";
        ++line;
        if (bar == std::string::npos) break;
        start = bar + 1;
    }
    return s.str();
}

}  // namespace

// The explain view (explanation_svg): the pixel's neighbourhood twice, side by side, on the
// same pixel grid: left the primitives as setup receives them (unsnapped window coordinates),
// right as the edge functions see them (snapped to the 1/2^bits grid), each edge with its
// direction and the side its inside lies on. Cells outside the target are hatched; geometry
// is clipped to each panel. A legend says what every mark means.
namespace svg_view {
constexpr int kCell = 40;         // screen pixels per framebuffer pixel
constexpr int kAxis = 34;         // room for the y labels left of a panel
constexpr int kTitle = 30;        // a panel's title above it
constexpr int kTicks = 22;        // the x labels below a panel
constexpr int kGap = 28;          // between the panels
constexpr int kLegendRow = 22;    // one legend entry, one row
constexpr int kCaptionLine = 16;  // a line of the wrapped verdict
constexpr int kSubpixel = 8;      // grid lines a pixel: 1/8 pixel (32 of llvmpipe's 1/256)
}  // namespace svg_view

std::string explanation_svg(const Explanation& e, int radius) {
    using namespace svg_view;
    const auto& fb = e.reference_image;
    const int cx = e.trace.x;
    const int cy = e.trace.y;
    const int S = kCell;
    const int n = 2 * radius + 1;
    const int x0 = cx - radius;
    const int y0 = cy - radius;
    const int PW = n * S;
    const int panel_w = kAxis + PW;
    const int W0 = 2 * panel_w + kGap + 8;
    const int pictures_h = kTitle + PW + kTicks;
    const bool multisampled = !e.reference_samples.empty();
    // The captions under the pictures, wrapped at spaces to the picture's width (about 6.5
    // screen pixels a character at 12 px): both sides' values at the pixel, then the verdict.
    const bool is8 = fb.color_format == refraster::ColorFormat::Rgba8;
    std::string sides = "pixel (" + std::to_string(cx) + ", " + std::to_string(cy) +
                        "): reference " + color_text(e.reference_color, is8);
    if (e.reference_depth) sides += " depth " + std::to_string(*e.reference_depth);
    if (e.backend) {
        sides += "; backend " + color_text(e.backend_color, is8);
        if (e.backend_depth) sides += " depth " + std::to_string(*e.backend_depth);
    }
    const std::size_t per_line = static_cast<std::size_t>((W0 - 40) / 7);
    const auto wrap = [&](const std::string& text) {
        std::vector<std::string> lines;
        std::string line;
        std::size_t at = 0;
        while (at < text.size()) {
            auto end = text.find(' ', at);
            if (end == std::string::npos) end = text.size();
            const std::string word = text.substr(at, end - at);
            if (!line.empty() && line.size() + 1 + word.size() > per_line) {
                lines.push_back(line);
                line.clear();
            }
            line += (line.empty() ? "" : " ") + word;
            at = end + 1;
        }
        if (!line.empty()) lines.push_back(line);
        return lines;
    };
    std::vector<std::string> captions = wrap(sides);
    for (auto& l : wrap("verdict: " + e.verdict)) captions.push_back(std::move(l));
    const int caption_top = pictures_h + 18;
    const int legend_top = caption_top + static_cast<int>(captions.size()) * kCaptionLine + 4;
    constexpr int kLegendEntries = 12;
    const int H0 = legend_top + 14 + kLegendEntries * kLegendRow;
    std::ostringstream s;
    const std::string width_text = std::to_string(W0);
    const std::string height_text = std::to_string(H0);
    s << markup::svg_open({{"width", width_text},
                           {"height", height_text},
                           {"viewBox", "0 0 " + width_text + " " + height_text},
                           {"font-family", "system-ui,sans-serif"},
                           {"font-size", "12"}})
      << "\n";
    s << "<title>pixel (" << cx << ", " << cy << "): " << markup::escape(e.verdict) << "</title>\n";
    s << "<defs><pattern id=\"outside\" width=\"8\" height=\"8\" patternUnits=\"userSpaceOnUse\" "
         "patternTransform=\"rotate(45)\"><rect width=\"8\" height=\"8\" fill=\"#d7d7d7\"/>"
         "<line x1=\"0\" y1=\"0\" x2=\"0\" y2=\"8\" stroke=\"#9e9e9e\" stroke-width=\"3\"/>"
         "</pattern><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"5\" refY=\"5\" "
         "markerWidth=\"7\" markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0 "
         "L10,5 L0,10 z\" fill=\"context-stroke\"/></marker></defs>\n";
    bool tie = false;
    for (const auto& p : e.trace.primitives)
        for (const auto& st : p.setups)
            for (const auto& ed : st.edges) tie = tie || ed.tie;
    // The traced point: the pixel centre, or the traced sample of a 4x target.
    double tx = cx + 0.5;
    double ty = cy + 0.5;
    if (multisampled) {
        const auto& o = kSampleOffsets[static_cast<std::size_t>(e.trace.sample)];
        tx = cx + o[0];
        ty = cy + o[1];
    }

    // A colour as an SVG fill: bytes, or floats clamped to [0, 1] and scaled.
    const auto hex = [&](const std::array<float, 4>& c) {
        int rgb[3];
        for (int k = 0; k < 3; ++k) {
            const float v = is8 ? c[static_cast<std::size_t>(k)]
                                : std::clamp(c[static_cast<std::size_t>(k)], 0.0f, 1.0f) * 255.0f;
            rgb[k] = static_cast<int>(v);
        }
        char buf[8];
        std::snprintf(buf, sizeof buf, "#%02x%02x%02x", rgb[0] & 255, rgb[1] & 255, rgb[2] & 255);
        return std::string(buf);
    };
    // The backend's image, when it drew one of the reference's size and format (a 4x target's
    // resolve).
    const refraster::Framebuffer* theirs = nullptr;
    if (e.backend && e.backend->status == RenderStatus::Ok && e.backend->image.width == fb.width &&
        e.backend->image.height == fb.height && e.backend->image.color_format == fb.color_format)
        theirs = &e.backend->image;
    const auto panel = [&](int left, bool snapped) {
        const int top = kTitle;
        const auto sx = [&](double wx) { return left + kAxis + (wx - x0) * S; };
        const auto sy = [&](double wy) { return top + (y0 + n - wy) * S; };  // y up
        const std::string clip = snapped ? "clip-snapped" : "clip-unsnapped";
        s << "<g class=\"panel\" id=\"" << (snapped ? "snapped" : "unsnapped") << "\">\n";
        s << "<text x=\"" << left + kAxis << "\" y=\"18\" font-weight=\"600\">"
          << (snapped ? "snapped: corners as the edge functions see them"
                      : "unsnapped: window coordinates into setup")
          << "</text>\n";
        s << "<clipPath id=\"" << clip << "\"><rect x=\"" << sx(x0) << "\" y=\"" << sy(y0 + n)
          << "\" width=\"" << PW << "\" height=\"" << PW << "\"/></clipPath>\n";
        // Pixels in the reference's colours; outside the target hatched.
        for (int y = y0; y < y0 + n; ++y) {
            for (int x = x0; x < x0 + n; ++x) {
                const bool inside = x >= 0 && y >= 0 && static_cast<std::uint32_t>(x) < fb.width &&
                                    static_cast<std::uint32_t>(y) < fb.height;
                std::string fill = "url(#outside)";
                if (inside) fill = hex(color_at(fb, x, y));
                s << "<rect class=\"" << (inside ? "cell" : "cell outside") << "\" x=\"" << sx(x)
                  << "\" y=\"" << sy(y + 1) << "\" width=\"" << S << "\" height=\"" << S
                  << "\" fill=\"" << fill << "\" stroke=\"#888\" stroke-width=\"1\">"
                  << "<title>pixel (" << x << ", " << y << ")"
                  << (inside ? "" : ": outside the target") << "</title></rect>\n";
                // Where the backend's pixel differs, its colour fills the cell's lower-right half.
                if (inside && theirs != nullptr) {
                    const auto mine = color_at(fb, x, y);
                    const auto other = color_at(*theirs, x, y);
                    if (!explain_detail::same_color(mine, other)) {
                        s << "<polygon class=\"backend-half\" points=\"" << sx(x + 1) << ","
                          << sy(y + 1) << " " << sx(x + 1) << "," << sy(y) << " " << sx(x) << ","
                          << sy(y) << "\" fill=\"" << hex(other)
                          << "\" stroke=\"#888\" stroke-width=\"1\"><title>pixel (" << x << ", "
                          << y << "): backend " << color_text(other, is8) << ", reference "
                          << color_text(mine, is8) << "</title></polygon>\n";
                    }
                }
            }
        }
        // The sub-pixel grid, faint, over the cells.
        s << "<g class=\"subpixel-grid\" stroke=\"#7f7f7f\" stroke-opacity=\"0.25\" "
             "stroke-width=\"0.5\">";
        for (int k = 1; k < n * kSubpixel; ++k) {
            if (k % kSubpixel == 0) continue;
            const double f = static_cast<double>(k) / kSubpixel;
            s << "<line x1=\"" << sx(x0 + f) << "\" y1=\"" << sy(y0) << "\" x2=\"" << sx(x0 + f)
              << "\" y2=\"" << sy(y0 + n) << "\"/><line x1=\"" << sx(x0) << "\" y1=\"" << sy(y0 + f)
              << "\" x2=\"" << sx(x0 + n) << "\" y2=\"" << sy(y0 + f) << "\"/>";
        }
        s << "</g>\n";
        // Sample points: pixel centres, or a 4x target's four positions.
        for (int y = y0; y < y0 + n; ++y) {
            for (int x = x0; x < x0 + n; ++x) {
                if (!multisampled) {
                    s << "<circle cx=\"" << sx(x + 0.5) << "\" cy=\"" << sy(y + 0.5)
                      << "\" r=\"2.5\" fill=\"#666\"/>\n";
                } else {
                    for (const auto& o : kSampleOffsets) {
                        s << "<circle cx=\"" << sx(x + o[0]) << "\" cy=\"" << sy(y + o[1])
                          << "\" r=\"2\" fill=\"#666\"/>\n";
                    }
                }
            }
        }
        // The traced pixel.
        s << "<rect x=\"" << sx(cx) << "\" y=\"" << sy(cy + 1) << "\" width=\"" << S
          << "\" height=\"" << S << "\" fill=\"none\" stroke=\"#ff00ff\" stroke-width=\"3\"/>\n";
        // A tie ring under the primitives, so that the edges' arrows and ticks stay visible.
        if (tie) {
            s << "<circle class=\"tie\" cx=\"" << sx(tx) << "\" cy=\"" << sy(ty)
              << "\" r=\"9\" fill=\"none\" stroke=\"#ff6d00\" stroke-width=\"3\" "
                 "stroke-opacity=\"0.8\"><title>tie: the point lies exactly on an edge</title>"
                 "</circle>\n";
        }
        // The primitives that reach the pixel, clipped to the panel. Their labels are gathered
        // and placed after them, each moved up or down a line until it overlaps none before it.
        struct Label {
            double x, y;  // screen: the text's middle and baseline
            std::string text;
            const char* colour;
            const char* cls;
            int size;
        };
        std::vector<Label> labels;
        s << "<g clip-path=\"url(#" << clip << ")\">\n";
        for (const auto& p : e.trace.primitives) {
            for (const auto& st : p.setups) {
                const char* colour = p.covered ? "#00a844" : "#2962ff";
                std::vector<std::array<double, 2>> pts;
                if (snapped) {
                    if (st.x.size() < 2) continue;
                    const double one = static_cast<double>(1 << st.subpixel_bits);
                    // The snapped grid's origin: the pixel centre, or its corner when
                    // multisampling.
                    const double origin = p.multisample ? 0.0 : 0.5;
                    for (std::size_t i = 0; i < st.x.size(); ++i)
                        pts.push_back({st.x[i] / one + origin, st.y[i] / one + origin});
                } else {
                    for (const auto& w : st.window) pts.push_back({w[0], w[1]});
                }
                if (pts.empty()) continue;
                if (pts.size() == 1) {
                    // A point: its centre.
                    s << "<circle cx=\"" << sx(pts[0][0]) << "\" cy=\"" << sy(pts[0][1])
                      << "\" r=\"4\" fill=\"" << colour << "\"><title>" << where(p) << ": centre ("
                      << pts[0][0] << ", " << pts[0][1] << ")</title></circle>\n";
                    continue;
                }
                s << "<polygon class=\"" << (snapped ? "snapped" : "unsnapped")
                  << "\" fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\""
                  << (snapped ? "" : " stroke-dasharray=\"6 4\"") << " points=\"";
                for (const auto& q : pts) s << sx(q[0]) << "," << sy(q[1]) << " ";
                s << "\"><title>" << where(p) << " (" << st.outcome << ")</title></polygon>\n";
                // The primitive's label, "d0 t1" for draws[0] triangle 1 (as the text and the
                // verdict name it), at its corners' mean, kept inside the panel; placed below.
                {
                    double lx = 0, ly = 0;
                    for (const auto& q : pts) {
                        lx += q[0];
                        ly += q[1];
                    }
                    lx = std::clamp(lx / static_cast<double>(pts.size()), x0 + 0.6, x0 + n - 0.6);
                    ly = std::clamp(ly / static_cast<double>(pts.size()), y0 + 0.4, y0 + n - 0.4);
                    labels.push_back({sx(lx), sy(ly) + 4,
                                      "d" + std::to_string(p.draw) + " " + p.kind.substr(0, 1) +
                                          std::to_string(p.primitive),
                                      colour, "primitive-label", 12});
                }
                if (!snapped || pts.size() < 3) continue;
                // Each edge's direction (an arrow at its middle) and its inside side (a tick
                // towards the polygon's centre, which is inside: the set-up polygons are convex).
                double mx = 0, my = 0;
                for (const auto& q : pts) {
                    mx += q[0];
                    my += q[1];
                }
                mx /= static_cast<double>(pts.size());
                my /= static_cast<double>(pts.size());
                for (std::size_t i = 0; i < pts.size(); ++i) {
                    const auto& a = pts[i];
                    const auto& b = pts[(i + 1) % pts.size()];
                    const double ex = b[0] - a[0], ey = b[1] - a[1];
                    const double len = std::hypot(ex, ey);
                    if (len == 0) continue;
                    // The marks sit at the edge's point nearest the traced point (kept off the
                    // corners), so that an edge crossing the panel shows them inside it.
                    const double t =
                        std::clamp(((tx - a[0]) * ex + (ty - a[1]) * ey) / (len * len), 0.15, 0.85);
                    const double hx = a[0] + t * ex, hy = a[1] + t * ey;
                    // An edge that passes the panel by shows no marks.
                    if (hx < x0 + 0.1 || hx > x0 + n - 0.1 || hy < y0 + 0.1 || hy > y0 + n - 0.1)
                        continue;
                    const double step = 0.18;  // pixels
                    s << "<line class=\"edge-direction\" x1=\"" << sx(hx - ex / len * step)
                      << "\" y1=\"" << sy(hy - ey / len * step) << "\" x2=\""
                      << sx(hx + ex / len * step) << "\" y2=\"" << sy(hy + ey / len * step)
                      << "\" stroke=\"" << colour
                      << "\" stroke-width=\"2\" marker-end=\"url(#arrow)\"><title>edge " << i
                      << ": from corner " << i << " to corner " << (i + 1) % pts.size()
                      << "</title></line>\n";
                    // The normal towards the centre.
                    double nx = -ey / len, ny = ex / len;
                    if ((mx - hx) * nx + (my - hy) * ny < 0) {
                        nx = -nx;
                        ny = -ny;
                    }
                    s << "<line class=\"inside-side\" x1=\"" << sx(hx) << "\" y1=\"" << sy(hy)
                      << "\" x2=\"" << sx(hx + nx * 0.3) << "\" y2=\"" << sy(hy + ny * 0.3)
                      << "\" stroke=\"" << colour
                      << "\" stroke-width=\"3\" stroke-linecap=\"round\"><title>edge " << i
                      << ": its inside is this side</title></line>\n";
                    // The edge's number as the text gives it ("edge 1"), on its outside.
                    labels.push_back({sx(hx - nx * 0.32), sy(hy - ny * 0.32) + 4,
                                      "e" + std::to_string(i), colour, "edge-label", 11});
                }
            }
        }
        std::vector<std::array<double, 4>> placed;  // left, top, right, bottom
        // Inside the panel, so that no label meets the axes' numbers outside it.
        const double box_l = sx(x0), box_r = sx(x0 + n), box_t = sy(y0 + n), box_b = sy(y0);
        for (const auto& l : labels) {
            const double half = 0.62 * l.size * static_cast<double>(l.text.size()) / 2 + 2;
            const double top_of = l.size + 1;
            const double x = std::clamp(l.x, box_l + half, box_r - half);
            const double y_first = std::clamp(l.y, box_t + top_of, box_b - 3);
            double y = y_first;
            for (int k = 0; k < 16; ++k) {
                const double dy = (k % 2 == 0 ? 1 : -1) * ((k + 1) / 2) * (l.size + 3);
                const double at = y_first + dy;
                if (at - top_of < box_t || at + 3 > box_b) continue;
                const bool clear = std::none_of(placed.begin(), placed.end(), [&](const auto& b) {
                    return x - half < b[2] && b[0] < x + half && at - top_of < b[3] &&
                           b[1] < at + 3;
                });
                if (clear) {
                    y = at;
                    break;
                }
            }
            placed.push_back({x - half, y - top_of, x + half, y + 3});
            s << "<text class=\"" << l.cls << "\" x=\"" << x << "\" y=\"" << y
              << "\" text-anchor=\"middle\" font-size=\"" << l.size << "\""
              << (l.size == 12 ? " font-weight=\"600\"" : "") << " fill=\"" << l.colour
              << "\" stroke=\"#fff\" stroke-width=\"3\" paint-order=\"stroke\">"
              << markup::escape(l.text) << "</text>\n";
        }
        s << "</g>\n";
        if (multisampled) {
            s << "<circle cx=\"" << sx(tx) << "\" cy=\"" << sy(ty)
              << "\" r=\"4\" fill=\"#ff00ff\"><title>sample " << e.trace.sample
              << "</title></circle>\n";
        }
        // Pixel-coordinate axes: each column's x below, each row's y to the left.
        for (int x = x0; x < x0 + n; ++x) {
            s << "<text class=\"axis-x\" x=\"" << sx(x + 0.5) << "\" y=\"" << sy(y0) + 15
              << "\" text-anchor=\"middle\" fill=\"#444\">" << x << "</text>";
        }
        for (int y = y0; y < y0 + n; ++y) {
            s << "<text class=\"axis-y\" x=\"" << sx(x0) - 5 << "\" y=\"" << sy(y + 0.5) + 4
              << "\" text-anchor=\"end\" fill=\"#444\">" << y << "</text>";
        }
        s << "\n</g>\n";
    };
    panel(0, false);
    panel(panel_w + kGap, true);

    // Both sides' values and the verdict, each line whole.
    s << "<g id=\"captions\">";
    for (std::size_t i = 0; i < captions.size(); ++i) {
        s << "<text x=\"4\" y=\"" << caption_top + static_cast<int>(i) * kCaptionLine << "\">"
          << markup::escape(captions[i]) << "</text>";
    }
    s << "</g>\n";
    // The legend: every mark of the two panels.
    s << "<g id=\"legend\" transform=\"translate(8 " << legend_top << ")\">\n";
    struct Entry {
        std::string mark;
        const char* text;
    };
    const Entry entries[] = {
        {"<rect x=\"0\" y=\"-10\" width=\"14\" height=\"14\" fill=\"none\" stroke=\"#ff00ff\" "
         "stroke-width=\"3\"/>",
         "the explained pixel (x right, y up, GL's window coordinates)"},
        {"<line x1=\"0\" y1=\"-3\" x2=\"22\" y2=\"-3\" stroke=\"#00a844\" stroke-width=\"2\"/>",
         "a primitive that covers the point"},
        {"<line x1=\"0\" y1=\"-3\" x2=\"22\" y2=\"-3\" stroke=\"#2962ff\" stroke-width=\"2\"/>",
         "a primitive that reaches the pixel but does not cover the point"},
        {"<line x1=\"0\" y1=\"-3\" x2=\"22\" y2=\"-3\" stroke=\"#555\" stroke-width=\"2\" "
         "stroke-dasharray=\"6 4\"/>",
         "unsnapped outline (left); solid: snapped corners (right)"},
        {"<line x1=\"0\" y1=\"-3\" x2=\"16\" y2=\"-3\" stroke=\"#555\" stroke-width=\"2\" "
         "marker-end=\"url(#arrow)\"/><line x1=\"8\" y1=\"-3\" x2=\"8\" y2=\"4\" stroke=\"#555\" "
         "stroke-width=\"3\"/>",
         "an edge's direction, and a tick on its inside side"},
        {"<circle cx=\"7\" cy=\"-3\" r=\"2.5\" fill=\"#666\"/>",
         multisampled ? "sample positions (4x: four a pixel)"
                      : "pixel centres (where coverage is tested)"},
        {"<circle cx=\"7\" cy=\"-3\" r=\"6\" fill=\"none\" stroke=\"#ff6d00\" stroke-width=\"3\"/>",
         "a tie: the point lies exactly on an edge, and the tie rule decides"},
        {"<rect x=\"0\" y=\"-10\" width=\"14\" height=\"14\" fill=\"url(#outside)\"/>",
         "outside the target"},
        {"<rect x=\"0\" y=\"-10\" width=\"14\" height=\"14\" fill=\"none\" stroke=\"#7f7f7f\" "
         "stroke-opacity=\"0.5\"/><line x1=\"7\" y1=\"-10\" x2=\"7\" y2=\"4\" stroke=\"#7f7f7f\" "
         "stroke-opacity=\"0.5\"/>",
         "faint lines: the sub-pixel grid, every 1/8 pixel"},
        {"<text x=\"0\" y=\"0\" font-weight=\"600\" font-size=\"11\">d0 t1</text>",
         "a primitive: d0 t1 is draws[0] triangle 1 (l a line, p a point), as the text names it"},
        {"<text x=\"4\" y=\"0\" font-size=\"11\">e1</text>",
         "an edge's number, on its outside: edge 1 runs from corner 1 to corner 2"},
        {"<rect x=\"0\" y=\"-10\" width=\"14\" height=\"14\" fill=\"#bbb\" stroke=\"#888\"/>"
         "<polygon points=\"14,-10 14,4 0,4\" fill=\"#444\"/>",
         "a cell: the reference's colour; its lower-right half the backend's, where they differ"},
    };
    static_assert(std::size(entries) == kLegendEntries, "one row an entry");
    int row = 0;
    for (const auto& en : entries) {
        s << "<g transform=\"translate(0 " << 14 + row * kLegendRow << ")\">" << en.mark
          << "<text x=\"40\" y=\"0\">" << en.text << "</text></g>\n";
        ++row;
    }
    s << "</g>\n";
    if (e.texels) s << texel_panel_svg(*e.texels, H0);
    s << markup::svg_close() << "\n";
    std::string out = s.str();
    if (e.texels) {
        // The texel panel sits below: widen and heighten the picture to hold it.
        const int width = std::max(W0, kTexelPanelWidth);
        const int height = H0 + kTexelPanelHeight;
        const std::string old_head = "width=\"" + std::to_string(W0) + "\" height=\"" +
                                     std::to_string(H0) + "\" viewBox=\"0 0 " + std::to_string(W0) +
                                     " " + std::to_string(H0) + "\"";
        const std::string new_head = "width=\"" + std::to_string(width) + "\" height=\"" +
                                     std::to_string(height) + "\" viewBox=\"0 0 " +
                                     std::to_string(width) + " " + std::to_string(height) + "\"";
        if (const auto at = out.find(old_head); at != std::string::npos)
            out.replace(at, old_head.size(), new_head);
    }
    return out;
}

}  // namespace harness
