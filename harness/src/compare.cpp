#include "harness/compare.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <cmath>
#include <sstream>

namespace harness {
namespace {

// Maps a float's bits onto integers ordered like the floats, so that the distance between two
// mapped values counts the representable floats between them (ULPs). +0 and -0 map together.
std::int64_t ordered_float(float f) {
    const auto bits = static_cast<std::int64_t>(std::bit_cast<std::uint32_t>(f));
    return bits & 0x80000000 ? -(bits & 0x7fffffff) : bits;
}

std::uint64_t ulp_distance(float a, float b) {
    if (std::isnan(a) || std::isnan(b)) {
        return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b)
                   ? 0
                   : std::numeric_limits<std::uint32_t>::max();
    }
    const std::int64_t d = ordered_float(a) - ordered_float(b);
    return static_cast<std::uint64_t>(d < 0 ? -d : d);
}

std::uint64_t depth_distance(refraster::DepthFormat f, std::uint32_t a, std::uint32_t b) {
    if (f == refraster::DepthFormat::Z32f) {
        return ulp_distance(std::bit_cast<float>(a), std::bit_cast<float>(b));
    }
    return a > b ? a - b : b - a;
}

}  // namespace

std::array<std::uint8_t, 4> mask_color(PixelClass c) {
    switch (c) {
        case PixelClass::Equal: return {48, 48, 48, 255};
        case PixelClass::Missing: return {255, 0, 255, 255};
        case PixelClass::Extra: return {255, 0, 0, 255};
        case PixelClass::ColorOnly: return {255, 255, 0, 255};
        case PixelClass::DepthOnly: return {0, 96, 255, 255};
        case PixelClass::Coverage: return {255, 140, 0, 255};
    }
    return {0, 0, 0, 255};
}

Comparison compare_images(const refraster::Framebuffer& ref, const refraster::Framebuffer& act,
                          const refraster::ClearValues& clear, const Expect& expect) {
    Comparison c;
    if (ref.width != act.width || ref.height != act.height ||
        ref.color_format != act.color_format || ref.depth_format != act.depth_format) {
        c.size_mismatch = true;
        c.mismatched_pixels = std::max(ref.pixel_count(), act.pixel_count());
        return c;
    }
    c.mask = refraster::Framebuffer(ref.width, ref.height, refraster::ColorFormat::Rgba8,
                                    refraster::DepthFormat::None);
    const bool is8 = ref.color_format == refraster::ColorFormat::Rgba8;
    const bool owners = !ref.owner.empty() && ref.owner.size() == act.owner.size();
    c.classified_by_owners = owners;

    // The clear colour as each format stores it, to tell drawn pixels from untouched ones.
    std::array<std::uint8_t, 4> clear8{};
    for (std::size_t k = 0; k < 4; ++k) {
        clear8[k] = static_cast<std::uint8_t>(
            std::lround(std::clamp(clear.color[k], 0.0f, 1.0f) * 255.0f));
    }
    const auto is_clear = [&](const refraster::Framebuffer& fb, std::size_t i) {
        for (std::size_t k = 0; k < 4; ++k) {
            if (is8 ? fb.color8[4 * i + k] != clear8[k]
                    : std::bit_cast<std::uint32_t>(fb.color32f[4 * i + k]) !=
                          std::bit_cast<std::uint32_t>(clear.color[k])) {
                return false;
            }
        }
        return true;
    };

    for (std::uint32_t y = 0; y < ref.height; ++y) {
        for (std::uint32_t x = 0; x < ref.width; ++x) {
            const std::size_t i = ref.index(x, y);
            std::uint64_t worst = 0;
            std::uint32_t worst_channel = 0;
            for (std::uint32_t k = 0; k < 4; ++k) {
                const std::size_t j = 4 * i + k;
                const std::uint64_t d =
                    is8 ? static_cast<std::uint64_t>(std::abs(int{ref.color8[j]} - int{act.color8[j]}))
                        : ulp_distance(ref.color32f[j], act.color32f[j]);
                if (d > worst) {
                    worst = d;
                    worst_channel = k;
                }
            }
            if (worst > 0 && (!c.max_color || worst > c.max_color->amount)) {
                ChannelDifference m;
                m.amount = worst;
                m.x = x;
                m.y = y;
                m.channel = worst_channel;
                for (std::size_t k = 0; k < 4; ++k) {
                    m.reference[k] = is8 ? ref.color8[4 * i + k] : double{ref.color32f[4 * i + k]};
                    m.actual[k] = is8 ? act.color8[4 * i + k] : double{act.color32f[4 * i + k]};
                }
                c.max_color = m;
            }
            std::uint64_t ddepth = 0;
            if (ref.depth_format != refraster::DepthFormat::None) {
                ddepth = depth_distance(ref.depth_format, ref.depth[i], act.depth[i]);
                if (ddepth > 0 && (!c.max_depth || ddepth > c.max_depth->amount)) {
                    c.max_depth = DepthDifference{ddepth, x, y, ref.depth[i], act.depth[i]};
                }
            }
            PixelClass cls = PixelClass::Equal;
            if (owners && (worst > expect.color_tolerance || ddepth > 0) && ref.owner[i] != act.owner[i]) {
                cls = ref.owner[i] == 0   ? PixelClass::Extra
                      : act.owner[i] == 0 ? PixelClass::Missing
                                          : PixelClass::Coverage;
            } else if (worst > expect.color_tolerance && owners) {
                cls = PixelClass::ColorOnly;
            } else if (worst > expect.color_tolerance) {
                const bool ref_clear = is_clear(ref, i);
                const bool act_clear = is_clear(act, i);
                cls = act_clear && !ref_clear   ? PixelClass::Missing
                      : ref_clear && !act_clear ? PixelClass::Extra
                                                : PixelClass::ColorOnly;
            } else if (ddepth > 0) {
                cls = PixelClass::DepthOnly;
            }
            switch (cls) {
                case PixelClass::Equal: break;
                case PixelClass::Missing: ++c.missing; break;
                case PixelClass::Extra: ++c.extra; break;
                case PixelClass::ColorOnly: ++c.color_only; break;
                case PixelClass::DepthOnly: ++c.depth_only; break;
                case PixelClass::Coverage: ++c.coverage; break;
            }
            if (cls != PixelClass::Equal) ++c.mismatched_pixels;
            const auto mc = mask_color(cls);
            std::copy(mc.begin(), mc.end(), c.mask.color8.begin() + static_cast<std::ptrdiff_t>(4 * i));
        }
    }
    c.within_expect = c.mismatched_pixels <= expect.max_mismatched_pixels;
    return c;
}

std::string Comparison::summary() const {
    std::ostringstream s;
    if (size_mismatch) return "the images differ in size or format";
    const std::uint64_t total = mask.pixel_count();
    s << mismatched_pixels << " of " << total << " pixels mismatched";
    if (mismatched_pixels > 0) {
        s << " (missing " << missing << ", extra " << extra;
        if (classified_by_owners) s << ", other primitive " << coverage;
        s << ", colour only " << color_only << ", depth only " << depth_only << ")";
    }
    if (max_color) {
        static const char* names[] = {"R", "G", "B", "A"};
        s << "; max colour error " << max_color->amount << " @ (" << max_color->x << ", "
          << max_color->y << ", " << names[max_color->channel] << ") values are ";
        for (std::size_t k = 0; k < 4; ++k) s << (k ? "," : "") << max_color->reference[k];
        s << " vs ";
        for (std::size_t k = 0; k < 4; ++k) s << (k ? "," : "") << max_color->actual[k];
    }
    if (max_depth) {
        s << "; max depth error " << max_depth->amount << " @ (" << max_depth->x << ", "
          << max_depth->y << ") values are " << max_depth->reference << " vs "
          << max_depth->actual;
    }
    return s.str();
}

}  // namespace harness
