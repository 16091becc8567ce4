// framebuffer.hpp: the pixels a renderer produces, in the form every comparison uses.
//
// Implements: colour (rgba8 bytes or rgba32f floats) and depth storage for `samples` samples a
// pixel, pixel-major (the samples of pixel i at i * samples .. i * samples + samples - 1, so
// a single-sample framebuffer is the plain image), rows bottom-up (row 0 is window row 0, as
// glReadPixels returns them), and the depth values exactly as the scene format compares them:
// z16 as 16-bit integers, z24 as 24-bit integers, z32f as the float's bit pattern.
//
// Also: the resolve of a 4x framebuffer as glBlitFramebuffer computes it in Mesa 22.3, and
// the plane of one sample (a single-sample framebuffer holding sample s of every pixel).
//
// Deliberately does not: know about image files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "refraster/assert.hpp"
#include "refraster/draw.hpp"

namespace refraster {

namespace detail {
void* allocate_pixels(std::size_t bytes);
void release_pixels(void* p, std::size_t bytes) noexcept;
}  // namespace detail

// The allocator of a framebuffer's colour and depth: storage of 2 MB and more is mapped on its
// own and the kernel asked to back it with huge pages (Linux; operator new otherwise and for
// smaller storage). A small primitive's rows lie a framebuffer row apart, a 4 KB page apart at
// 1024 pixels, so shading many small primitives at random places pays for address
// translations as much as for the data. Allocators compare equal.
template <class T>
struct PixelAllocator {
    using value_type = T;
    PixelAllocator() = default;
    template <class U>
    constexpr PixelAllocator(const PixelAllocator<U>&) noexcept {}  // NOLINT: converting
    T* allocate(std::size_t n) { return static_cast<T*>(detail::allocate_pixels(n * sizeof(T))); }
    void deallocate(T* p, std::size_t n) noexcept { detail::release_pixels(p, n * sizeof(T)); }
    template <class U>
    friend constexpr bool operator==(const PixelAllocator&, const PixelAllocator<U>&) noexcept {
        return true;
    }
};
template <class T>
using PixelVector = std::vector<T, PixelAllocator<T>>;

// Storage the allocator maps itself bypasses operator new; a heap meter that counts operator
// new (the CLI's, for `refraster bench`) learns of it here: +bytes when mapped, -bytes when
// released. One observer for the process; nullptr (the default) for none.
using PixelStorageObserver = void (*)(std::ptrdiff_t bytes);
void set_pixel_storage_observer(PixelStorageObserver observer);

struct Framebuffer {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    ColorFormat color_format = ColorFormat::Rgba8;
    DepthFormat depth_format = DepthFormat::None;
    std::uint32_t samples = 1;
    PixelVector<std::uint8_t> color8;  // rgba8: 4 bytes a sample, row 0 at the bottom
    PixelVector<float> color32f;       // rgba32f: 4 floats a sample, row 0 at the bottom
    PixelVector<std::uint32_t> depth;  // one value a sample when depth_format != None
    // Which primitive wrote each pixel last, when asked for: (draw index << 24) |
    // (gl_PrimitiveID + 1), 0 where nothing was drawn. Empty unless requested.
    std::vector<std::uint32_t> owner;

    Framebuffer() = default;
    Framebuffer(std::uint32_t w, std::uint32_t h, ColorFormat cf, DepthFormat df,
                std::uint32_t sample_count = 1);

    std::size_t pixel_count() const { return std::size_t{width} * height; }
    // The pixel's index, which a single-sample framebuffer's storage uses too; (x, y) must lie
    // inside.
    std::size_t index(std::uint32_t x, std::uint32_t y) const {
        REFRASTER_ASSERT(x < width && y < height, "a pixel inside the framebuffer");
        return std::size_t{y} * width + x;
    }
    // Index of sample `s` of pixel (x, y) in the colour (times 4) and depth storage.
    std::size_t sample_index(std::uint32_t x, std::uint32_t y, std::uint32_t s) const {
        REFRASTER_ASSERT(s < samples, "a sample of the pixel");
        return index(x, y) * samples + s;
    }
    friend bool operator==(const Framebuffer&, const Framebuffer&) = default;
};

// The single-sample image glBlitFramebuffer makes of `ms` (samples 1 or 4): colour averaged
// as Mesa 22.3's resolve shader does (u_simple_shaders.c: util_make_fs_msaa_resolve: each
// sample fetched as float, summed in sample order starting from +0, times 0.25, then stored
// in the target's format); depth is sample 0's (the resolved image's depth is informative only:
// every sample's depth is compared on its own). Owners, when present, are sample 0's too.
Framebuffer resolve_samples(const Framebuffer& ms);

// Sample `s` of every pixel of `ms`, as a single-sample framebuffer (owners included).
Framebuffer sample_plane(const Framebuffer& ms, std::uint32_t s);

// The owner value of primitive `primitive` (GL's gl_PrimitiveID) of draw `draw`.
constexpr std::uint32_t owner_id(std::size_t draw, std::size_t primitive) {
    return static_cast<std::uint32_t>((draw << 24) | ((primitive + 1) & 0xffffffu));
}

// Number of meaningful bits in a depth value of format `f` (z32f: all 32 bits of the float).
constexpr std::uint32_t depth_bits(DepthFormat f) {
    switch (f) {
        case DepthFormat::Z16:
            return 16;
        case DepthFormat::Z24:
            return 24;
        case DepthFormat::Z32f:
            return 32;
        case DepthFormat::None:
            return 0;
    }
    return 0;
}

}  // namespace refraster
