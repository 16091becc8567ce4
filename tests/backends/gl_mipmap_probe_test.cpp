// gl_mipmap_probe_test.cpp: glGenerateMipmap in an OSMesa llvmpipe context of this process,
// every level read back with glGetTexImage and compared byte for byte with the llvmpipe
// model's blit of llvmpipe's level above it (refraster/src/models/llvmpipe/texture.cpp,
// blit_level; docs/precision.md, "Generated mipmaps"), so that one difference does not
// cascade. The model fuses as the host does, like llvmpipe on it.
//
// The default run covers a representative set of long, odd and power-of-two sizes. The full
// sweep (every pair of 49 sizes from 1 to 4096, 2,401 textures, about 4 minutes) runs when
// the environment sets REFRASTER_MIPMAP_SWEEP=1:
//   REFRASTER_MIPMAP_SWEEP=1 build/bin/gl_mipmap_probe_tests
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "models/llvmpipe/texture.hpp"
#include "osmesa_llvmpipe_fixture.hpp"
#include "refraster/renderer.hpp"

namespace {

using refraster::TextureImage;

using MipmapProbe = OsmesaLlvmpipeTest;

// llvmpipe's levels 1.. of `base`, read back.
std::vector<TextureImage> llvmpipe_levels(const TextureImage& base) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, static_cast<GLsizei>(base.width),
                 static_cast<GLsizei>(base.height), 0, GL_RGBA, GL_UNSIGNED_BYTE, base.rgba.data());
    glGenerateMipmap(GL_TEXTURE_2D);
    std::vector<TextureImage> out;
    std::uint32_t w = base.width, h = base.height;
    for (GLint level = 1; w > 1 || h > 1; ++level) {
        w = std::max(1u, w / 2);
        h = std::max(1u, h / 2);
        TextureImage img{w, h, std::vector<std::uint8_t>(std::size_t{w} * h * 4)};
        glGetTexImage(GL_TEXTURE_2D, level, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
        out.push_back(std::move(img));
    }
    glDeleteTextures(1, &t);
    return out;
}

TextureImage random_image(std::uint32_t w, std::uint32_t h, std::mt19937& rng) {
    TextureImage img{w, h, std::vector<std::uint8_t>(std::size_t{w} * h * 4)};
    for (auto& b : img.rgba) b = static_cast<std::uint8_t>(rng() & 0xffu);
    return img;
}

// Compares every level; returns a description of the mismatches (empty when none).
std::string compare_levels(std::uint32_t w, std::uint32_t h, std::mt19937& rng) {
    const TextureImage base = random_image(w, h, rng);
    const auto want = llvmpipe_levels(base);
    // Each level blitted from llvmpipe's level above, so that a difference does not cascade.
    static const bool fma = refraster::host_has_fma();
    std::vector<TextureImage> got;
    for (std::size_t l = 0; l < want.size(); ++l)
        got.push_back(refraster::detail::blit_level(l == 0 ? base : want[l - 1], fma));
    std::ostringstream os;
    for (std::size_t l = 0; l < want.size(); ++l) {
        std::size_t bad = 0, first = 0;
        for (std::size_t i = 0; i < want[l].rgba.size(); ++i) {
            if (want[l].rgba[i] != got[l].rgba[i] && bad++ == 0) first = i;
        }
        if (bad == 0) continue;
        const std::size_t texel = first / 4;
        os << w << "x" << h << " level " << l + 1 << " (" << want[l].width << "x" << want[l].height
           << "): " << bad << " channels differ, first at texel (" << texel % want[l].width << ", "
           << texel / want[l].width << ") channel " << first % 4 << ": " << int(got[l].rgba[first])
           << ", llvmpipe " << int(want[l].rgba[first]) << "\n";
    }
    return os.str();
}

// Long and odd sizes whose levels llvmpipe's blit samples away from the texel-centre rule that
// fits small sizes, beside powers of two and their neighbours.
TEST_F(MipmapProbe, GeneratedLevelsMatchLlvmpipe) {
    const std::vector<std::pair<std::uint32_t, std::uint32_t>> sizes = {
        {2047, 7}, {1, 2999}, {3001, 2}, {511, 1},  {1023, 1},  {1023, 515}, {7, 13},
        {5, 3},    {64, 64},  {33, 17},  {1, 4095}, {4095, 3},  {4096, 1},   {129, 255},
        {3, 2047}, {255, 1},  {2, 1},    {1, 3},    {1025, 63}, {2999, 5}};
    std::mt19937 rng(7);
    std::string report;
    for (const auto& [w, h] : sizes) report += compare_levels(w, h, rng);
    EXPECT_EQ(report, "");
}

// The full sweep: every pair of sizes below, every level (REFRASTER_MIPMAP_SWEEP=1).
TEST_F(MipmapProbe, SweepOfSizes) {
    const char* env = std::getenv("REFRASTER_MIPMAP_SWEEP");
    if (env == nullptr || std::string(env) != "1")
        GTEST_SKIP() << "REFRASTER_MIPMAP_SWEEP=1 runs it";
    std::vector<std::uint32_t> sizes;
    for (std::uint32_t s = 1; s <= 33; ++s) sizes.push_back(s);
    for (const std::uint32_t s : {63u, 65u, 127u, 129u, 255u, 257u, 511u, 513u, 1023u, 1025u, 2047u,
                                  2049u, 2999u, 3001u, 4095u, 4096u})
        sizes.push_back(s);
    std::mt19937 rng(11);
    std::string report;
    std::size_t pairs = 0;
    for (const std::uint32_t w : sizes) {
        for (const std::uint32_t h : sizes) {
            report += compare_levels(w, h, rng);
            ++pairs;
        }
    }
    std::cout << pairs << " sizes compared\n";
    EXPECT_EQ(report, "");
}

}  // namespace
