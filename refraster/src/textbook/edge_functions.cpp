// edge_functions.cpp: GL's edge functions for teaching (edge_functions.hpp), computed by the
// reference's own setup so that a lecture shows exactly the values that decide coverage.
#include "refraster/textbook/edge_functions.hpp"

#include "stages/edge_rules.hpp"

namespace refraster::textbook {

namespace {

// The setup parameters the snap and the edge functions read.
detail::SetupParams params_of(const GlEdgeRule& rule) {
    detail::SetupParams p;
    p.bits = rule.subpixel_bits;
    p.rounding = rule.snap_rounding;
    p.pixel_center_offset = rule.pixel_center_offset;
    p.tie_rule = rule.tie_rule;
    return p;
}

}  // namespace

GlEdgeRule gl_edge_rule(const Profile& profile, const DrawState& state, const Target& target) {
    const detail::SetupParams p = detail::setup_params(profile, state, target);
    return {p.bits, p.rounding, p.pixel_center_offset, p.tie_rule};
}

std::optional<std::array<std::int32_t, 2>> gl_snap(const GlEdgeRule& rule, float x, float y) {
    return detail::snap_position(x, y, params_of(rule));
}

std::int64_t GlEdgeFunction::at(int px, int py, int subpixel_bits) const {
    return detail::EdgeFunction{a, b, c, owns_ties}.at(px, py, subpixel_bits);
}

GlEdgeFunction gl_edge_function(const GlEdgeRule& rule, const std::array<std::int32_t, 2>& from,
                                const std::array<std::int32_t, 2>& to) {
    const detail::EdgeFunction e = detail::make_edge(from[0], from[1], to[0], to[1], rule.tie_rule);
    return {e.a, e.b, e.c, e.owns_ties};
}

}  // namespace refraster::textbook
