// render(): clears the target, checks what the profile can draw, and runs every draw through
// the pipeline (pipeline.hpp, the stage order) with the observer the options ask for.
#include "refraster/renderer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <optional>
#include <thread>

#include "common/stop.hpp"
#include "models/llvmpipe/texture.hpp"
#include "pipeline.hpp"
#include "stages/observer.hpp"
#include "stages/output_merge.hpp"
#include "stages/polygon_draw.hpp"
#include "stages/rules.hpp"
#include "trace/trace_observer.hpp"

namespace refraster {

std::size_t primitive_count(PrimitiveType p, std::size_t n) {
    switch (p) {
        case PrimitiveType::Points:
            return n;
        case PrimitiveType::Lines:
            return n / 2;
        case PrimitiveType::LineStrip:
            return n >= 2 ? n - 1 : 0;
        case PrimitiveType::LineLoop:
            return n >= 2 ? n : 0;
        case PrimitiveType::Triangles:
            return n / 3;
        case PrimitiveType::TriangleStrip:
        case PrimitiveType::TriangleFan:
        case PrimitiveType::Polygon:
            return n >= 3 ? n - 2 : 0;
    }
    return 0;
}

bool host_has_fma() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init();
    return __builtin_cpu_supports("fma");
#else
    return false;
#endif
}

namespace {

// glClearDepth stores RNE(double(z) * (2^bits - 1)), computed in double: measured for z24
// (docs/precision.md, "Depth"), the same packing for z16 (util_pack_z in
// gallium/auxiliary/util/u_pack_color.h). z32f stores the float itself.
std::uint32_t clear_depth_value(DepthFormat f, float z, ClearPrecision precision) {
    if (precision == ClearPrecision::Float) return detail::quantise_depth(z, f);
    return detail::quantise_depth(static_cast<double>(z), f);
}

// Clears the whole target (scissor off, every mask on): unorm8 colours through
// float_to_ubyte as util_pack_color does for R8G8B8A8_UNORM, floats as given.
// `pattern` (one pixel) repeated over `buffer`, whose size is a whole number of pixels: the
// first pixel written, then the filled part copied after itself, doubling each time (a few
// block copies instead of a loop of one pixel at a time).
template <class T, std::size_t N>
void fill_pattern(T* buffer, std::size_t size, const std::array<T, N>& pattern) {
    if (size == 0) return;
    std::memcpy(buffer, pattern.data(), sizeof(T) * N);
    for (std::size_t done = N; done < size;) {
        const std::size_t chunk = std::min(done, size - done);
        std::memcpy(buffer + done, buffer, sizeof(T) * chunk);
        done += chunk;
    }
}

RenderOutcome clear(const DrawList& list, Framebuffer& out, ClearPrecision precision) {
    const auto& c = list.clear.color;
    if (list.target.color == ColorFormat::Rgba8) {
        std::array<std::uint8_t, 4> bytes{};
        for (std::size_t k = 0; k < 4; ++k) bytes[k] = detail::clear_to_unorm8(c[k]);
        fill_pattern(out.color8.data(), out.color8.size(), bytes);
    } else {
        fill_pattern(out.color32f.data(), out.color32f.size(), c);
    }
    fill_pattern(out.depth.data(), out.depth.size(),
                 std::array<std::uint32_t, 1>{
                     clear_depth_value(list.target.depth, list.clear.depth, precision)});
    return {};
}

bool is_triangle(PrimitiveType p) {
    return p >= PrimitiveType::Triangles;
}

std::string unsupported(const Draw& d, const Target& target, const Profile& profile) {
    if (auto why = detail::fill_rule_unsupported(d, target, profile); !why.empty()) return why;
    if (detail::draw_model(profile, d) == CoverageModel::Scanline) {
        // softpipe has no multisampling (GL_MAX_SAMPLES is 0).
        if (target.samples != 1) return "the scanline (softpipe) rules have no multisampling";
        return {};
    }
    if (profile.model != CoverageModel::Exact) return {};
    if (d.state.texture) return "the exact profile draws untextured primitives only";
    if (!is_triangle(d.primitive) || d.state.polygon_mode != PolygonMode::Fill) {
        return "the exact profile covers filled triangles only";
    }
    if (target.samples != 1) return "the exact profile covers single-sample targets only";
    return {};
}

// What a fill rule decided at the traced pixel (polygon_draw.hpp): the winding number at the
// nudged centre on the first of the draw's traced primitives, and on each of its triangles
// that covers the pixel whether the cover pass let it draw there (only the first may, and
// only inside the rule's region).
void note_fill_rule(const detail::DrawContext& ctx, PixelTrace& trace, std::size_t first,
                    bool inside) {
    if (first >= trace.primitives.size()) return;
    const FillRule rule = *ctx.draw.state.fill_rule;
    const auto contours = detail::fill_contours(ctx);
    std::string note = "fill rule " + std::string(to_string(rule)) + ": ";
    if (contours) {
        const std::int64_t w =
            detail::winding_at(*contours, ctx.params.tie_rule, ctx.params.bits, trace.x, trace.y);
        const auto [sx, sy] = detail::nudge_of(ctx.params.tie_rule);
        note += "winding number " + std::to_string(w) + " at the centre nudged by (" +
                (sx > 0 ? "+e" : "-e") + ", " + (sy > 0 ? "+e^2" : "-e^2") + ") over " +
                (contours->size() == 1
                     ? std::string("the polygon's outline")
                     : std::to_string(contours->size()) + " clipped triangles' outlines") +
                ": ";
    }
    note += inside ? "inside, drawn by the first of the polygon's triangles to cover it"
                   : "outside (or beyond the scissor): not drawn";
    trace.primitives[first].note =
        trace.primitives[first].note.empty() ? note : trace.primitives[first].note + "; " + note;
    bool taken = !inside;
    for (std::size_t k = first; k < trace.primitives.size(); ++k) {
        for (auto& st : trace.primitives[k].setups) {
            if (!st.covered) continue;
            if (!taken) {
                taken = true;
                continue;
            }
            st.has_fragment = false;
            st.coverage_note = inside ? "the fill rule's cover pass: an earlier triangle of the "
                                        "polygon took this pixel, so this one does not draw it"
                                      : "the fill rule leaves this pixel out: not drawn";
        }
    }
}

}  // namespace

std::vector<TextureImage> texture_levels(const Texture& texture, const Profile& profile) {
    const FmaMode m = profile.gl.viewport_fma;
    return detail::resolve_levels(texture,
                                  m == FmaMode::On || (m == FmaMode::Auto && host_has_fma()),
                                  profile.gl.texture_filtering);
}

RenderOutcome render(const DrawList& list, const RenderOptions& options, Framebuffer& out) {
    const std::uint32_t samples = list.target.samples;
    if (samples != 1 && samples != 4) {
        return {RenderStatus::NotSupported,
                "targets of " + std::to_string(samples) + " samples (1 and 4 exist)"};
    }
    if (samples != 1 && options.profile.model == CoverageModel::Scanline) {
        // softpipe has no multisampling (GL_MAX_SAMPLES is 0).
        return {RenderStatus::NotSupported, "the scanline (softpipe) profile has no multisampling"};
    }
    out = Framebuffer(list.target.width, list.target.height, list.target.color, list.target.depth,
                      samples);
    if (options.record_owners) out.owner.assign(out.pixel_count() * samples, 0);
    if (auto c = clear(list, out, options.profile.gl.depth_clear); c.status != RenderStatus::Ok)
        return c;
    PixelTrace* trace = options.trace;
    if (trace != nullptr) {
        trace->profile = options.profile.name;
        trace->primitives.clear();
    }
    for (std::size_t i = 0; i < list.draws.size(); ++i) {
        const Draw& d = list.draws[i];
        if (primitive_count(d.primitive, d.element_count()) == 0) continue;
        if (auto why = unsupported(d, list.target, options.profile); !why.empty()) {
            return {RenderStatus::NotSupported, why + " (draws[" + std::to_string(i) + "])"};
        }
    }
    const FmaMode fma_mode = options.profile.gl.viewport_fma;
    const bool fma = fma_mode == FmaMode::On || (fma_mode == FmaMode::Auto && host_has_fma());
    // A trace records what the model computes; every path computes the same.
    // Truncating conversions exist on the Model path only.
    const bool model_only = options.profile.gl.depth_rounding == Rounding::Truncate ||
                            options.profile.gl.color_rounding == Rounding::Truncate;
    const KernelPath kernels =
        trace != nullptr || model_only ? KernelPath::Model : resolve_kernel_path(options.kernels);
    // The scanline model's fast path rounds depth either way; it needs colours rounded to
    // nearest, under which a byte survives softpipe's tile cache (load, then write-back) as it
    // is (softpipe_lazy_tiles.hpp).
    const KernelPath scanline_kernels =
        trace != nullptr || options.profile.gl.color_rounding == Rounding::Truncate
            ? KernelPath::Model
            : resolve_kernel_path(options.kernels);
    // Threads only for the paths that shade row blocks; a traced render stays on one.
    unsigned threads =
        options.threads == 0 ? std::max(1u, std::thread::hardware_concurrency()) : options.threads;
    if (kernels == KernelPath::Model || options.stop_after != RenderStage::Fragment) threads = 1;
    // Started before anything costly (the texture levels, the threads), so that it bounds them.
    const detail::StopSignal stop(options.deadline, options.stop);
    stop.throw_if_requested();
    std::optional<detail::BandWorkers> workers;
    if (threads > 1) workers.emplace(threads);
    detail::ModelStates states(list, options.profile, out, scanline_kernels != KernelPath::Model);
    RenderOutcome outcome;
    for (std::size_t i = 0; i < list.draws.size(); ++i) {
        const Draw& d = list.draws[i];
        if (primitive_count(d.primitive, d.element_count()) == 0) continue;
        stop.throw_if_requested();
        const CoverageModel model = detail::draw_model(options.profile, d);
        detail::DrawContext ctx{i,
                                d,
                                list.target,
                                options.profile,
                                detail::setup_params(options.profile, d.state, list.target),
                                fma,
                                !out.owner.empty(),
                                model == CoverageModel::Scanline ? scanline_kernels : kernels,
                                workers ? &*workers : nullptr,
                                model};
        ctx.stop = &stop;
        // A fill rule: the stencil pass's pixels, taken by the cover pass (polygon_draw.hpp).
        std::optional<detail::FillMask> fill;
        if (d.state.fill_rule) {
            fill = detail::fill_rule_mask(ctx);
            if (!fill) {
                return {RenderStatus::NotSupported,
                        "a fill rule's vertex outside the snapped range (draws[" +
                            std::to_string(i) + "])"};
            }
            ctx.fill = &*fill;
        }
        if (trace != nullptr) {
            const std::size_t traced_before = trace->primitives.size();
            const bool inside = fill && fill->test(trace->x, trace->y);
            detail::TraceObserver obs(*trace, ctx.params.multisample);
            outcome.fragments += detail::run_draw(ctx, states, obs, options.stop_after, out);
            if (fill) note_fill_rule(ctx, *trace, traced_before, inside);
        } else {
            detail::NoObserver obs;
            outcome.fragments += detail::run_draw(ctx, states, obs, options.stop_after, out);
        }
    }
    states.finish_render();
    if (trace != nullptr && trace->x >= 0 && trace->y >= 0 &&
        static_cast<std::uint32_t>(trace->x) < out.width &&
        static_cast<std::uint32_t>(trace->y) < out.height) {
        const auto sample =
            static_cast<std::uint32_t>(std::clamp(trace->sample, 0, 3)) % out.samples;
        const std::size_t i = 4 * out.sample_index(static_cast<std::uint32_t>(trace->x),
                                                   static_cast<std::uint32_t>(trace->y), sample);
        for (std::size_t k = 0; k < 4; ++k) {
            trace->final_color[k] =
                out.color_format == ColorFormat::Rgba8 ? out.color8[i + k] : out.color32f[i + k];
        }
    }
    return outcome;
}

}  // namespace refraster
