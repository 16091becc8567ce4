// compare.hpp: pixel-by-pixel comparison of two renders of one scene.
//
// Implements the scene format's comparison on decoded pixels (never file bytes): colour per
// channel in units of the target's last bit (one unorm8 step for rgba8, one float ULP for
// rgba32f), depth as exact integers (z16, z24 values; z32f bit patterns), the scene's
// `expect` (tolerance and mismatched-pixel budget), the largest differences with their
// location and both values, and an error mask image.
//
// When both images carry primitive owners (Framebuffer::owner), a mismatched pixel is classed
// by them: drawn by one side only (missing, extra), by different primitives (coverage), or by
// the same primitive with other bytes (colour only, depth only). Without owners, "missing" and
// "extra" are judged against the clear colour instead.
//
// A 4x target is compared twice: its resolved image (colour only, compare_resolved: the
// resolve's depth is sample 0's, which the samples already compare) and every sample
// (compare_samples: each sample plane through compare_images, the same classes, the largest
// difference with its pixel and sample, and a sample mask of 2W x 2H pixels showing each
// pixel's four samples at their positions). The scene's `expect` bounds both: a case passes
// only when the resolved pixels and the samples are within it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "harness/scene.hpp"
#include "refraster/framebuffer.hpp"

namespace harness {

// Classes of the error mask, each with its colour in the mask image.
enum class PixelClass : std::uint8_t {
    Equal,      // dark grey (within tolerance, depth equal)
    Missing,    // magenta: the reference drew it, the other render left the clear colour
    Extra,      // red: the other render drew it, the reference left the clear colour
    ColorOnly,  // yellow: both drew it, colours differ beyond tolerance
    DepthOnly,  // blue: colours within tolerance, depth values differ
    Coverage,   // orange: both drew it, but different primitives own it (owners only)
};

struct ChannelDifference {
    std::uint64_t amount = 0;  // last-bit units (rgba8) or ULPs (rgba32f)
    std::uint32_t x = 0;
    std::uint32_t y = 0;                // window coordinates, row 0 at the bottom
    std::uint32_t channel = 0;          // 0..3 = r, g, b, a
    std::array<double, 4> reference{};  // both pixels' values, in the format's own units
    std::array<double, 4> actual{};
    std::uint32_t sample = 0;   // compare_samples: the sample of pixel (x, y); 0 otherwise
    bool float_values = false;  // rgba32f: `amount` counts ULPs between float values
};

struct DepthDifference {
    std::uint64_t amount = 0;  // |a - b| of the integer values (z32f: ULPs)
    std::uint32_t x = 0;
    std::uint32_t y = 0;
    std::uint32_t reference = 0;  // the stored values (z32f: a float's bits)
    std::uint32_t actual = 0;
    std::uint32_t sample = 0;  // compare_samples: the sample of pixel (x, y); 0 otherwise
    bool float_bits = false;   // z32f: reference and actual are float bits, `amount` ULPs
};

struct Comparison {
    bool size_mismatch = false;
    std::uint64_t mismatched_pixels = 0;  // colour beyond tolerance or depth different
    std::uint64_t missing = 0;
    std::uint64_t extra = 0;
    std::uint64_t color_only = 0;
    std::uint64_t depth_only = 0;
    std::uint64_t coverage = 0;  // owners only: different primitives own the pixel
    bool classified_by_owners = false;
    std::optional<ChannelDifference> max_color;  // largest colour difference, if any differs
    std::optional<DepthDifference> max_depth;
    bool within_expect = false;
    refraster::Framebuffer mask;  // rgba8, one PixelClass colour a pixel

    std::string summary() const;  // one line, idiff's vocabulary
};

// The standard positions of a 4x pixel's samples (GL's standard 4x pattern, which Mesa 22.3
// llvmpipe uses), in units of the pixel from its bottom-left corner, in sample order: 0
// bottom-left, 1 bottom-right, 2 top-left, 3 top-right.
inline constexpr std::array<std::array<float, 2>, 4> kSamplePositions4x{
    {{0.375f, 0.125f}, {0.875f, 0.375f}, {0.125f, 0.625f}, {0.625f, 0.875f}}};

// Where sample `s` (0..3) of pixel (x, y) is drawn in a sample mask: the pixel (2x + dx,
// 2y + dy) of the 2W x 2H mask, dx and dy the halves of the pixel its position lies in (window
// coordinates, row 0 at the bottom, like every Framebuffer; image files flip them).
std::array<std::uint32_t, 2> sample_mask_pixel(std::uint32_t x, std::uint32_t y, std::uint32_t s);

// Every sample of two 4x renders compared (compare_samples).
struct SampleComparison {
    bool size_mismatch = false;  // not two 4x framebuffers of one size and format
    std::uint32_t samples = 0;   // samples a pixel (4)
    std::uint64_t mismatched_samples = 0;
    std::uint64_t pixels_with_mismatched_samples = 0;  // pixels with at least one
    // The classes summed over every sample, as Comparison counts them for pixels.
    std::uint64_t missing = 0;
    std::uint64_t extra = 0;
    std::uint64_t color_only = 0;
    std::uint64_t depth_only = 0;
    std::uint64_t coverage = 0;
    bool classified_by_owners = false;
    // Sample s of every pixel compared as an image (its counts and its largest differences;
    // no mask of its own: `mask` shows every sample); per_sample[s].mismatched_pixels counts
    // the mismatched samples of index s.
    std::vector<Comparison> per_sample;
    // The largest colour and depth differences over all samples, with their pixel and sample
    // (the `sample` fields): among equals the lowest sample, then the first in row order.
    std::optional<ChannelDifference> max_color;
    std::optional<DepthDifference> max_depth;
    // Each sample's class, pixel-major like the framebuffers: sample s of pixel i at
    // i * samples + s.
    std::vector<PixelClass> classes;
    bool within_expect = false;  // mismatched_samples <= expect.max_mismatched_pixels
    // rgba8, 2W x 2H: each pixel a 2x2 block of its samples' class colours
    // (sample_mask_pixel).
    refraster::Framebuffer mask;

    // The class of sample `s` of pixel (x, y); Equal when nothing was compared.
    PixelClass class_at(std::uint32_t x, std::uint32_t y, std::uint32_t s) const;
    std::string summary() const;  // one line
};

// The class of one pixel of two renders of the same target, as compare_images counts it and
// as explain reasons from it. A pixel is untouched when it holds exactly what the target's
// clear stores (colour as the reference quantises the clear, and depth), or, when both
// renders carry owners, when no primitive owns it.
class PixelClassifier {
  public:
    // The two framebuffers must have the same size and formats; they are referenced, not
    // copied.
    PixelClassifier(const refraster::Framebuffer& reference, const refraster::Framebuffer& actual,
                    const refraster::ClearValues& clear, const Expect& expect);
    // Which values a pixel index reads: index i is slot i * stride + sample of the buffers (a
    // 4x framebuffer's sample `sample` of pixel i with stride 4), and depth is ignored when
    // `depth` is false (a resolved image, whose depth is sample 0's).
    struct View {
        std::uint32_t stride = 1;
        std::uint32_t sample = 0;
        bool depth = true;
    };
    PixelClassifier(const refraster::Framebuffer& reference, const refraster::Framebuffer& actual,
                    const refraster::ClearValues& clear, const Expect& expect, View view);

    struct Pixel {
        PixelClass cls = PixelClass::Equal;
        std::uint64_t color_difference = 0;  // largest channel difference (last-bit units or ULPs)
        std::uint32_t channel = 0;           // its channel
        std::uint64_t depth_difference = 0;
    };
    Pixel at(std::size_t index) const;
    bool by_owners() const { return owners_; }
    // Whether a pixel of either render holds the clear values (colour and depth).
    bool untouched(const refraster::Framebuffer& fb, std::size_t index) const;
    // The clear colour as the reference stores it.
    std::uint8_t clear_color8(std::size_t channel) const { return clear_.color8[channel]; }
    float clear_color32f(std::size_t channel) const { return clear_.color32f[channel]; }

  private:
    const refraster::Framebuffer& ref_;
    const refraster::Framebuffer& act_;
    Expect expect_;
    View view_;
    bool depth_ = false;  // depth is compared
    bool owners_ = false;
    refraster::Framebuffer clear_;  // one pixel holding the clear as the reference stores it
};

// An owner buffer is believable when every pixel of the plain render `fb` that holds anything
// but the clear colour has an owner: something must have written it. A driver that cannot
// write the integer attachment (softpipe 22.3 leaves it at zero) fails this, and its
// mismatches keep the clear-value classes. For a 4x framebuffer `owner` holds one value a
// sample (pixel-major) and every sample is checked.
bool owners_plausible(const std::vector<std::uint32_t>& owner, const refraster::Framebuffer& fb,
                      const refraster::ClearValues& clear);

Comparison compare_images(const refraster::Framebuffer& reference,
                          const refraster::Framebuffer& actual, const refraster::ClearValues& clear,
                          const Expect& expect);

// Two 4x renders' resolved images (RenderResult::image), compared by colour only: their depth
// is sample 0's, which compare_samples compares with every other sample, so it is not counted
// twice. Single-sample images are compared as compare_images does.
Comparison compare_resolved(const refraster::Framebuffer& reference,
                            const refraster::Framebuffer& actual,
                            const refraster::ClearValues& clear, const Expect& expect);

// Every sample of two 4x renders (RenderResult::samples): each sample plane
// (refraster::sample_plane, owners included) through compare_images with `clear` and
// `expect`; `expect.max_mismatched_pixels` bounds the mismatched samples. Anything but two
// 4-sample framebuffers of one size and format is a size mismatch (never within expect).
SampleComparison compare_samples(const refraster::Framebuffer& reference,
                                 const refraster::Framebuffer& actual,
                                 const refraster::ClearValues& clear, const Expect& expect);

std::array<std::uint8_t, 4> mask_color(PixelClass c);

// A float as the fewest digits that read back as it (0.1f is "0.1", not 0.100000001): how
// comparisons and reports print float colours and z32f depths.
std::string float_text(float v);

}  // namespace harness
