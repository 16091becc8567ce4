#include "harness/compare.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
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
    : PixelClassifier(reference, actual, clear, expect, View{}) {}

PixelClassifier::PixelClassifier(const refraster::Framebuffer& reference,
                                 const refraster::Framebuffer& actual,
                                 const refraster::ClearValues& clear, const Expect& expect,
                                 View view)
    : ref_(reference), act_(actual), expect_(expect), view_(view) {
    REFRASTER_ASSERT(ref_.width == act_.width && ref_.height == act_.height &&
                         ref_.color_format == act_.color_format &&
                         ref_.depth_format == act_.depth_format,
                     "two renders of the same target");
    REFRASTER_ASSERT(view_.stride >= 1 && view_.sample < view_.stride, "a sample of the stride");
    depth_ = view_.depth && ref_.depth_format != refraster::DepthFormat::None;
    owners_ = !ref_.owner.empty() && ref_.owner.size() == act_.owner.size();
    // The clear as the reference stores it (rgba8 clears quantise with Mesa's float_to_ubyte,
    // depth clears with their own rounding): a one-pixel render of no draws.
    refraster::DrawList empty;
    empty.target = {1, 1, reference.color_format, reference.depth_format, 1};
    empty.clear = clear;
    (void)refraster::render(empty, refraster::RenderOptions{}, clear_);
}

bool PixelClassifier::untouched(const refraster::Framebuffer& fb, std::size_t index) const {
    const std::size_t i = index * view_.stride + view_.sample;
    for (std::size_t k = 0; k < 4; ++k) {
        const bool same = fb.color_format == refraster::ColorFormat::Rgba8
                              ? fb.color8[4 * i + k] == clear_.color8[k]
                              : std::bit_cast<std::uint32_t>(fb.color32f[4 * i + k]) ==
                                    std::bit_cast<std::uint32_t>(clear_.color32f[k]);
        if (!same) return false;
    }
    return !depth_ || fb.depth[i] == clear_.depth[0];
}

PixelClassifier::Pixel PixelClassifier::at(std::size_t index) const {
    const std::size_t i = index * view_.stride + view_.sample;
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
    if (depth_) {
        p.depth_difference = depth_distance(ref_.depth_format, ref_.depth[i], act_.depth[i]);
    }
    const bool color_differs = p.color_difference > expect_.color_tolerance;
    if (!color_differs && p.depth_difference == 0) return p;
    if (owners_ && ref_.owner[i] != act_.owner[i]) {
        p.cls = ref_.owner[i] == 0   ? PixelClass::Extra
                : act_.owner[i] == 0 ? PixelClass::Missing
                                     : PixelClass::Coverage;
    } else if (untouched(act_, index) != untouched(ref_, index)) {
        // Also with equal owners: an owner pass can draw what the plain render does not
        // (llvmpipe's nine-vertex analysis never sees an owner pass).
        p.cls = untouched(act_, index) ? PixelClass::Missing : PixelClass::Extra;
    } else {
        p.cls = color_differs ? PixelClass::ColorOnly : PixelClass::DepthOnly;
    }
    return p;
}

bool owners_plausible(const std::vector<std::uint32_t>& owner, const refraster::Framebuffer& fb,
                      const refraster::ClearValues& clear) {
    // Samples are stored pixel-major, so every sample of every pixel is one slot of colour
    // (four values) and one owner.
    const std::size_t slots = fb.pixel_count() * fb.samples;
    if (owner.size() != slots) return false;
    const PixelClassifier clear_of(fb, fb, clear, Expect{});
    for (std::size_t i = 0; i < slots; ++i) {
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

namespace {

// compare_images of the values `view` selects (a sample plane of 4x framebuffers, or colour
// alone), read in place, also writing each pixel's class to `classes` (every `stride`-th entry
// from `classes[0]`) when it is given, and the mask only when `with_mask`.
Comparison compare_classified(const refraster::Framebuffer& ref, const refraster::Framebuffer& act,
                              const refraster::ClearValues& clear, const Expect& expect,
                              PixelClass* classes, std::size_t stride,
                              PixelClassifier::View view = {}, bool with_mask = true) {
    Comparison c;
    if (ref.width != act.width || ref.height != act.height ||
        ref.color_format != act.color_format ||
        (view.depth && ref.depth_format != act.depth_format)) {
        c.size_mismatch = true;
        c.mismatched_pixels = std::max(ref.pixel_count(), act.pixel_count());
        return c;
    }
    if (with_mask) {
        c.mask = refraster::Framebuffer(ref.width, ref.height, refraster::ColorFormat::Rgba8,
                                        refraster::DepthFormat::None);
    }
    const bool is8 = ref.color_format == refraster::ColorFormat::Rgba8;
    // Depth formats that differ are compared as colour only (view.depth false).
    const PixelClassifier classify(ref, act, clear, expect, view);
    c.classified_by_owners = classify.by_owners();

    for (std::uint32_t y = 0; y < ref.height; ++y) {
        for (std::uint32_t x = 0; x < ref.width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * ref.width + x;
            const std::size_t slot = i * view.stride + view.sample;
            const auto px = classify.at(i);
            if (px.color_difference > 0 &&
                (!c.max_color || px.color_difference > c.max_color->amount)) {
                ChannelDifference m;
                m.amount = px.color_difference;
                m.x = x;
                m.y = y;
                m.channel = px.channel;
                for (std::size_t k = 0; k < 4; ++k) {
                    const std::size_t j = 4 * slot + k;
                    m.reference[k] = is8 ? ref.color8[j] : static_cast<double>(ref.color32f[j]);
                    m.actual[k] = is8 ? act.color8[j] : static_cast<double>(act.color32f[j]);
                }
                m.float_values = !is8;
                c.max_color = m;
            }
            if (px.depth_difference > 0 &&
                (!c.max_depth || px.depth_difference > c.max_depth->amount)) {
                c.max_depth =
                    DepthDifference{px.depth_difference, x, y, ref.depth[slot], act.depth[slot]};
                c.max_depth->float_bits = ref.depth_format == refraster::DepthFormat::Z32f;
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
            if (classes != nullptr) classes[i * stride] = px.cls;
            if (with_mask) {
                const auto mc = mask_color(px.cls);
                std::copy(mc.begin(), mc.end(),
                          c.mask.color8.begin() + static_cast<std::ptrdiff_t>(4 * i));
            }
        }
    }
    c.within_expect = c.mismatched_pixels <= expect.max_mismatched_pixels;
    return c;
}

}  // namespace

Comparison compare_images(const refraster::Framebuffer& ref, const refraster::Framebuffer& act,
                          const refraster::ClearValues& clear, const Expect& expect) {
    return compare_classified(ref, act, clear, expect, nullptr, 0);
}

Comparison compare_resolved(const refraster::Framebuffer& ref, const refraster::Framebuffer& act,
                            const refraster::ClearValues& clear, const Expect& expect) {
    if (ref.depth_format == refraster::DepthFormat::None ||
        act.depth_format == refraster::DepthFormat::None) {
        return compare_images(ref, act, clear, expect);
    }
    // Colour alone, read in place.
    PixelClassifier::View colour_only;
    colour_only.depth = false;
    return compare_classified(ref, act, clear, expect, nullptr, 0, colour_only);
}

std::array<std::uint32_t, 2> sample_mask_pixel(std::uint32_t x, std::uint32_t y, std::uint32_t s) {
    REFRASTER_ASSERT(s < kSamplePositions4x.size(), "a sample of a 4x pixel");
    const auto& p = kSamplePositions4x[s];
    return {2 * x + (p[0] >= 0.5f ? 1u : 0u), 2 * y + (p[1] >= 0.5f ? 1u : 0u)};
}

SampleComparison compare_samples(const refraster::Framebuffer& ref,
                                 const refraster::Framebuffer& act,
                                 const refraster::ClearValues& clear, const Expect& expect) {
    SampleComparison c;
    constexpr std::uint32_t kSamples = 4;
    c.samples = kSamples;
    const auto storage_ok = [](const refraster::Framebuffer& fb) {
        const std::size_t slots = fb.pixel_count() * fb.samples;
        const bool colour = fb.color_format == refraster::ColorFormat::Rgba8
                                ? fb.color8.size() == 4 * slots
                                : fb.color32f.size() == 4 * slots;
        const bool depth =
            fb.depth_format == refraster::DepthFormat::None || fb.depth.size() == slots;
        return colour && depth && (fb.owner.empty() || fb.owner.size() == slots);
    };
    if (ref.samples != kSamples || act.samples != kSamples || ref.width != act.width ||
        ref.height != act.height || ref.pixel_count() == 0 ||
        ref.color_format != act.color_format || ref.depth_format != act.depth_format ||
        !storage_ok(ref) || !storage_ok(act)) {
        c.size_mismatch = true;
        c.mismatched_samples =
            std::max(ref.pixel_count() * ref.samples, act.pixel_count() * act.samples);
        return c;
    }
    // Owners classify only when both sides carry them for every sample.
    const bool owners = !ref.owner.empty() && !act.owner.empty();
    c.classified_by_owners = owners;
    const std::size_t n = ref.pixel_count();
    c.classes.assign(n * kSamples, PixelClass::Equal);
    for (std::uint32_t s = 0; s < kSamples; ++s) {
        // Sample s of every pixel, read in place; `mask` below shows every sample.
        PixelClassifier::View plane;
        plane.stride = kSamples;
        plane.sample = s;
        Comparison k = compare_classified(ref, act, clear, expect, c.classes.data() + s, kSamples,
                                          plane, false);
        c.mismatched_samples += k.mismatched_pixels;
        c.missing += k.missing;
        c.extra += k.extra;
        c.color_only += k.color_only;
        c.depth_only += k.depth_only;
        c.coverage += k.coverage;
        // Strictly larger only: among equal amounts the lowest sample keeps it.
        if (k.max_color && (!c.max_color || k.max_color->amount > c.max_color->amount)) {
            c.max_color = k.max_color;
            c.max_color->sample = s;
        }
        if (k.max_depth && (!c.max_depth || k.max_depth->amount > c.max_depth->amount)) {
            c.max_depth = k.max_depth;
            c.max_depth->sample = s;
        }
        c.per_sample.push_back(std::move(k));
    }
    c.mask = refraster::Framebuffer(2 * ref.width, 2 * ref.height, refraster::ColorFormat::Rgba8,
                                    refraster::DepthFormat::None);
    for (std::uint32_t y = 0; y < ref.height; ++y) {
        for (std::uint32_t x = 0; x < ref.width; ++x) {
            const std::size_t i = ref.index(x, y);
            bool any = false;
            for (std::uint32_t s = 0; s < kSamples; ++s) {
                const PixelClass cls = c.classes[i * kSamples + s];
                any = any || cls != PixelClass::Equal;
                const auto at = sample_mask_pixel(x, y, s);
                const auto mc = mask_color(cls);
                std::copy(mc.begin(), mc.end(),
                          c.mask.color8.begin() +
                              static_cast<std::ptrdiff_t>(4 * c.mask.index(at[0], at[1])));
            }
            c.pixels_with_mismatched_samples += any ? 1 : 0;
        }
    }
    c.within_expect = c.mismatched_samples <= expect.max_mismatched_pixels;
    return c;
}

PixelClass SampleComparison::class_at(std::uint32_t x, std::uint32_t y, std::uint32_t s) const {
    const std::size_t w = mask.width / 2;
    const std::size_t h = mask.height / 2;
    if (classes.empty() || x >= w || y >= h || s >= samples) return PixelClass::Equal;
    return classes[(std::size_t{y} * w + x) * samples + s];
}

std::string float_text(float f) {
    std::ostringstream t;
    for (int digits = 1; digits <= std::numeric_limits<float>::max_digits10; ++digits) {
        t.str("");
        t.precision(digits);
        t << f;
        if (!std::isfinite(f) || std::strtof(t.str().c_str(), nullptr) == f) break;
    }
    return t.str();
}

namespace {

// "colour error 3 @ (x, y, G): reference 1,2,3,4, backend 1,2,6,4" (rgba8 units), or with
// "ULPs" and the float values (rgba32f); the sample after the pixel when `sampled`.
std::string color_error_text(const ChannelDifference& m, bool sampled) {
    static const char* names[] = {"R", "G", "B", "A"};
    std::ostringstream s;
    s << "colour error " << m.amount << (m.float_values ? " ULPs" : "") << " @ (" << m.x << ", "
      << m.y;
    if (sampled) s << ", sample " << m.sample;
    s << ", " << names[m.channel & 3] << "): reference ";
    const auto values = [&](const std::array<double, 4>& v) {
        for (std::size_t k = 0; k < 4; ++k) {
            s << (k ? "," : "");
            if (m.float_values) {
                s << float_text(static_cast<float>(v[k]));
            } else {
                s << static_cast<int>(v[k]);
            }
        }
    };
    values(m.reference);
    s << ", backend ";
    values(m.actual);
    return s.str();
}

// "depth error 2 @ (x, y): reference 1000, backend 1002" (the stored integers), or with "ULPs"
// and the float values (z32f).
std::string depth_error_text(const DepthDifference& m, bool sampled) {
    std::ostringstream s;
    s << "depth error " << m.amount << (m.float_bits ? " ULPs" : "") << " @ (" << m.x << ", "
      << m.y;
    if (sampled) s << ", sample " << m.sample;
    const auto value = [&](std::uint32_t v) {
        return m.float_bits ? float_text(std::bit_cast<float>(v)) : std::to_string(v);
    };
    s << "): reference " << value(m.reference) << ", backend " << value(m.actual);
    return s.str();
}

}  // namespace

std::string SampleComparison::summary() const {
    if (size_mismatch) return "the samples differ in count, size or format";
    std::ostringstream s;
    const std::uint64_t total = std::uint64_t{mask.pixel_count() / 4} * samples;
    s << mismatched_samples << " of " << total << " samples mismatched";
    if (mismatched_samples > 0) {
        s << " in " << pixels_with_mismatched_samples << " pixels (by sample";
        for (std::size_t k = 0; k < per_sample.size(); ++k) {
            s << (k ? ", " : " ") << k << ": " << per_sample[k].mismatched_pixels;
        }
        s << "; missing " << missing << ", extra " << extra;
        if (classified_by_owners) s << ", other primitive " << coverage;
        s << ", colour only " << color_only << ", depth only " << depth_only << ")";
    }
    if (max_color) s << "; max sample " << color_error_text(*max_color, true);
    if (max_depth) s << "; max sample " << depth_error_text(*max_depth, true);
    return s.str();
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
    if (max_color) s << "; max " << color_error_text(*max_color, false);
    if (max_depth) s << "; max " << depth_error_text(*max_depth, false);
    return s.str();
}

}  // namespace harness
