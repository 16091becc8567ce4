// softpipe_lazy_tiles.cpp: softpipe's colour tile cache without whole-tile copies
// (softpipe_lazy_tiles.hpp).
#include "models/softpipe/softpipe_lazy_tiles.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <memory>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "stages/output_merge.hpp"

namespace refraster::detail {

namespace {

// util_format pack of one pixel, as SoftpipeTileCache::write_back: float_to_ubyte for
// R8G8B8A8_UNORM (color_to_unorm8: 0 for NaN and c <= 0, 255 from 1 on, else RNE(fl(c * 255)),
// the rounding in the current mode), the float itself for R32G32B32A32_FLOAT.
void store_pixel(const float* c, Framebuffer& fb, std::size_t i) {
    if (fb.color_format != ColorFormat::Rgba8) {
        std::copy(c, c + 4, fb.color32f.begin() + static_cast<std::ptrdiff_t>(i));
        return;
    }
#if defined(__SSE2__)
    // The four channels at once: cvtps2dq rounds in the current mode as nearbyintf does, and
    // the compares take denormals as the scalar compares do under the same mode.
    const __m128 v = _mm_loadu_ps(c);
    __m128i r = _mm_cvtps_epi32(_mm_mul_ps(v, _mm_set1_ps(255.0f)));
    r = _mm_and_si128(r, _mm_castps_si128(_mm_cmpgt_ps(v, _mm_setzero_ps())));
    const __m128i full = _mm_castps_si128(_mm_cmpge_ps(v, _mm_set1_ps(1.0f)));
    r = _mm_or_si128(_mm_andnot_si128(full, r), _mm_and_si128(full, _mm_set1_epi32(255)));
    r = _mm_packs_epi32(r, r);
    r = _mm_packus_epi16(r, r);
    const auto packed = static_cast<std::uint32_t>(_mm_cvtsi128_si32(r));
    std::memcpy(fb.color8.data() + i, &packed, 4);
#else
    for (std::size_t k = 0; k < 4; ++k) fb.color8[i + k] = color_to_unorm8(c[k]);
#endif
}

}  // namespace

SoftpipeLazyTiles::SoftpipeLazyTiles(Framebuffer& fb,
                                     const std::optional<std::array<float, 4>>& clear)
    : fb_(fb), clear_(clear.value_or(std::array<float, 4>{})) {
    tiles_x_ = static_cast<int>((fb.width + kTileSize - 1) / kTileSize);
    const int tiles_y = static_cast<int>((fb.height + kTileSize - 1) / kTileSize);
    flagged_clear_.assign(static_cast<std::size_t>(tiles_x_) * static_cast<std::size_t>(tiles_y),
                          clear ? 1 : 0);
    for (std::size_t k = 0; k < 4; ++k) clear8_[k] = color_to_unorm8(clear_[k]);
}

void SoftpipeLazyTiles::store_clear(int y, int x0, int x1) {
    for (int x = x0; x < x1; ++x) {
        const std::size_t i =
            4 * fb_.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
        if (fb_.color_format == ColorFormat::Rgba8) {
            std::copy(clear8_.begin(), clear8_.end(), fb_.color8.begin() + static_cast<long>(i));
        } else {
            std::copy(clear_.begin(), clear_.end(), fb_.color32f.begin() + static_cast<long>(i));
        }
    }
}

void SoftpipeLazyTiles::write_back(Slot& s) {
    if (s.tile < 0) return;
    const int x0 = (s.tile % tiles_x_) * kTileSize;
    const int y0 = (s.tile / tiles_x_) * kTileSize;
    const int rows = std::min(kTileSize, static_cast<int>(fb_.height) - y0);
    const int cols = std::min(kTileSize, static_cast<int>(fb_.width) - x0);
    for (int r = 0; r < rows; ++r) {
        std::uint64_t bits = s.written[static_cast<std::size_t>(r)];
        s.written[static_cast<std::size_t>(r)] = 0;
        if (s.from_clear) {
            // The model's tile holds the clear colour wherever nothing was written.
            int x = 0;
            while (x < cols) {
                if (((bits >> x) & 1u) != 0) {
                    ++x;
                    continue;
                }
                int end = x + 1;
                while (end < cols && ((bits >> end) & 1u) == 0) ++end;
                store_clear(y0 + r, x0 + x, x0 + end);
                x = end;
            }
        }
        while (bits != 0) {
            const int ox = std::countr_zero(bits);
            bits &= bits - 1;
            const float* c = s.data.get() + 4 * static_cast<std::size_t>(r * kTileSize + ox);
            store_pixel(c, fb_,
                        4 * fb_.index(static_cast<std::uint32_t>(x0 + ox),
                                      static_cast<std::uint32_t>(y0 + r)));
        }
    }
    s.tile = -1;
}

void SoftpipeLazyTiles::load(Slot& s, int tile) {
    if (!s.data)
        s.data = std::make_unique_for_overwrite<float[]>(std::size_t{kTileSize} * kTileSize * 4);
    s.tile = tile;
    auto& flag = flagged_clear_[static_cast<std::size_t>(tile)];
    s.from_clear = flag != 0;
    flag = 0;
}

void SoftpipeLazyTiles::read_unwritten(const Slot& s, int x, int y, float* rgba) const {
    if (s.from_clear) {
        std::copy(clear_.begin(), clear_.end(), rgba);
        return;
    }
    // SoftpipeTileCache::load: ubyte_to_float, b * (1.0f / 255.0f).
    const std::size_t i =
        4 * fb_.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    for (std::size_t k = 0; k < 4; ++k) {
        rgba[k] = fb_.color_format == ColorFormat::Rgba8
                      ? static_cast<float>(fb_.color8[i + k]) * (1.0f / 255.0f)
                      : fb_.color32f[i + k];
    }
}

void SoftpipeLazyTiles::flush() {
    for (Slot& s : slots_) write_back(s);
    // sp_tile_cache_flush_clear: the clear colour into every tile still flagged.
    for (std::size_t t = 0; t < flagged_clear_.size(); ++t) {
        if (flagged_clear_[t] == 0) continue;
        const int tile = static_cast<int>(t);
        const int x0 = (tile % tiles_x_) * kTileSize;
        const int y0 = (tile / tiles_x_) * kTileSize;
        const int x1 = std::min(x0 + kTileSize, static_cast<int>(fb_.width));
        for (int y = y0; y < std::min(y0 + kTileSize, static_cast<int>(fb_.height)); ++y)
            store_clear(y, x0, x1);
        flagged_clear_[t] = 0;
    }
}

}  // namespace refraster::detail
