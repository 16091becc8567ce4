#include "harness/image_hash.hpp"

#include <bit>
#include <cstdio>

namespace harness {

namespace {

struct Fnv1a {
    std::uint64_t h = 1469598103934665603ull;
    void byte(std::uint8_t b) {
        h ^= b;
        h *= 1099511628211ull;
    }
    void u32(std::uint32_t v) {
        for (int i = 0; i < 4; ++i) byte(static_cast<std::uint8_t>(v >> (8 * i)));
    }
};

}  // namespace

std::string image_hash(const refraster::Framebuffer& fb) {
    Fnv1a f;
    f.u32(fb.width);
    f.u32(fb.height);
    f.u32(static_cast<std::uint32_t>(fb.color_format));
    f.u32(static_cast<std::uint32_t>(fb.depth_format));
    for (auto b : fb.color8) f.byte(b);
    for (auto v : fb.color32f) f.u32(std::bit_cast<std::uint32_t>(v));
    for (auto d : fb.depth) f.u32(d);
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(f.h));
    return buf;
}

std::string render_hash(const refraster::Framebuffer& image,
                        const refraster::Framebuffer& samples) {
    if (samples.samples <= 1) return image_hash(image);
    Fnv1a f;
    f.u32(samples.samples);
    const std::string h = image_hash(samples);
    for (const char c : h) f.byte(static_cast<std::uint8_t>(c));
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(f.h));
    return buf;
}

}  // namespace harness
