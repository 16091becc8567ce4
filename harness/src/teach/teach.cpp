#include "harness/teach.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "refraster/assembly.hpp"
#include "refraster/profile.hpp"
#include "refraster/textbook/circle.hpp"
#include "refraster/textbook/ear_clipping.hpp"
#include "refraster/textbook/edge_functions.hpp"
#include "refraster/textbook/flood_fill.hpp"
#include "refraster/textbook/homogeneous.hpp"
#include "refraster/textbook/lines.hpp"
#include "refraster/textbook/painter.hpp"
#include "refraster/textbook/scanline_fill.hpp"
#include "refraster/textbook/trapezoids.hpp"
#include "refraster/textbook/wu_line.hpp"

namespace harness {

namespace tb = refraster::textbook;
using refraster::PrimitiveType;

const std::vector<TeachAlgorithmInfo>& teach_algorithms() {
    static const std::vector<TeachAlgorithmInfo> all{
        {"dda", "the DDA line", "the segments of line draws"},
        {"bresenham", "Bresenham's line algorithm", "the segments of line draws"},
        {"midpoint", "the midpoint line algorithm", "the segments of line draws"},
        {"wu", "Xiaolin Wu's antialiased line", "the segments of line draws"},
        {"circle", "the midpoint circle",
         "point draws: each point a circle of diameter point_size; line loops of 8 or more "
         "vertices on a circle: that circle"},
        {"scanline-evenodd", "scanline polygon fill (edge table, active edge list), even-odd",
         "polygon, triangle_fan and triangle draws as outlines"},
        {"scanline-nonzero", "scanline polygon fill (edge table, active edge list), non-zero",
         "polygon, triangle_fan and triangle draws as outlines"},
        {"flood4", "4-connected boundary fill", "polygon outlines drawn by Bresenham"},
        {"flood8", "8-connected boundary fill", "polygon outlines drawn by Bresenham"},
        {"ear-clipping", "ear clipping", "polygon draws, each a simple polygon"},
        {"trapezoids", "trapezoidal decomposition (Seidel)",
         "polygon draws, each a simple polygon"},
        {"painter", "the painter's algorithm", "triangle draws with window depth"},
        {"homogeneous", "homogeneous (Olano-Greer) rasterization",
         "triangle draws in clip space, w <= 0 included"},
        {"half-space", "edge functions with GL's tie rule (Pineda), as llvmpipe sets them up",
         "the triangles of triangle draws, unclipped"},
    };
    return all;
}

namespace {

// The draws an algorithm takes, and the bound on their vertices.
struct TakenDraws {
    bool (*takes)(refraster::PrimitiveType);
    std::uint64_t max_vertices;
    const char* what;
};

TakenDraws taken_draws(std::string_view algorithm) {
    using P = refraster::PrimitiveType;
    if (algorithm == "dda" || algorithm == "bresenham" || algorithm == "midpoint" ||
        algorithm == "wu")
        return {[](P p) { return p == P::Lines || p == P::LineStrip || p == P::LineLoop; },
                TeachLimits::kMaxVertices, "line draws"};
    if (algorithm == "circle")
        return {[](P p) { return p == P::Points; }, TeachLimits::kMaxVertices, "point draws"};
    if (algorithm == "ear-clipping" || algorithm == "trapezoids")
        return {[](P p) { return p == P::Polygon; }, TeachLimits::kMaxPolygonVertices,
                "polygon draws"};
    if (algorithm == "painter" || algorithm == "homogeneous" || algorithm == "half-space")
        return {[](P p) { return p >= P::Triangles && p != P::Polygon; }, TeachLimits::kMaxVertices,
                "triangle draws"};
    return {[](P p) { return p == P::Polygon || p == P::TriangleFan || p == P::Triangles; },
            TeachLimits::kMaxVertices, "polygon, triangle_fan and triangle draws"};
}

}  // namespace

void check_teach_input(const Scene& scene, std::string_view algorithm) {
    const std::uint64_t w = scene.draw_list.target.width;
    const std::uint64_t h = scene.draw_list.target.height;
    if (w * h > TeachLimits::kMaxPixels) {
        throw TeachError("target: teach draws at most " + std::to_string(TeachLimits::kMaxPixels) +
                         " pixels (width x height; a page shows every pixel, docs/limits.md), "
                         "this target has " +
                         std::to_string(w) + " x " + std::to_string(h) + " = " +
                         std::to_string(w * h));
    }
    const TakenDraws taken = taken_draws(algorithm);
    std::uint64_t vertices = 0;
    for (std::size_t d = 0; d < scene.draw_list.draws.size(); ++d) {
        const auto& draw = scene.draw_list.draws[d];
        if (!taken.takes(draw.primitive)) continue;
        vertices += draw.element_count();
        if (vertices > taken.max_vertices) {
            throw TeachError("draws[" + std::to_string(d) + "]: \"" + std::string(algorithm) +
                             "\" takes at most " + std::to_string(taken.max_vertices) +
                             " vertices of the " + taken.what +
                             " (docs/limits.md), this draw brings them to " +
                             std::to_string(vertices));
        }
    }
}

namespace {

// ---- what a scene holds --------------------------------------------------------------------

// One draw's vertices in window coordinates, in element order (through its indices): the
// file's own numbers for a window-space draw, else clip / w through the viewport in double.
std::vector<tb::Point2> window_points(const Scene& s, std::size_t d) {
    const refraster::Draw& draw = s.draw_list.draws[d];
    const SceneDraw& file = s.file.draws[d];
    std::vector<tb::Point2> out;
    for (std::size_t i = 0; i < draw.element_count(); ++i) {
        const std::uint32_t e = draw.element(i);
        if (file.space == VertexSpace::Window) {
            out.push_back({static_cast<double>(file.vertices[e].position[0]),
                           static_cast<double>(file.vertices[e].position[1])});
            continue;
        }
        const auto p = draw.vertices.position(e);
        const auto& v = draw.state.viewport;
        const auto w = static_cast<double>(p[3]);
        out.push_back({v.x + (static_cast<double>(p[0]) / w + 1.0) * v.width / 2.0,
                       v.y + (static_cast<double>(p[1]) / w + 1.0) * v.height / 2.0});
    }
    return out;
}

std::array<std::uint8_t, 4> flat_color(const refraster::Draw& d, std::uint32_t e) {
    std::array<std::uint8_t, 4> c{255, 255, 255, 255};
    if (d.vertices.attributes.empty()) return c;
    const auto v = d.vertices.vertex(e);
    for (std::size_t k = 0; k < 4; ++k) {
        const float f = std::clamp(v[4 + k], 0.0f, 1.0f);
        c[k] = static_cast<std::uint8_t>(std::lround(f * 255.0f));
    }
    return c;
}

struct SceneSegment {
    tb::Point2 a, b;
    std::size_t draw = 0;
};

std::vector<SceneSegment> scene_segments(const Scene& s) {
    std::vector<SceneSegment> out;
    for (std::size_t d = 0; d < s.draw_list.draws.size(); ++d) {
        const auto p = s.draw_list.draws[d].primitive;
        if (p != PrimitiveType::Lines && p != PrimitiveType::LineStrip &&
            p != PrimitiveType::LineLoop)
            continue;
        const auto pts = window_points(s, d);
        for (const auto& seg : refraster::assemble_lines(p, pts.size()))
            out.push_back({pts[seg[0]], pts[seg[1]], d});
    }
    return out;
}

// The outlines of polygon, fan and triangle draws: a polygon or fan is one outline (a fan's
// vertices in order make the polygon it is usually meant to be), each triangle of a list one;
// with the fill rule GL draws each with, for the polygon algorithms' reasons.
struct GlPolygons {
    std::vector<tb::Contour> outlines;
    std::vector<std::optional<refraster::FillRule>> rules;  // per outline
    std::vector<bool> polygon;                              // from a polygon draw
};

GlPolygons gl_polygons(const Scene& s) {
    GlPolygons g;
    for (std::size_t d = 0; d < s.draw_list.draws.size(); ++d) {
        const auto& draw = s.draw_list.draws[d];
        const auto pts = window_points(s, d);
        if (draw.primitive == PrimitiveType::Polygon ||
            draw.primitive == PrimitiveType::TriangleFan) {
            if (pts.size() < 3) continue;
            g.outlines.push_back(pts);
            g.rules.push_back(draw.state.fill_rule);
            g.polygon.push_back(draw.primitive == PrimitiveType::Polygon);
        } else if (draw.primitive == PrimitiveType::Triangles) {
            for (std::size_t i = 0; i + 2 < pts.size(); i += 3) {
                g.outlines.push_back({pts[i], pts[i + 1], pts[i + 2]});
                g.rules.push_back(std::nullopt);
                g.polygon.push_back(false);
            }
        }
    }
    return g;
}

std::vector<tb::Contour> scene_outlines(const Scene& s, bool polygons_only = false) {
    GlPolygons g = gl_polygons(s);
    if (!polygons_only) return std::move(g.outlines);
    std::vector<tb::Contour> out;
    for (std::size_t k = 0; k < g.outlines.size(); ++k)
        if (g.polygon[k]) out.push_back(std::move(g.outlines[k]));
    return out;
}

// ---- exact helpers for the reasons -----------------------------------------------------------

// The winding number of the outlines at the centre of (x, y) nudged by (+e, +e^2) (GL's
// left-bottom rule), from the crossings of the nudged horizontal line.
int winding_at(const std::vector<tb::Contour>& contours, int x, int y) {
    const double cx = x + 0.5;
    const double cy = y + 0.5;
    int w = 0;
    for (const auto& c : contours) {
        for (std::size_t k = 0; k < c.size(); ++k) {
            const tb::Point2 a = c[k];
            const tb::Point2 b = c[(k + 1) % c.size()];
            if ((a.y > cy) == (b.y > cy)) continue;
            const double xc = a.x + (cy - a.y) * (b.x - a.x) / (b.y - a.y);
            if (xc <= cx) w += b.y > a.y ? 1 : -1;
        }
    }
    return w;
}

bool on_outline(const std::vector<tb::Contour>& contours, int x, int y) {
    const double cx = x + 0.5;
    const double cy = y + 0.5;
    for (const auto& c : contours) {
        for (std::size_t k = 0; k < c.size(); ++k) {
            const tb::Point2 a = c[k];
            const tb::Point2 b = c[(k + 1) % c.size()];
            const double cross = (b.x - a.x) * (cy - a.y) - (b.y - a.y) * (cx - a.x);
            if (cross == 0.0 && std::min(a.x, b.x) <= cx && cx <= std::max(a.x, b.x) &&
                std::min(a.y, b.y) <= cy && cy <= std::max(a.y, b.y))
                return true;
        }
    }
    return false;
}

// How many of GL_POLYGON's fan triangles (v0, v[i-1], v[i]) of an outline cover the centre.
int fan_cover(const tb::Contour& c, int x, int y) {
    const double cx = x + 0.5;
    const double cy = y + 0.5;
    // winding_at of one triangle, without building it.
    const auto crossing = [&](tb::Point2 a, tb::Point2 b) {
        if ((a.y > cy) == (b.y > cy)) return 0;
        const double xc = a.x + (cy - a.y) * (b.x - a.x) / (b.y - a.y);
        return xc <= cx ? (b.y > a.y ? 1 : -1) : 0;
    };
    int n = 0;
    for (std::size_t i = 2; i < c.size(); ++i) {
        const int w = crossing(c[0], c[i - 1]) + crossing(c[i - 1], c[i]) + crossing(c[i], c[0]);
        n += w != 0 ? 1 : 0;
    }
    return n;
}

std::string pixel_text(int x, int y) {
    return "(" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

std::string num(double v) {
    return tb::format_number(v);
}

bool on_centre(tb::Point2 p) {
    return p.x - std::floor(p.x) == 0.5 && p.y - std::floor(p.y) == 0.5;
}

double distance_to_segment(tb::Point2 a, tb::Point2 b, double px, double py) {
    const double dx = b.x - a.x;
    const double dy = b.y - a.y;
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((px - a.x) * dx + (py - a.y) * dy) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(px - (a.x + t * dx), py - (a.y + t * dy));
}

// ---- the algorithms -------------------------------------------------------------------------

struct Run {
    tb::Raster raster;
    std::vector<std::array<std::uint8_t, 4>> colors;  // per pixel, when the algorithm colours
    std::vector<tb::Segment> input;
    std::vector<tb::Step> steps;
    std::vector<std::string> pseudo_code;  // the first trace's
    std::vector<std::string> notes;
    // Why pixel (x, y) differs, given the algorithm's weight and GL's coverage.
    std::function<std::string(int, int, double, bool)> reason;
    // A difference besides coverage (the painter: another triangle is seen), if any.
    std::function<bool(int, int)> differs;
    // The steps past the bounds (TeachLimits), and the pixel marks of the recorded ones.
    std::size_t omitted = 0;
    std::size_t marks = 0;
    std::size_t segments = 0;
};

// Whether another step fits the run's bounds.
bool room_for_step(const Run& run) {
    return run.steps.size() < TeachLimits::kMaxSteps && run.marks < TeachLimits::kMaxStepPixels &&
           run.segments < TeachLimits::kMaxStepSegments;
}

// A trace bounded by what the run may still record.
tb::Trace bounded_trace(const Run& run) {
    tb::Trace t;
    t.max_steps = TeachLimits::kMaxSteps - std::min(run.steps.size(), TeachLimits::kMaxSteps);
    t.max_pixels = TeachLimits::kMaxStepPixels - std::min(run.marks, TeachLimits::kMaxStepPixels);
    t.max_segments =
        TeachLimits::kMaxStepSegments - std::min(run.segments, TeachLimits::kMaxStepSegments);
    t.max_values = TeachLimits::kMaxStepValues;
    t.max_value_chars = TeachLimits::kMaxValueChars;
    return t;
}

void add_step(Run& run, tb::Step step) {
    if (!room_for_step(run)) {
        ++run.omitted;
        return;
    }
    tb::trim_step(step, TeachLimits::kMaxStepValues, TeachLimits::kMaxValueChars);
    run.marks += step.pixels.size();
    run.segments += step.overlay.size();
    run.steps.push_back(std::move(step));
}

// The steps of one part of the scene (a segment, a polygon), each titled and grouped by the
// part ("segment 2: ..." in group "segment 2") when the scene has several.
void append_trace(Run& run, tb::Trace& t, const std::string& prefix) {
    const std::string group =
        prefix.size() > 2 ? prefix.substr(0, prefix.size() - 2) : std::string();
    for (auto& s : t.steps) {
        if (!prefix.empty()) s.title = prefix + s.title;
        if (!group.empty()) s.group = group;
        add_step(run, std::move(s));
    }
    run.omitted += t.omitted;
    for (auto& seg : t.input) run.input.push_back(std::move(seg));
    if (run.pseudo_code.empty()) run.pseudo_code = t.pseudo_code;
}

void merge_max(tb::Raster& into, const tb::Raster& r) {
    for (int y = 0; y < r.height(); ++y)
        for (int x = 0; x < r.width(); ++x)
            if (r.at(x, y) > into.at(x, y)) into.set(x, y, r.at(x, y));
}

Run run_lines(const Scene& s, std::string_view name, int w, int h) {
    const auto segments = scene_segments(s);
    if (segments.empty()) {
        throw TeachError("the scene has no line draws (lines, line_strip, line_loop); \"" +
                         std::string(name) + "\" draws " + "the segments of line draws");
    }
    Run run;
    run.raster = tb::Raster(w, h);
    for (std::size_t k = 0; k < segments.size(); ++k) {
        tb::Trace t = bounded_trace(run);
        const auto& sg = segments[k];
        const std::string prefix =
            segments.size() > 1 ? "segment " + std::to_string(k) + ": " : std::string();
        if (name == "wu") {
            const auto r = tb::wu_line(sg.a, sg.b, w, h, &t);
            merge_max(run.raster, r.raster);
        } else {
            const auto r = name == "dda" ? tb::dda_line(sg.a, sg.b, w, h, &t)
                           : name == "bresenham"
                               ? tb::bresenham_line(sg.a, sg.b, w, h, tb::MinorTie::Step, &t)
                               : tb::midpoint_line(sg.a, sg.b, w, h, tb::MinorTie::Keep, &t);
            merge_max(run.raster, r.raster);
        }
        append_trace(run, t, prefix);
    }
    bool rounded = false;
    for (const auto& sg : segments) rounded = rounded || !on_centre(sg.a) || !on_centre(sg.b);
    if (rounded && name != "wu") {
        run.notes.push_back(
            "Some endpoints are not on pixel centres: the textbook rounds each to the centre of "
            "the pixel it lies in, so it has no sub-pixel precision; GL keeps 1/256 of a pixel.");
    }
    run.notes.push_back(
        "GL's aliased lines (here llvmpipe's) are parallelograms one pixel across the minor "
        "axis, half-open at their ends (the diamond-exit rule: a line does not light the pixel "
        "it ends in, so that the segments of a strip do not draw a shared vertex twice).");
    run.reason = [segments, name = std::string(name)](int x, int y, double a,
                                                      bool gl) -> std::string {
        // The segment nearest the centre.
        std::size_t best = 0;
        double dist = 1e300;
        for (std::size_t k = 0; k < segments.size(); ++k) {
            const double d = distance_to_segment(segments[k].a, segments[k].b, x + 0.5, y + 0.5);
            if (d < dist) {
                dist = d;
                best = k;
            }
        }
        const auto& sg = segments[best];
        const tb::PixelIndex end = tb::pixel_containing(sg.b);
        const tb::PixelIndex start = tb::pixel_containing(sg.a);
        const std::string seg =
            segments.size() > 1 ? "segment " + std::to_string(best) : "the line";
        if (name == "wu" && a > 0.0 && a < 1.0) {
            return "Wu's line spreads each column over the two pixels nearest the line, by their "
                   "distance to it (weight " +
                   num(a) + " here); GL's aliased line lights one pixel or none" +
                   (gl ? " (it lights this one)." : ".");
        }
        if (a > 0.0 && !gl && end.x == x && end.y == y) {
            return "the last pixel of " + seg +
                   ": GL's rule is half-open at a line's end (the diamond-exit rule), the "
                   "textbook draws both ends.";
        }
        if (!gl && a > 0.0 && start.x == x && start.y == y && !on_centre(sg.a)) {
            return "the first pixel of " + seg + ": its start " + pixel_text(x, y) +
                   " is off the centre, and GL's line does not reach this pixel's diamond.";
        }
        // A tie on the rounded line: the exact line through the two centres passes halfway
        // between two centres at this pixel's major coordinate.
        const double ax = start.x + 0.5, ay = start.y + 0.5;
        const double bx = end.x + 0.5, by = end.y + 0.5;
        const bool xmajor = std::abs(bx - ax) >= std::abs(by - ay);
        if ((xmajor ? bx != ax : by != ay)) {
            const double t = xmajor ? (x + 0.5 - ax) / (bx - ax) : (y + 0.5 - ay) / (by - ay);
            const double minor = xmajor ? ay + t * (by - ay) : ax + t * (bx - ax);
            const double frac = minor - std::floor(minor);
            if (t >= 0.0 && t <= 1.0 && frac == 0.0) {
                return std::string(
                           "a tie: the line through the rounded endpoints passes exactly "
                           "halfway between this pixel's centre and its neighbour's; ") +
                       (name == "bresenham"  ? "Bresenham takes the step there (its error >= 0)"
                        : name == "midpoint" ? "the midpoint rule keeps its row there (d <= 0)"
                                             : "DDA rounds half up there") +
                       ", and GL's rule " + (gl ? "lights this pixel." : "lights the other.");
            }
        }
        if (!on_centre(sg.a) || !on_centre(sg.b)) {
            return "the rounding: the textbook moved " + seg +
                   "'s endpoints to pixel centres (no sub-pixel precision), GL draws them where "
                   "they are (to 1/256 pixel); the exact line passes " +
                   num(std::round(dist * 1000.0) / 1000.0) + " pixels from this centre.";
        }
        return std::string(
                   "GL's line rule and the textbook's nearest pixel per column part "
                   "here: the exact line passes ") +
               num(std::round(dist * 1000.0) / 1000.0) + " pixels from this centre, and GL " +
               (gl ? "lights" : "does not light") + " it.";
    };
    return run;
}

Run run_circle(const Scene& s, int w, int h) {
    Run run;
    run.raster = tb::Raster(w, h);
    struct Circle {
        tb::PixelIndex centre;
        int radius;
        std::size_t chords;            // 0: from a point; else the line loop's vertex count
        std::vector<tb::Point2> loop;  // the loop's window vertices
    };
    std::vector<Circle> circles;
    for (std::size_t d = 0; d < s.draw_list.draws.size(); ++d) {
        const auto& draw = s.draw_list.draws[d];
        if (draw.primitive == PrimitiveType::Points) {
            for (const auto& p : window_points(s, d)) {
                const int r = static_cast<int>(std::lround(draw.state.point_size / 2.0f));
                circles.push_back({tb::pixel_containing(p), r, 0, {}});
            }
        } else if (draw.primitive == PrimitiveType::LineLoop) {
            // A loop of 8 or more vertices about equally far from their mean is a circle
            // drawn as GL draws one: a polygon of chords.
            const auto pts = window_points(s, d);
            if (pts.size() < 8) continue;
            double cx = 0.0, cy = 0.0;
            for (const auto& p : pts) {
                cx += p.x;
                cy += p.y;
            }
            cx /= static_cast<double>(pts.size());
            cy /= static_cast<double>(pts.size());
            double mean = 0.0, lo = 1e300, hi = 0.0;
            for (const auto& p : pts) {
                const double r = std::hypot(p.x - cx, p.y - cy);
                mean += r;
                lo = std::min(lo, r);
                hi = std::max(hi, r);
            }
            mean /= static_cast<double>(pts.size());
            if (mean < 1.0 || hi - lo > std::max(0.75, 0.05 * mean)) continue;
            circles.push_back({tb::pixel_containing({cx, cy}), static_cast<int>(std::lround(mean)),
                               pts.size(), pts});
        }
    }
    if (circles.empty())
        throw TeachError(
            "the scene has no point draws and no line loop of 8 or more vertices on "
            "a circle; \"circle\" draws a circle for each");
    bool any_point = false, any_loop = false;
    for (std::size_t k = 0; k < circles.size(); ++k) {
        tb::Trace t = bounded_trace(run);
        const auto r = tb::midpoint_circle(circles[k].centre, circles[k].radius, w, h, &t);
        merge_max(run.raster, r.raster);
        append_trace(run, t, circles.size() > 1 ? "circle " + std::to_string(k) + ": " : "");
        (circles[k].chords == 0 ? any_point : any_loop) = true;
    }
    if (any_point)
        run.notes.push_back(
            "Each point of the scene becomes a circle centred on the pixel holding the vertex, of "
            "radius point_size / 2 rounded. GL has no circles: its point is a square of side "
            "point_size (smooth points aside), so the two agree only where the circle's outline "
            "meets the square.");
    if (any_loop)
        run.notes.push_back(
            "Each line loop of 8 or more vertices on a circle becomes a circle centred on the "
            "pixel holding the vertices' mean, of their mean distance from it, rounded. GL draws "
            "the loop as it draws any line loop: straight chords between the vertices, each lit "
            "by the diamond-exit rule. The midpoint circle lights, column by column, the pixel "
            "whose centre is nearest the exact circle; the chords cut inside the arc between "
            "vertices, and a chord crossing a pixel's diamond lights it where the circle's "
            "nearest pixel is its neighbour.");
    // Which circle a pixel belongs to: the one whose outline passes nearest its centre.
    const auto nearest = [circles](int x, int y) {
        const Circle* best = &circles.front();
        double best_d = 1e300;
        for (const Circle& c : circles) {
            const double d = std::fabs(std::hypot(x - c.centre.x, y - c.centre.y) - c.radius);
            if (d < best_d) {
                best_d = d;
                best = &c;
            }
        }
        return *best;
    };
    run.reason = [nearest](int x, int y, double a, bool gl) -> std::string {
        const Circle c = nearest(x, y);
        const double d = std::hypot(x - c.centre.x, y - c.centre.y);
        const std::string where = "its centre is " + tb::format_number(std::round(d * 100) / 100) +
                                  " px from the circle's centre, radius " +
                                  std::to_string(c.radius);
        if (c.chords == 0) {
            if (a > 0.0 && !gl) {
                return "on the circle's outline, outside GL's square point (GL draws no "
                       "circles).";
            }
            return "inside GL's square point: the midpoint circle draws only the outline, the "
                   "pixel nearest the exact circle at each step.";
        }
        // The chord nearest the pixel's centre, and how far it passes.
        const double px = x + 0.5, py = y + 0.5;
        double gap = 1e300;
        bool vertex = false;
        for (std::size_t i = 0; i < c.loop.size(); ++i) {
            const tb::Point2 p = c.loop[i], q = c.loop[(i + 1) % c.loop.size()];
            const double dx = q.x - p.x, dy = q.y - p.y, len2 = dx * dx + dy * dy;
            const double t =
                len2 > 0.0 ? std::clamp(((px - p.x) * dx + (py - p.y) * dy) / len2, 0.0, 1.0) : 0.0;
            gap = std::min(gap, std::hypot(px - p.x - t * dx, py - p.y - t * dy));
            vertex = vertex || (p.x == px && p.y == py);
        }
        const std::string chord =
            vertex ? "a vertex of the loop lies on its centre, where one chord ends (half-open) "
                     "and the next begins"
                   : "the nearest chord passes " + tb::format_number(std::round(gap * 100) / 100) +
                         " px from its centre";
        if (a > 0.0 && !gl)
            return "the midpoint circle's pixel (" + where + "), not lit by GL's loop of " +
                   std::to_string(c.chords) + " straight chords: " + chord +
                   ", and GL's line rule gives the pixel to a neighbour.";
        return "lit by GL's loop of " + std::to_string(c.chords) + " straight chords (" + chord +
               "), not by the midpoint circle, which lit the pixel nearest the exact circle in "
               "this column or row (" +
               where + ").";
    };
    return run;
}

// Why a polygon algorithm (which fills the outlines' region by `rule`) and GL part at (x, y).
std::string polygon_reason(const GlPolygons& g, const std::string& algorithm_rule, int x, int y,
                           double a, bool gl) {
    const int wind = winding_at(g.outlines, x, y);
    const std::string here = "winding number " + std::to_string(wind) + " at the centre";
    if (on_outline(g.outlines, x, y)) {
        return "the centre lies exactly on an outline: GL's tie rule (left and bottom edges are "
               "in: the region just right, or just above, decides) " +
               std::string(gl ? "lights" : "leaves") + " it; " + here + ".";
    }
    for (std::size_t k = 0; k < g.outlines.size(); ++k) {
        const int own = winding_at({g.outlines[k]}, x, y);
        const int fan = fan_cover(g.outlines[k], x, y);
        if (own == 0 && fan == 0) continue;
        if (!g.rules[k]) {
            if (gl && own == 0) {
                return "GL draws GL_POLYGON (or the fan) as its triangles (v0, v[i-1], v[i]): " +
                       std::to_string(fan) +
                       " of them cover this centre, which is outside the outline (a concave "
                       "polygon is not its fan).";
            }
            if (!gl && a > 0.0 && fan == 0) {
                return "inside the outline (" + here +
                       "), but none of GL_POLYGON's fan triangles covers it: the fan from v0 "
                       "misses this part of a concave polygon.";
            }
            if (a == 0.0 && gl) {
                return "GL_POLYGON's fan covers this centre " + std::to_string(fan) +
                       " times and draws it; the " + algorithm_rule + " rule with " + here +
                       " leaves it out.";
            }
        } else {
            const bool odd = (wind & 1) != 0;
            const bool nonzero = (wind & 0xff) != 0;
            return "the rules differ: " + here + "; even-odd " + (odd ? "lights" : "leaves") +
                   " it, non-zero " + (nonzero ? "lights" : "leaves") + " it (GL draws " +
                   std::string(refraster::to_string(*g.rules[k])) + ", the algorithm " +
                   algorithm_rule + ").";
        }
    }
    return "unexplained: " + here +
           ", and neither the outline nor GL_POLYGON's fan decides it "
           "here (snapping to 1/256 pixel may).";
}

Run run_scanline(const Scene& s, tb::FillRule rule, int w, int h) {
    const auto outlines = scene_outlines(s);
    if (outlines.empty())
        throw TeachError("the scene has no polygon, triangle_fan or triangle draw to fill");
    Run run;
    tb::Trace t = bounded_trace(run);
    const auto r = tb::scanline_fill(outlines, rule, w, h, &t);
    run.raster = r.raster;
    append_trace(run, t, "");
    const std::string rule_name = rule == tb::FillRule::EvenOdd ? "even-odd" : "non-zero";
    run.notes.push_back(
        "The filler takes every polygon and fan of the scene as one outline and each listed "
        "triangle as its own, and tests each pixel centre with GL's tie rule (the region just "
        "right of a centre on an edge, or just above it for a horizontal edge, decides). GL "
        "fills a polygon with a fill rule by the stencil method, with the same result; "
        "GL_POLYGON without one draws its fan.");
    const GlPolygons g = gl_polygons(s);
    run.reason = [g, rule_name](int x, int y, double a, bool gl) {
        return polygon_reason(g, rule_name, x, y, a, gl);
    };
    return run;
}

std::vector<std::array<std::uint8_t, 4>> palette_colors(const tb::Raster& ids_raster,
                                                        const std::vector<int>& ids) {
    static const std::array<std::array<std::uint8_t, 4>, 8> pal{{{230, 80, 80, 255},
                                                                 {80, 200, 90, 255},
                                                                 {80, 120, 230, 255},
                                                                 {230, 200, 60, 255},
                                                                 {200, 90, 220, 255},
                                                                 {70, 210, 210, 255},
                                                                 {240, 140, 50, 255},
                                                                 {160, 160, 160, 255}}};
    std::vector<std::array<std::uint8_t, 4>> out(ids.size(), {0, 0, 0, 0});
    for (std::size_t i = 0; i < ids.size(); ++i) {
        if (ids[i] >= 0) out[i] = pal[static_cast<std::size_t>(ids[i]) % pal.size()];
    }
    (void)ids_raster;
    return out;
}

// Pixels of triangles (exact nudged centre test), coloured by triangle.
void raster_triangles(Run& run, const std::vector<std::array<tb::Point2, 3>>& tris, int w, int h) {
    run.raster = tb::Raster(w, h);
    std::vector<int> ids(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), -1);
    for (std::size_t k = 0; k < tris.size(); ++k) {
        tb::DepthTriangle d;
        d.position = tris[k];
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        for (const auto& p : tris[k]) {
            x0 = std::min(x0, p.x);
            x1 = std::max(x1, p.x);
            y0 = std::min(y0, p.y);
            y1 = std::max(y1, p.y);
        }
        for (int y = std::max(0, static_cast<int>(std::floor(y0)) - 1);
             y <= std::min(h - 1, static_cast<int>(std::ceil(y1))); ++y) {
            for (int x = std::max(0, static_cast<int>(std::floor(x0)) - 1);
                 x <= std::min(w - 1, static_cast<int>(std::ceil(x1))); ++x) {
                if (!tb::covers_centre(d, x, y)) continue;
                run.raster.set(x, y, 1.0);
                ids[static_cast<std::size_t>(y * w + x)] = static_cast<int>(k);
            }
        }
    }
    run.colors = palette_colors(run.raster, ids);
}

Run run_triangulation(const Scene& s, bool ears, int w, int h) {
    const auto outlines = scene_outlines(s, true);
    if (outlines.empty())
        throw TeachError(std::string("the scene has no polygon draw; \"") +
                         (ears ? "ear-clipping" : "trapezoids") +
                         "\" triangulates the primitive \"polygon\"");
    Run run;
    std::vector<std::array<tb::Point2, 3>> tris;
    for (std::size_t k = 0; k < outlines.size(); ++k) {
        tb::Trace t = bounded_trace(run);
        const std::string prefix =
            outlines.size() > 1 ? "polygon " + std::to_string(k) + ": " : std::string();
        if (ears) {
            const auto r = tb::ear_clip(outlines[k], &t);
            for (const auto& tri : r.triangles) {
                tris.push_back({outlines[k][static_cast<std::size_t>(tri[0])],
                                outlines[k][static_cast<std::size_t>(tri[1])],
                                outlines[k][static_cast<std::size_t>(tri[2])]});
            }
            if (!r.complete)
                run.notes.push_back(prefix +
                                    "ear clipping stopped early: the polygon is not simple.");
        } else {
            for (const auto& tri : tb::triangulate(tb::trapezoidate(outlines[k], &t)))
                tris.push_back(tri.points);
        }
        append_trace(run, t, prefix);
    }
    raster_triangles(run, tris, w, h);
    run.notes.push_back(
        "The pieces are rasterized with GL's rule at pixel centres and coloured one by one: they "
        "tile the polygon, so their pixels are the polygon's interior, which is what GL's fill "
        "rules give and what GL_POLYGON's fan gives only for a convex polygon.");
    const GlPolygons g = gl_polygons(s);
    run.reason = [g](int x, int y, double a, bool gl) {
        return polygon_reason(g, "interior (a triangulation)", x, y, a, gl);
    };
    return run;
}

// A Bresenham outline of every polygon, then a fill from a seed inside each.
Run run_flood(const Scene& s, bool eight, int w, int h) {
    const auto outlines = scene_outlines(s);
    if (outlines.empty())
        throw TeachError("the scene has no polygon, triangle_fan or triangle draw to outline");
    Run run;
    tb::Raster boundary(w, h);
    for (const auto& c : outlines) {
        for (std::size_t k = 0; k < c.size(); ++k) {
            const auto r = tb::bresenham_line(c[k], c[(k + 1) % c.size()], w, h);
            merge_max(boundary, r.raster);
        }
        tb::add_outline(run.input, c);
    }
    run.raster = boundary;
    for (std::size_t k = 0; k < outlines.size(); ++k) {
        // The seed: the first pixel inside the outline, not on the boundary, in rings from the
        // vertices' mean outwards (flood_fill.hpp: each pixel of the outline's box once).
        const std::optional<tb::PixelIndex> seed = tb::seed_inside(boundary, outlines[k]);
        if (!seed) continue;
        tb::Trace t = bounded_trace(run);
        const auto r = tb::flood_fill(boundary, *seed,
                                      eight ? tb::Connectivity::Eight : tb::Connectivity::Four, &t);
        merge_max(run.raster, r.raster);
        append_trace(run, t,
                     outlines.size() > 1 ? "outline " + std::to_string(k) + ": " : std::string());
        run.notes.push_back("seed " + pixel_text(seed->x, seed->y) + " for outline " +
                            std::to_string(k));
    }
    run.notes.push_back(
        "The outline is drawn by Bresenham (an 8-connected boundary) and the fill starts from a "
        "pixel inside it: a 4-connected fill stays inside such an outline, an 8-connected one "
        "leaks through its diagonal steps. The outline's own pixels are part of the result.");
    const GlPolygons g = gl_polygons(s);
    run.reason = [g, boundary, outlines, eight](int x, int y, double a, bool gl) -> std::string {
        const int wind = winding_at(outlines, x, y);
        if (boundary.at(x, y) > 0) {
            return std::string("a pixel of the Bresenham outline, which the fill keeps; ") +
                   (gl ? "GL lights it too" : "GL does not light it: its centre is outside") +
                   " (winding number " + std::to_string(wind) + ").";
        }
        if (a > 0.0 && wind == 0 && eight) {
            return "the 8-connected fill leaked out through a diagonal step of the outline: this "
                   "centre is outside the polygon.";
        }
        if (!(a > 0.0) && gl && wind != 0) {
            return "inside the polygon, but the fill did not reach it from the seed: the outline "
                   "cuts this region off (a thin part, or a 4-connected fill stopped by a "
                   "diagonal).";
        }
        return polygon_reason(g, "filled region", x, y, a, gl);
    };
    return run;
}

struct SceneTriangle {
    tb::DepthTriangle t;
    std::size_t draw = 0;
    std::size_t primitive = 0;
    std::array<float, 4> clip[3];
    std::array<std::uint8_t, 4> color{};
};

std::vector<SceneTriangle> scene_triangles(const Scene& s) {
    std::vector<SceneTriangle> out;
    for (std::size_t d = 0; d < s.draw_list.draws.size(); ++d) {
        const auto& draw = s.draw_list.draws[d];
        if (draw.primitive < PrimitiveType::Triangles || draw.primitive == PrimitiveType::Polygon)
            continue;
        const auto pts = window_points(s, d);
        const bool first = draw.state.provoking_vertex == refraster::ProvokingVertex::First;
        const auto prims = refraster::assemble_primitives(draw.primitive, pts.size(), first);
        for (std::size_t p = 0; p < prims.size(); ++p) {
            SceneTriangle st;
            st.draw = d;
            st.primitive = p;
            for (std::size_t k = 0; k < 3; ++k) {
                const std::uint32_t e = prims[p][k];
                st.t.position[k] = pts[e];
                const auto pos = draw.vertices.position(draw.element(e));
                // Window depth through the depth range, as the viewport transform gives it.
                const double zn = static_cast<double>(pos[2]) / static_cast<double>(pos[3]);
                const auto n = static_cast<double>(draw.state.depth_near);
                const auto f = static_cast<double>(draw.state.depth_far);
                st.t.depth[k] = n + (zn + 1.0) / 2.0 * (f - n);
                st.clip[k] = {pos[0], pos[1], pos[2], pos[3]};
            }
            st.color = flat_color(draw, draw.element(prims[p][first ? 0 : 2]));
            out.push_back(st);
        }
    }
    return out;
}

Run run_painter(const Scene& s, const refraster::Framebuffer& gl, int w, int h) {
    const auto tris = scene_triangles(s);
    if (tris.empty()) throw TeachError("the scene has no triangle draw to paint");
    std::vector<tb::DepthTriangle> dt;
    for (const auto& t : tris) dt.push_back(t.t);
    Run run;
    tb::Trace t = bounded_trace(run);
    const auto painted = tb::painter(dt, tb::PainterKey::FarthestVertex, w, h, &t);
    const auto zbuf = tb::z_buffer(dt, w, h);
    run.raster = painted.raster;
    append_trace(run, t, "");
    run.colors.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), {0, 0, 0, 0});
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (painted.at(x, y) >= 0)
                run.colors[static_cast<std::size_t>(y * w + x)] =
                    tris[static_cast<std::size_t>(painted.at(x, y))].color;
    if (const auto first = tb::first_difference(painted, zbuf)) {
        run.notes.push_back("The first pixel where the painter's order and a z-buffer part: " +
                            pixel_text(first->x, first->y) + ", painted by triangle " +
                            std::to_string(first->painter_triangle) + ", nearest is triangle " +
                            std::to_string(first->z_buffer_triangle) + ".");
    } else {
        run.notes.push_back(
            "The painter's order (farthest vertex first) and a z-buffer agree on every pixel: no "
            "triangles intersect or overlap in a cycle here.");
    }
    run.notes.push_back(
        "Triangles are sorted by their farthest vertex and drawn back to front; GL tests depth "
        "per pixel (the scene's depth_test), which a painter's order cannot replace when "
        "triangles intersect or overlap cyclically. Colours compare which triangle is seen.");
    // GL's triangle at a pixel, from the owner pass.
    std::vector<int> gl_tri(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), -1);
    if (!gl.owner.empty()) {
        for (std::size_t i = 0; i < gl_tri.size(); ++i) {
            const std::uint32_t o = gl.owner[i];
            if (o == 0) continue;
            for (std::size_t k = 0; k < tris.size(); ++k) {
                if (refraster::owner_id(tris[k].draw, tris[k].primitive) == o) {
                    gl_tri[i] = static_cast<int>(k);
                    break;
                }
            }
        }
    }
    run.differs = [painted, gl_tri, w](int x, int y) {
        const int g = gl_tri[static_cast<std::size_t>(y * w + x)];
        return g >= 0 && painted.at(x, y) >= 0 && g != painted.at(x, y);
    };
    run.reason = [painted, zbuf, gl_tri, w](int x, int y, double a, bool lit) -> std::string {
        const int p = painted.at(x, y);
        const int z = zbuf.at(x, y);
        const int g = gl_tri[static_cast<std::size_t>(y * w + x)];
        if (p != z && p >= 0 && z >= 0) {
            return "the painter's order draws triangle " + std::to_string(p) +
                   " last here, but "
                   "triangle " +
                   std::to_string(z) +
                   " is nearer at this pixel: they intersect or overlap in a cycle, which only a "
                   "per-pixel depth test decides (GL shows triangle " +
                   std::to_string(g) + ").";
        }
        if (g != p) {
            return "GL shows triangle " + std::to_string(g) + " here and the painter " +
                   std::to_string(p) +
                   (a > 0.0 && !lit ? " (GL's depth test or coverage drops it)" : "") +
                   ": GL snaps vertices to 1/256 pixel and tests depth with the scene's compare "
                   "function, the textbook tests exact centres.";
        }
        return "the colours differ: GL interpolates or blends, the painter shows the triangle's "
               "flat colour.";
    };
    return run;
}

Run run_homogeneous(const Scene& s, int w, int h) {
    const auto tris = scene_triangles(s);
    if (tris.empty()) throw TeachError("the scene has no triangle draw to rasterize");
    Run run;
    run.raster = tb::Raster(w, h);
    std::vector<std::pair<tb::ClipTriangle, tb::Viewport>> inputs;
    for (std::size_t k = 0; k < tris.size(); ++k) {
        const auto& st = tris[k];
        tb::ClipTriangle ct;
        for (std::size_t i = 0; i < 3; ++i)
            ct[i] = {static_cast<double>(st.clip[i][0]), static_cast<double>(st.clip[i][1]),
                     static_cast<double>(st.clip[i][3])};
        const auto& v = s.draw_list.draws[st.draw].state.viewport;
        const tb::Viewport vp{v.x, v.y, v.width, v.height};
        tb::Trace t = bounded_trace(run);
        merge_max(run.raster, tb::homogeneous_rasterize(ct, vp, w, h, true, &t));
        append_trace(run, t, tris.size() > 1 ? "triangle " + std::to_string(k) + ": " : "");
        inputs.push_back({ct, vp});
    }
    run.notes.push_back(
        "Olano and Greer's rasterizer evaluates the three edge functions of the adjugate of the "
        "vertices' homogeneous matrix at each pixel centre and never divides by w, so a "
        "triangle crossing w = 0 needs no clipping; GL clips it against the near plane first. "
        "The two differ where a centre sees the part of the triangle between the eye and the "
        "near plane, or, without the w test, the external triangle behind the eye.");
    constexpr double kNearW = 1.0 / 256.0;
    run.reason = [inputs](int x, int y, double a, bool gl) -> std::string {
        for (const auto& [ct, vp] : inputs) {
            const auto d = tb::explain_difference(ct, vp, kNearW, x, y);
            if (d != tb::HomogeneousDifference::Unexplained) {
                return std::string(tb::to_string(d)) + " (" +
                       (a > 0.0 ? "the homogeneous rasterizer lights it" : "GL lights it") + ").";
            }
        }
        return std::string("GL snaps the clipped vertices to 1/256 pixel and clips at z = -w; ") +
               (gl ? "GL lights it, the exact rasterizer does not."
                   : "the exact rasterizer lights it, GL does not.");
    };
    return run;
}

// GL's own rule as a lecture shows it: each triangle snapped to 1/256 pixel, its three edge
// functions E(x, y) = c - a*x + b*y with the tie rule's +1 on the edges it owns
// (refraster/textbook/edge_functions.hpp: the reference's own setup), and each pixel of its box
// tested at its centre: covered iff all three are positive. A step a pixel: the three values, and
// which edge a centre lies on and whether the rule gives it the pixel.
Run run_half_space(const Scene& s, int w, int h) {
    const auto tris = scene_triangles(s);
    if (tris.empty()) throw TeachError("the scene has no triangle draw to rasterize");
    Run run;
    run.raster = tb::Raster(w, h);
    run.pseudo_code = {
        "snap the vertices to 1/256 pixel; orient the triangle counter-clockwise (area 0: "
        "nothing to draw)",
        "set up each edge's function E = c - a x + b y; an edge that owns its ties (a left edge, "
        "or a bottom one) adds 1 to c",
        "for each pixel centre of the bounding box:", "    covered when all three E > 0"};
    const refraster::Profile profile = refraster::llvmpipe_22_3_profile();
    std::vector<bool> clipped_any(tris.size(), false);
    for (std::size_t k = 0; k < tris.size(); ++k) {
        const auto& st = tris[k];
        const auto& draw = s.draw_list.draws[st.draw];
        const auto rule = tb::gl_edge_rule(profile, draw.state, s.draw_list.target);
        std::array<std::array<std::int32_t, 2>, 3> v{};
        bool ok = true;
        for (std::size_t i = 0; i < 3; ++i) {
            const auto c = st.clip[i];
            clipped_any[k] = clipped_any[k] || c[3] <= 0.0f || std::abs(c[0]) > c[3] ||
                             std::abs(c[1]) > c[3] || std::abs(c[2]) > c[3];
            const auto p = tb::gl_snap(rule, static_cast<float>(st.t.position[i].x),
                                       static_cast<float>(st.t.position[i].y));
            if (!p) {
                ok = false;
                break;
            }
            v[i] = *p;
        }
        const std::string prefix =
            tris.size() > 1 ? "triangle " + std::to_string(k) + ": " : std::string();
        const std::string group = tris.size() > 1 ? "triangle " + std::to_string(k) : std::string();
        for (std::size_t i = 0; i < 3; ++i) {
            const auto& a = st.t.position[i];
            const auto& b = st.t.position[(i + 1) % 3];
            run.input.push_back({a.x, a.y, b.x, b.y, "edge"});
        }
        if (!ok || clipped_any[k]) {
            tb::Step step;
            step.group = group;
            step.line = 1;
            step.title = prefix +
                         "a vertex outside the view volume: GL clips this triangle "
                         "first, which this lecture version does not";
            add_step(run, std::move(step));
            continue;
        }
        const std::int64_t area =
            (std::int64_t{v[0][0]} - v[1][0]) * (std::int64_t{v[2][1]} - v[0][1]) -
            (std::int64_t{v[2][0]} - v[0][0]) * (std::int64_t{v[0][1]} - v[1][1]);
        tb::Step head;
        head.group = group;
        head.line = 1;
        head.title = prefix + "snapped to 1/256 pixel (pixel centre at 0): (" +
                     std::to_string(v[0][0]) + ", " + std::to_string(v[0][1]) + ") (" +
                     std::to_string(v[1][0]) + ", " + std::to_string(v[1][1]) + ") (" +
                     std::to_string(v[2][0]) + ", " + std::to_string(v[2][1]) + "), area " +
                     std::to_string(area);
        if (area == 0) {
            head.title += ": zero area, nothing drawn";
            add_step(run, std::move(head));
            continue;
        }
        if (area < 0) std::swap(v[0], v[1]);  // setup's orientation: counter-clockwise
        head.line = 2;
        std::array<tb::GlEdgeFunction, 3> e;
        for (std::size_t i = 0; i < 3; ++i) {
            const auto& p = v[i];
            const auto& q = v[(i + 1) % 3];
            e[i] = tb::gl_edge_function(rule, p, q);
            // E = c - a x + b y, written with its signs merged ("1 + 2816 x - 2816 y"), x and y
            // in 1/256 px from the pixel centre's grid.
            const auto term = [](std::int64_t coefficient, const char* var) {
                return std::string(coefficient < 0 ? " - " : " + ") +
                       std::to_string(coefficient < 0 ? -coefficient : coefficient) + " " + var;
            };
            head.state.push_back(
                {"E" + std::to_string(i),
                 std::to_string(e[i].c) + term(-std::int64_t{e[i].a}, "x") +
                     term(std::int64_t{e[i].b}, "y") +
                     " (x, y in 1/256 px, pixel (i, j) at (256 i, 256 j); inside where E > 0" +
                     (e[i].owns_ties ? "; owns its ties: c carries +1)" : ")")});
        }
        add_step(run, std::move(head));
        int x0 = std::numeric_limits<int>::max(), x1 = std::numeric_limits<int>::min();
        int y0 = x0, y1 = x1;
        for (const auto& p : v) {
            x0 = std::min(x0, p[0] >> 8);
            x1 = std::max(x1, (p[0] >> 8) + 1);
            y0 = std::min(y0, p[1] >> 8);
            y1 = std::max(y1, (p[1] >> 8) + 1);
        }
        for (int y = std::max(0, y0); y <= std::min(h - 1, y1); ++y) {
            for (int x = std::max(0, x0); x <= std::min(w - 1, x1); ++x) {
                bool in = true;
                for (std::size_t i = 0; i < 3; ++i)
                    in = in && e[i].at(x, y, rule.subpixel_bits) > 0;
                if (in) run.raster.set(x, y, 1.0);
                // The step, when the run still records: past the bounds only counted, so that
                // a large box costs no memory.
                if (!room_for_step(run)) {
                    ++run.omitted;
                    continue;
                }
                tb::Step step;
                step.group = group;
                step.line = 4;
                std::string ties;
                for (std::size_t i = 0; i < 3; ++i) {
                    const std::int64_t value = e[i].at(x, y, rule.subpixel_bits);
                    const std::int64_t bare = value - (e[i].owns_ties ? 1 : 0);
                    // The value with the tie rule's bias shown apart ("0 + 1 (tie bias) = 1"),
                    // so that a centre on an owned edge does not read as a plain 1.
                    step.state.push_back(
                        {"E" + std::to_string(i) + " here",
                         e[i].owns_ties
                             ? std::to_string(bare) + " + 1 (tie bias) = " + std::to_string(value)
                             : std::to_string(value)});
                    if (bare == 0) {
                        ties += " centre on edge " + std::to_string(i) + ", which " +
                                (e[i].owns_ties ? "owns" : "does not own") + " it;";
                    }
                }
                step.title = prefix + "pixel " + pixel_text(x, y) + ": " +
                             (in ? "all three positive: covered" : "not covered") +
                             (ties.empty() ? "" : " (" + ties.substr(1, ties.size() - 2) + ")");
                step.pixels.push_back({x, y, in ? 1.0 : 0.0});
                add_step(run, std::move(step));
            }
        }
    }
    run.notes.push_back(
        "This is GL's rule itself, written as a lecture writes it: the edge functions of the "
        "snapped triangle, positive inside, evaluated at every pixel centre of its box, with the "
        "tie rule's +1 on the edges that own the centres on them (left edges, and bottom edges "
        "for horizontal ones). It agrees with GL on every triangle that needs no clipping.");
    run.reason = [clipped_any](int x, int y, double a, bool gl) -> std::string {
        (void)x;
        (void)y;
        const bool clipped =
            std::find(clipped_any.begin(), clipped_any.end(), true) != clipped_any.end();
        if (clipped) {
            return std::string(
                       "a triangle of the scene has a vertex outside the view volume: GL "
                       "clips it first (new vertices on the clip planes), which the "
                       "lecture version skips; ") +
                   (gl ? "GL lights it." : "the lecture version lights it.");
        }
        return std::string("GL's draw order, culling, depth test or scissor decides it: ") +
               (a > 0.0 ? "the edge functions cover the centre" : "GL lights it") + ".";
    };
    return run;
}

std::array<std::uint8_t, 4> gl_rgba_at(const refraster::Framebuffer& fb, std::size_t i) {
    if (fb.color_format == refraster::ColorFormat::Rgba8) {
        return {fb.color8[4 * i], fb.color8[4 * i + 1], fb.color8[4 * i + 2], fb.color8[4 * i + 3]};
    }
    std::array<std::uint8_t, 4> c{};
    for (std::size_t k = 0; k < 4; ++k) {
        const float f = std::clamp(fb.color32f[4 * i + k], 0.0f, 1.0f);
        c[k] = static_cast<std::uint8_t>(std::lround(f * 255.0f));
    }
    return c;
}

}  // namespace

TeachResult teach(const Scene& scene, std::string_view algorithm,
                  const refraster::Framebuffer& gl) {
    const auto& all = teach_algorithms();
    const auto info = std::find_if(
        all.begin(), all.end(), [&](const TeachAlgorithmInfo& i) { return i.name == algorithm; });
    if (info == all.end()) throw TeachError("unknown algorithm \"" + std::string(algorithm) + "\"");
    const int w = static_cast<int>(scene.draw_list.target.width);
    const int h = static_cast<int>(scene.draw_list.target.height);
    check_teach_input(scene, algorithm);
    Run run;
    if (algorithm == "dda" || algorithm == "bresenham" || algorithm == "midpoint" ||
        algorithm == "wu") {
        run = run_lines(scene, algorithm, w, h);
    } else if (algorithm == "circle") {
        run = run_circle(scene, w, h);
    } else if (algorithm == "scanline-evenodd" || algorithm == "scanline-nonzero") {
        run = run_scanline(
            scene, algorithm == "scanline-evenodd" ? tb::FillRule::EvenOdd : tb::FillRule::NonZero,
            w, h);
    } else if (algorithm == "flood4" || algorithm == "flood8") {
        run = run_flood(scene, algorithm == "flood8", w, h);
    } else if (algorithm == "ear-clipping" || algorithm == "trapezoids") {
        run = run_triangulation(scene, algorithm == "ear-clipping", w, h);
    } else if (algorithm == "half-space") {
        run = run_half_space(scene, w, h);
    } else if (algorithm == "painter") {
        run = run_painter(scene, gl, w, h);
    } else {
        run = run_homogeneous(scene, w, h);
    }

    TeachResult r;
    r.algorithm = std::string(algorithm);
    r.title = std::string(info->title);
    r.width = w;
    r.height = h;
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    r.algorithm_rgba.resize(4 * n);
    r.gl_rgba.resize(4 * n);
    r.gl_lit.resize(n);
    int only_algorithm = 0, only_gl = 0, partial = 0, other = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                  static_cast<std::size_t>(x);
            const double a = std::clamp(run.raster.at(x, y), 0.0, 1.0);
            std::array<std::uint8_t, 4> c{};
            if (!run.colors.empty() && run.colors[i][3] != 0) {
                c = run.colors[i];
            } else {
                const auto v = static_cast<std::uint8_t>(std::lround(a * 255.0));
                c = {v, v, v, 255};
            }
            std::copy(c.begin(), c.end(), r.algorithm_rgba.begin() + static_cast<long>(4 * i));
            const auto g = gl_rgba_at(gl, i);
            std::copy(g.begin(), g.end(), r.gl_rgba.begin() + static_cast<long>(4 * i));
            const bool lit = !gl.owner.empty() ? gl.owner[i] != 0 : g != gl_rgba_at(gl, 0);
            r.gl_lit[i] = lit;
            const bool differs =
                (a > 0.0) != lit || (a > 0.0 && a < 1.0) || (run.differs && run.differs(x, y));
            if (!differs) continue;
            if (a > 0.0 && a < 1.0) {
                ++partial;
            } else if (a > 0.0 && lit) {
                ++other;
            } else if (a > 0.0) {
                ++only_algorithm;
            } else {
                ++only_gl;
            }
            r.differences.push_back({x, y, a, lit, run.reason(x, y, a, lit)});
        }
    }
    if (run.omitted > 0) {
        // The record's end: what was not kept, in a last step (not counted in the bounds).
        tb::Step last;
        last.title = std::to_string(run.omitted) + " more step" + (run.omitted == 1 ? "" : "s") +
                     " not recorded";
        last.state.push_back({"recorded", std::to_string(run.steps.size()) + " steps"});
        last.state.push_back({"bounds", std::to_string(TeachLimits::kMaxSteps) + " steps, " +
                                            std::to_string(TeachLimits::kMaxStepPixels) +
                                            " pixel marks, " +
                                            std::to_string(TeachLimits::kMaxStepSegments) +
                                            " overlay segments (docs/limits.md)"});
        run.steps.push_back(std::move(last));
        run.notes.push_back("The page records the first " + std::to_string(run.steps.size() - 1) +
                            " steps of the algorithm and counts the " +
                            std::to_string(run.omitted) +
                            " after them (docs/limits.md, \"Teaching pages\"); the images and "
                            "the differences are the whole run's.");
    }
    r.omitted_steps = run.omitted;
    r.input = std::move(run.input);
    r.steps = std::move(run.steps);
    r.pseudo_code = std::move(run.pseudo_code);
    r.notes = std::move(run.notes);
    std::ostringstream sum;
    sum << r.differences.size() << " pixel" << (r.differences.size() == 1 ? "" : "s")
        << " differ: " << only_algorithm << " lit by " << r.title << " only, " << only_gl
        << " by GL only";
    if (partial > 0) sum << ", " << partial << " with partial weights";
    if (other > 0) sum << ", " << other << " lit by both, another primitive seen";
    r.summary = sum.str();
    return r;
}

TeachResult teach_beside(const TeachResult& a, const TeachResult& b) {
    TeachResult r;
    r.algorithm = a.algorithm;
    r.title = a.title;
    r.beside = b.title;
    r.width = a.width;
    r.height = a.height;
    r.algorithm_rgba = a.algorithm_rgba;
    r.gl_rgba = b.algorithm_rgba;
    r.input = a.input;
    r.steps = a.steps;
    r.pseudo_code = a.pseudo_code;
    r.omitted_steps = a.omitted_steps;
    for (const auto& n : a.notes) r.notes.push_back(a.title + ": " + n);
    for (const auto& n : b.notes) r.notes.push_back(b.title + ": " + n);
    // Each run's reason at a pixel where it parts from GL.
    std::map<std::pair<int, int>, const TeachDifference*> by_a, by_b;
    for (const auto& d : a.differences) by_a[{d.x, d.y}] = &d;
    for (const auto& d : b.differences) by_b[{d.x, d.y}] = &d;
    const auto why = [](const TeachResult& t, const auto& by, int x, int y) {
        const auto it = by.find(std::pair{x, y});
        std::string reason = it == by.end() ? std::string("as GL") : it->second->reason;
        if (!reason.empty() && reason.back() == '.') reason.pop_back();
        return t.title + ": " + reason;
    };
    const std::size_t n = static_cast<std::size_t>(a.width) * static_cast<std::size_t>(a.height);
    r.gl_lit.resize(n);
    int only_a = 0, only_b = 0, both = 0;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(a.width) +
                                  static_cast<std::size_t>(x);
            const auto lit = [&](const std::vector<std::uint8_t>& rgba) {
                return rgba[4 * i] != 0 || rgba[4 * i + 1] != 0 || rgba[4 * i + 2] != 0;
            };
            const bool la = lit(a.algorithm_rgba), lb = lit(b.algorithm_rgba);
            r.gl_lit[i] = lb;
            if (std::equal(a.algorithm_rgba.begin() + static_cast<long>(4 * i),
                           a.algorithm_rgba.begin() + static_cast<long>(4 * i + 4),
                           b.algorithm_rgba.begin() + static_cast<long>(4 * i)))
                continue;
            (la && lb ? both : la ? only_a : only_b) += 1;
            const double weight = std::max({a.algorithm_rgba[4 * i], a.algorithm_rgba[4 * i + 1],
                                            a.algorithm_rgba[4 * i + 2]}) /
                                  255.0;
            r.differences.push_back(
                {x, y, weight, lb, why(a, by_a, x, y) + "; " + why(b, by_b, x, y) + "."});
        }
    }
    std::ostringstream sum;
    sum << r.differences.size() << " pixel" << (r.differences.size() == 1 ? "" : "s")
        << " differ: " << only_a << " lit by " << a.title << " only, " << only_b << " by "
        << b.title << " only";
    if (both > 0) sum << ", " << both << " lit by both, differently";
    r.summary = sum.str();
    return r;
}

nlohmann::json teach_json(const TeachResult& r, const Scene& scene, const std::string& scene_file,
                          const std::string& gl_source) {
    using nlohmann::json;
    json j;
    j["algorithm"] = r.algorithm;
    j["title"] = r.title;
    j["scene"] = scene.file.name;
    j["scene_file"] = scene_file;
    j["width"] = r.width;
    j["height"] = r.height;
    j["gl_source"] = gl_source;
    j["algorithm_rgba"] = r.algorithm_rgba;
    j["gl_rgba"] = r.gl_rgba;
    json diffs = json::array();
    for (const auto& d : r.differences)
        diffs.push_back({{"x", d.x},
                         {"y", d.y},
                         {"algorithm", d.algorithm},
                         {"gl", d.gl},
                         {"reason", d.reason}});
    j["differences"] = diffs;
    j["summary"] = r.summary;
    const auto segment = [](const tb::Segment& s) {
        return json{{"x0", s.x0}, {"y0", s.y0}, {"x1", s.x1}, {"y1", s.y1}, {"role", s.role}};
    };
    json input = json::array();
    for (const auto& s : r.input) input.push_back(segment(s));
    j["input"] = input;
    json steps = json::array();
    for (const auto& s : r.steps) {
        json st;
        st["title"] = s.title;
        if (!s.group.empty()) st["group"] = s.group;
        if (s.line > 0) st["line"] = s.line;
        json state = json::array();
        for (const auto& [k, v] : s.state) state.push_back(json::array({k, v}));
        st["state"] = state;
        json px = json::array();
        for (const auto& p : s.pixels) px.push_back(json::array({p.x, p.y, p.weight}));
        st["pixels"] = px;
        json ov = json::array();
        for (const auto& o : s.overlay) ov.push_back(segment(o));
        st["overlay"] = ov;
        steps.push_back(st);
    }
    j["steps"] = steps;
    j["pseudo_code"] = r.pseudo_code;
    if (!r.beside.empty()) j["beside"] = r.beside;
    j["omitted_steps"] = r.omitted_steps;
    j["notes"] = r.notes;
    return j;
}

}  // namespace harness
