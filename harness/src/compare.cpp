#include "harness/compare.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <sstream>

#include "refraster/assert.hpp"
#include "refraster/renderer.hpp"

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
        case PixelClass::Equal:
            return {48, 48, 48, 255};
        case PixelClass::Missing:
            return {255, 0, 255, 255};
        case PixelClass::Extra:
            return {255, 0, 0, 255};
        case PixelClass::ColorOnly:
            return {255, 255, 0, 255};
        case PixelClass::DepthOnly:
            return {0, 96, 255, 255};
        case PixelClass::Coverage:
            return {255, 140, 0, 255};
    }
    return {0, 0, 0, 255};
}

PixelClassifier::PixelClassifier(const refraster::Framebuffer& reference,
                                 const refraster::Framebuffer& actual,
                                 const refraster::ClearValues& clear, const Expect& expect)
    : ref_(reference), act_(actual), expect_(expect) {
    REFRASTER_ASSERT(ref_.width == act_.width && ref_.height == act_.height &&
                         ref_.color_format == act_.color_format &&
                         ref_.depth_format == act_.depth_format,
                     "two renders of the same target");
    owners_ = !ref_.owner.empty() && ref_.owner.size() == act_.owner.size();
    // The clear as the reference stores it (rgba8 clears quantise with Mesa's float_to_ubyte,
    // depth clears with their own rounding): a one-pixel render of no draws.
    refraster::DrawList empty;
    empty.target = {1, 1, reference.color_format, reference.depth_format, 1};
    empty.clear = clear;
    (void)refraster::render(empty, refraster::RenderOptions{}, clear_);
}

bool PixelClassifier::untouched(const refraster::Framebuffer& fb, std::size_t i) const {
    for (std::size_t k = 0; k < 4; ++k) {
        const bool same = fb.color_format == refraster::ColorFormat::Rgba8
                              ? fb.color8[4 * i + k] == clear_.color8[k]
                              : std::bit_cast<std::uint32_t>(fb.color32f[4 * i + k]) ==
                                    std::bit_cast<std::uint32_t>(clear_.color32f[k]);
        if (!same) return false;
    }
    return fb.depth_format == refraster::DepthFormat::None || fb.depth[i] == clear_.depth[0];
}

PixelClassifier::Pixel PixelClassifier::at(std::size_t i) const {
    Pixel p;
    const bool is8 = ref_.color_format == refraster::ColorFormat::Rgba8;
    for (std::uint32_t k = 0; k < 4; ++k) {
        const std::size_t j = 4 * i + k;
        const std::uint64_t d =
            is8 ? static_cast<std::uint64_t>(std::abs(int{ref_.color8[j]} - int{act_.color8[j]}))
                : ulp_distance(ref_.color32f[j], act_.color32f[j]);
        if (d > p.color_difference) {
            p.color_difference = d;
            p.channel = k;
        }
    }
    if (ref_.depth_format != refraster::DepthFormat::None) {
        p.depth_difference = depth_distance(ref_.depth_format, ref_.depth[i], act_.depth[i]);
    }
    const bool color_differs = p.color_difference > expect_.color_tolerance;
    if (!color_differs && p.depth_difference == 0) return p;
    if (owners_ && ref_.owner[i] != act_.owner[i]) {
        p.cls = ref_.owner[i] == 0   ? PixelClass::Extra
                : act_.owner[i] == 0 ? PixelClass::Missing
                                     : PixelClass::Coverage;
    } else if (untouched(act_, i) != untouched(ref_, i)) {
        // Also with equal owners: an owner pass can draw what the plain render does not
        // (llvmpipe's nine-vertex analysis never sees an owner pass).
        p.cls = untouched(act_, i) ? PixelClass::Missing : PixelClass::Extra;
    } else {
        p.cls = color_differs ? PixelClass::ColorOnly : PixelClass::DepthOnly;
    }
    return p;
}

bool owners_plausible(const std::vector<std::uint32_t>& owner, const refraster::Framebuffer& fb,
                      const refraster::ClearValues& clear) {
    if (owner.size() != fb.pixel_count()) return false;
    const PixelClassifier clear_of(fb, fb, clear, Expect{});
    for (std::size_t i = 0; i < fb.pixel_count(); ++i) {
        if (owner[i] != 0) continue;
        for (std::size_t k = 0; k < 4; ++k) {
            const bool same = fb.color_format == refraster::ColorFormat::Rgba8
                                  ? fb.color8[4 * i + k] == clear_of.clear_color8(k)
                                  : std::bit_cast<std::uint32_t>(fb.color32f[4 * i + k]) ==
                                        std::bit_cast<std::uint32_t>(clear_of.clear_color32f(k));
            if (!same) return false;
        }
    }
    return true;
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
    const PixelClassifier classify(ref, act, clear, expect);
    c.classified_by_owners = classify.by_owners();

    for (std::uint32_t y = 0; y < ref.height; ++y) {
        for (std::uint32_t x = 0; x < ref.width; ++x) {
            const std::size_t i = ref.index(x, y);
            const auto px = classify.at(i);
            if (px.color_difference > 0 &&
                (!c.max_color || px.color_difference > c.max_color->amount)) {
                ChannelDifference m;
                m.amount = px.color_difference;
                m.x = x;
                m.y = y;
                m.channel = px.channel;
                for (std::size_t k = 0; k < 4; ++k) {
                    m.reference[k] = is8 ? ref.color8[4 * i + k] : double{ref.color32f[4 * i + k]};
                    m.actual[k] = is8 ? act.color8[4 * i + k] : double{act.color32f[4 * i + k]};
                }
                c.max_color = m;
            }
            if (px.depth_difference > 0 &&
                (!c.max_depth || px.depth_difference > c.max_depth->amount)) {
                c.max_depth =
                    DepthDifference{px.depth_difference, x, y, ref.depth[i], act.depth[i]};
            }
            switch (px.cls) {
                case PixelClass::Equal:
                    break;
                case PixelClass::Missing:
                    ++c.missing;
                    break;
                case PixelClass::Extra:
                    ++c.extra;
                    break;
                case PixelClass::ColorOnly:
                    ++c.color_only;
                    break;
                case PixelClass::DepthOnly:
                    ++c.depth_only;
                    break;
                case PixelClass::Coverage:
                    ++c.coverage;
                    break;
            }
            if (px.cls != PixelClass::Equal) ++c.mismatched_pixels;
            const auto mc = mask_color(px.cls);
            std::copy(mc.begin(), mc.end(),
                      c.mask.color8.begin() + static_cast<std::ptrdiff_t>(4 * i));
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
          << max_depth->y << ") values are " << max_depth->reference << " vs " << max_depth->actual;
    }
    return s.str();
}

}  // namespace harness
