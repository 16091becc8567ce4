#include "refraster/textbook/ear_clipping.hpp"

#include <cstdint>
#include <string>

#include "snap.hpp"

namespace refraster::textbook {

namespace {

using detail::SnappedPoint;

// A step shows the first kShown entries of a list and the count of the rest, so that a step
// costs the same on any polygon and the trace grows linearly with its steps.
constexpr std::size_t kShown = 24;

std::string index_list(const std::vector<int>& v) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size() && i < kShown; ++i) {
        if (i > 0) s += ", ";
        s += "v" + std::to_string(v[i]);
    }
    if (v.size() > kShown) s += ", ... " + std::to_string(v.size() - kShown) + " more";
    return s + "]";
}

}  // namespace

EarClipResult ear_clip(const std::vector<Point2>& polygon, Trace* trace) {
    EarClipResult out;
    const std::size_t n = polygon.size();
    if (trace != nullptr) {
        trace->algorithm = "ear clipping";
        set_pseudo_code(trace, {"orient the polygon counter-clockwise; remaining = every vertex",
                                "while more than 3 vertices remain:",
                                ("    find the next vertex v whose corner (u, v, w) is convex and "
                                 "holds no other vertex: an ear"),
                                "    cut the triangle (u, v, w) off; remove v",
                                "    if no vertex is an ear: the polygon is not simple; stop",
                                "the last three vertices are the last triangle"});
        add_outline(trace->input, polygon);
        begin_part(trace, "polygon");
    }
    if (n < 3) return out;
    std::vector<SnappedPoint> p(n);
    for (std::size_t i = 0; i < n; ++i)
        p[i] = {detail::snap(polygon[i].x), detail::snap(polygon[i].y)};
    // The orientation: twice the shoelace area, below n * 2^46.
    std::int64_t twice_area = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const SnappedPoint a = p[i];
        const SnappedPoint b = p[(i + 1) % n];
        twice_area += a.x * b.y - b.x * a.y;
    }
    if (twice_area == 0) return out;
    const std::int64_t sense = twice_area > 0 ? 1 : -1;
    const auto turn = [&](int a, int b, int c) {
        return sense * detail::orient(p[static_cast<std::size_t>(a)],
                                      p[static_cast<std::size_t>(b)],
                                      p[static_cast<std::size_t>(c)]);
    };
    std::vector<int> remaining(n);
    for (std::size_t i = 0; i < n; ++i) remaining[i] = static_cast<int>(i);
    // Why v is not an ear, or nullptr when it is.
    const auto blocker = [&](std::size_t k, int& blocking_vertex) -> const char* {
        const std::size_t m = remaining.size();
        const int u = remaining[(k + m - 1) % m];
        const int v = remaining[k];
        const int w = remaining[(k + 1) % m];
        const std::int64_t t = turn(u, v, w);
        if (t < 0) return "reflex";
        if (t == 0) return "collinear with its neighbours";
        for (const int q : remaining) {
            if (q == u || q == v || q == w) continue;
            if (turn(u, v, q) >= 0 && turn(v, w, q) >= 0 && turn(w, u, q) >= 0) {
                blocking_vertex = q;
                return "another vertex lies in its triangle";
            }
        }
        return nullptr;
    };
    std::size_t cursor = 0;
    while (remaining.size() > 3) {
        const std::size_t m = remaining.size();
        bool cut = false;
        std::vector<std::string> rejected;  // the first kShown, when the step is recorded
        std::size_t rejected_count = 0;
        const bool recording = trace != nullptr && trace->recording();
        for (std::size_t step = 0; step < m; ++step) {
            const std::size_t k = (cursor + step) % m;
            int blocking_vertex = -1;
            const char* why = blocker(k, blocking_vertex);
            if (why != nullptr) {
                ++rejected_count;
                if (recording && rejected.size() < kShown) {
                    rejected.push_back("v" + std::to_string(remaining[k]) + ": " + why +
                                       (blocking_vertex >= 0
                                            ? " (v" + std::to_string(blocking_vertex) + ")"
                                            : std::string()));
                }
                continue;
            }
            const int u = remaining[(k + m - 1) % m];
            const int v = remaining[k];
            const int w = remaining[(k + 1) % m];
            out.triangles.push_back({u, v, w});
            if (trace != nullptr) {
                Step& s = add_step(*trace, "ear at v" + std::to_string(v) + ": cut triangle (v" +
                                               std::to_string(u) + ", v" + std::to_string(v) +
                                               ", v" + std::to_string(w) + ")");
                s.line = 4;
                s.state.push_back({"remaining", index_list(remaining)});
                std::string skipped;
                for (const std::string& r : rejected) skipped += (skipped.empty() ? "" : "; ") + r;
                if (rejected_count > rejected.size())
                    skipped +=
                        "; ... " + std::to_string(rejected_count - rejected.size()) + " more";
                s.state.push_back({"not ears before it", skipped});
                const Point2 pu = polygon[static_cast<std::size_t>(u)];
                const Point2 pv = polygon[static_cast<std::size_t>(v)];
                const Point2 pw = polygon[static_cast<std::size_t>(w)];
                s.overlay.push_back({pu.x, pu.y, pv.x, pv.y, "ear"});
                s.overlay.push_back({pv.x, pv.y, pw.x, pw.y, "ear"});
                s.overlay.push_back({pw.x, pw.y, pu.x, pu.y, "diagonal"});
            }
            remaining.erase(remaining.begin() + static_cast<std::ptrdiff_t>(k));
            cursor = k % remaining.size();
            cut = true;
            break;
        }
        if (!cut) {
            if (trace != nullptr) {
                Step& s = add_step(*trace, "no ear: the polygon is not simple");
                s.line = 5;
                s.state.push_back({"remaining", index_list(remaining)});
            }
            return out;
        }
    }
    if (turn(remaining[0], remaining[1], remaining[2]) <= 0) return out;
    out.triangles.push_back({remaining[0], remaining[1], remaining[2]});
    if (trace != nullptr) {
        Step& s = add_step(*trace, "the last triangle (v" + std::to_string(remaining[0]) + ", v" +
                                       std::to_string(remaining[1]) + ", v" +
                                       std::to_string(remaining[2]) + ")");
        s.line = 6;
        s.state.push_back({"remaining", index_list(remaining)});
        for (std::size_t i = 0; i < 3; ++i) {
            const Point2 a = polygon[static_cast<std::size_t>(remaining[i])];
            const Point2 b = polygon[static_cast<std::size_t>(remaining[(i + 1) % 3])];
            s.overlay.push_back({a.x, a.y, b.x, b.y, "ear"});
        }
    }
    out.complete = true;
    return out;
}

}  // namespace refraster::textbook
