#include "harness/reduce.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <stdexcept>

#include "harness/compare.hpp"
#include "harness/explain.hpp"
#include "harness/front_end.hpp"
#include "refraster/assembly.hpp"
#include "refraster/renderer.hpp"

namespace harness {

namespace {

// The primitives of a draw as vertex lists in the order the driver assembles them
// (refraster/assembly.hpp), so that a list primitive with those vertices rasterizes
// identically.
std::vector<std::vector<SceneVertex>> primitives_of(const SceneDraw& d) {
    const std::size_t n = d.indices ? d.indices->size() : d.vertices.size();
    const auto v = [&](std::size_t i) { return d.vertices[d.indices ? (*d.indices)[i] : i]; };
    const bool first = d.state.provoking_vertex == refraster::ProvokingVertex::First;
    std::vector<std::vector<SceneVertex>> out;
    if (d.primitive == refraster::PrimitiveType::Polygon) {
        // One polygon: its triangles drawn apart would lose its outline (polygon modes) and its
        // region (fill rules), so it stays whole.
        auto& prim = out.emplace_back();
        for (std::size_t i = 0; i < n; ++i) prim.push_back(v(i));
        return out;
    }
    for (const auto& elements : refraster::assemble_primitives(d.primitive, n, first)) {
        auto& prim = out.emplace_back();
        for (const auto e : elements) prim.push_back(v(e));
    }
    return out;
}

refraster::PrimitiveType list_type(refraster::PrimitiveType p) {
    using refraster::PrimitiveType;
    switch (p) {
        case PrimitiveType::Points:
            return PrimitiveType::Points;
        case PrimitiveType::Lines:
        case PrimitiveType::LineStrip:
        case PrimitiveType::LineLoop:
            return PrimitiveType::Lines;
        case PrimitiveType::Polygon:
            return PrimitiveType::Polygon;
        default:
            return PrimitiveType::Triangles;
    }
}

// The working form: every draw's primitives, each removable on its own.
struct Piece {
    std::size_t draw;
    std::vector<SceneVertex> vertices;
};

SceneFile assemble(const SceneFile& base, const std::vector<Piece>& pieces) {
    SceneFile s = base;
    s.draws.clear();
    std::size_t current = SIZE_MAX;
    for (const auto& p : pieces) {
        if (p.draw != current) {
            SceneDraw d = base.draws[p.draw];
            d.primitive = list_type(d.primitive);
            d.vertices.clear();
            d.indices.reset();
            s.draws.push_back(d);
            current = p.draw;
        }
        auto& v = s.draws.back().vertices;
        v.insert(v.end(), p.vertices.begin(), p.vertices.end());
    }
    return s;
}

class Oracle {
  public:
    Oracle(const refraster::Profile& p, Backend& b, const std::string& label,
           const MismatchToKeep& keep, double timeout_seconds)
        : profile_(p), backend_(b), label_(label), keep_(keep), timeout_seconds_(timeout_seconds) {}

    // The mismatch signature, "class: rule", or "" when the scene has no mismatch of the kind
    // kept (or cannot be rendered).
    std::string signature(const SceneFile& f) {
        ++renders;
        Scene scene;
        scene.path = label_;
        scene.file = f;
        try {
            scene.draw_list = run_front_end(f, label_);
        } catch (const SceneError&) {
            return "";
        }
        try {
            Explainer ex(scene, profile_, &backend_, -1, timeout_seconds_);
            const auto& ref = ex.reference_image();
            std::optional<std::array<int, 2>> at = keep_.pixel;
            if (at) {
                const auto i = ref.index(static_cast<std::uint32_t>((*at)[0]),
                                         static_cast<std::uint32_t>((*at)[1]));
                if (ex.classifier()->at(i).cls == PixelClass::Equal) return "";
            } else {
                // The pixel of largest difference (colour first, then depth), of the kept class.
                std::pair<std::uint64_t, std::uint64_t> worst{0, 0};
                for (std::uint32_t y = 0; y < ref.height; ++y) {
                    for (std::uint32_t x = 0; x < ref.width; ++x) {
                        const auto px = ex.classifier()->at(ref.index(x, y));
                        if (px.cls == PixelClass::Equal || !of_class(px.cls)) continue;
                        const std::pair<std::uint64_t, std::uint64_t> d{px.color_difference,
                                                                        px.depth_difference};
                        if (!at || d > worst) {
                            worst = d;
                            at = std::array<int, 2>{static_cast<int>(x), static_cast<int>(y)};
                        }
                    }
                }
                if (!at) return "";
            }
            const auto e = ex.explain((*at)[0], (*at)[1]);
            if (!keep_.difference.empty() && e.difference != keep_.difference) return "";
            return e.difference + ": " + e.rule;
        } catch (const refraster::RenderStopped&) {
            throw;  // the reference ran out of time: the reduction ends (a backend failure)
        } catch (const std::runtime_error&) {
            return "";
        }
    }
    int renders = 0;

  private:
    bool of_class(PixelClass c) const {
        if (keep_.difference.empty()) return true;
        const bool coverage =
            c == PixelClass::Missing || c == PixelClass::Extra || c == PixelClass::Coverage;
        return keep_.difference == "coverage" ? coverage
               : keep_.difference == "colour" ? c == PixelClass::ColorOnly
                                              : c == PixelClass::DepthOnly;
    }

    const refraster::Profile& profile_;
    Backend& backend_;
    std::string label_;
    MismatchToKeep keep_;
    double timeout_seconds_ = 0.0;
};

}  // namespace

ReduceResult reduce_scene(const SceneFile& scene, const std::string& label,
                          const refraster::Profile& profile, Backend& backend, std::ostream& log,
                          const MismatchToKeep& keep, double timeout_seconds) {
    Oracle oracle(profile, backend, label, keep, timeout_seconds);
    ReduceResult r;
    r.signature = oracle.signature(scene);
    if (r.signature.empty()) {
        throw std::runtime_error(label +
                                 (keep.pixel || !keep.difference.empty()
                                      ? ": no mismatch of the kind asked for; nothing to reduce"
                                      : ": the scene matches the backend; nothing to reduce"));
    }
    // "class: rule": the kind of difference and the rule explain names for it; every step
    // keeps both.
    const auto colon = r.signature.find(": ");
    log << "signature: " << r.signature << " (a " << r.signature.substr(0, colon)
        << " difference that explain puts down to "
        << (colon == std::string::npos ? std::string("no rule") : r.signature.substr(colon + 2))
        << "; every step keeps it)\n";

    std::vector<Piece> pieces;
    for (std::size_t d = 0; d < scene.draws.size(); ++d) {
        for (auto& p : primitives_of(scene.draws[d])) pieces.push_back({d, std::move(p)});
    }
    r.primitives_before = pieces.size();
    const auto holds = [&](const std::vector<Piece>& ps) {
        return !ps.empty() && oracle.signature(assemble(scene, ps)) == r.signature;
    };
    if (!holds(pieces)) {
        throw std::runtime_error(label +
                                 ": the signature changes when draws become lists of primitives");
    }
    log << "step 0: " << pieces.size() << " primitives in " << scene.draws.size() << " draws\n";

    // ddmin over primitives: try dropping each of n chunks, then keeping only one chunk.
    std::size_t n = 2;
    int step = 0;
    while (pieces.size() >= 2) {
        const std::size_t chunk = (pieces.size() + n - 1) / n;
        bool reduced = false;
        for (std::size_t start = 0; start < pieces.size() && !reduced; start += chunk) {
            const std::size_t end = std::min(pieces.size(), start + chunk);
            std::vector<Piece> only(pieces.begin() + static_cast<std::ptrdiff_t>(start),
                                    pieces.begin() + static_cast<std::ptrdiff_t>(end));
            if (only.size() < pieces.size() && holds(only)) {
                pieces = std::move(only);
                n = 2;
                reduced = true;
                break;
            }
            std::vector<Piece> rest;
            rest.insert(rest.end(), pieces.begin(),
                        pieces.begin() + static_cast<std::ptrdiff_t>(start));
            rest.insert(rest.end(), pieces.begin() + static_cast<std::ptrdiff_t>(end),
                        pieces.end());
            if (holds(rest)) {
                pieces = std::move(rest);
                n = std::max<std::size_t>(n - 1, 2);
                reduced = true;
            }
        }
        if (reduced) {
            log << "step " << ++step << ": " << pieces.size() << " primitives\n" << std::flush;
            continue;
        }
        if (n >= pieces.size()) break;
        n = std::min(pieces.size(), n * 2);
    }

    // Coordinates to coarser binary grids, one vertex coordinate at a time.
    SceneFile best = assemble(scene, pieces);
    for (std::size_t di = 0; di < best.draws.size(); ++di) {
        auto& d = best.draws[di];
        for (std::size_t vi = 0; vi < d.vertices.size(); ++vi) {
            auto& v = d.vertices[vi];
            for (std::uint32_t k = 0; k < v.position_size; ++k) {
                for (float grid : {1.0f, 0.5f, 0.25f, 1.0f / 16, 1.0f / 256}) {
                    const float old = v.position[k];
                    const float rounded = std::round(old / grid) * grid;
                    if (rounded == old) break;
                    v.position[k] = rounded;
                    if (oracle.signature(best) == r.signature) {
                        log << "step " << ++step << ": draws[" << di << "].vertices[" << vi
                            << "].position "
                            << "xyzw"[k & 3] << " " << old << " -> " << rounded
                            << " (to a multiple of " << grid << ")\n";
                        break;
                    }
                    v.position[k] = old;
                }
            }
        }
    }
    r.scene = best;
    r.primitives_after = pieces.size();
    r.renders = oracle.renders;
    log << "done: " << r.primitives_before << " -> " << r.primitives_after << " primitives in "
        << r.renders << " renders\n";
    return r;
}

}  // namespace harness
