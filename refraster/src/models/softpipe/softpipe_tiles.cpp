// softpipe_tiles.cpp: softpipe's colour tile cache (softpipe_tiles.hpp).
#include "models/softpipe/softpipe_tiles.hpp"

#include <algorithm>
#include <memory>

#include "stages/output_merge.hpp"

namespace refraster::detail {

namespace {
constexpr std::size_t kTileFloats =
    std::size_t{SoftpipeTileCache::kTileSize} * SoftpipeTileCache::kTileSize * 4;
}

SoftpipeTileCache::SoftpipeTileCache(Framebuffer& fb,
                                     const std::optional<std::array<float, 4>>& clear,
                                     bool truncate)
    : fb_(fb), clear_(clear.value_or(std::array<float, 4>{})), truncate_(truncate) {
    tiles_x_ = static_cast<int>((fb.width + kTileSize - 1) / kTileSize);
    const int tiles_y = static_cast<int>((fb.height + kTileSize - 1) / kTileSize);
    flagged_clear_.assign(static_cast<std::size_t>(tiles_x_) * static_cast<std::size_t>(tiles_y),
                          clear ? 1 : 0);
    slot_tile_.fill(-1);
    data_ = std::make_unique_for_overwrite<float[]>(kSlots * kTileFloats);
}

std::uint8_t SoftpipeTileCache::to_unorm8(float c) const {
    return truncate_ ? color_to_unorm8_truncated(c) : color_to_unorm8(c);
}

void SoftpipeTileCache::write_back(int slot) {
    const int tile = slot_tile_[static_cast<std::size_t>(slot)];
    if (tile < 0) return;
    const int x0 = (tile % tiles_x_) * kTileSize;
    const int y0 = (tile / tiles_x_) * kTileSize;
    const float* src = data_.get() + static_cast<std::size_t>(slot) * kTileFloats;
    for (int y = y0; y < std::min(y0 + kTileSize, static_cast<int>(fb_.height)); ++y) {
        for (int x = x0; x < std::min(x0 + kTileSize, static_cast<int>(fb_.width)); ++x) {
            const float* c = src + 4 * (static_cast<std::size_t>(y - y0) * kTileSize +
                                        static_cast<std::size_t>(x - x0));
            const std::size_t i =
                4 * fb_.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
            for (std::size_t k = 0; k < 4; ++k) {
                // util_format pack: float_to_ubyte for R8G8B8A8_UNORM (the clamp and
                // RNE(fl(c * 255)), color_to_unorm8), the float itself for R32G32B32A32_FLOAT.
                if (fb_.color_format == ColorFormat::Rgba8) {
                    fb_.color8[i + k] = to_unorm8(c[k]);
                } else {
                    fb_.color32f[i + k] = c[k];
                }
            }
        }
    }
    slot_tile_[static_cast<std::size_t>(slot)] = -1;
}

void SoftpipeTileCache::load(int slot, int tile) {
    float* dst = data_.get() + static_cast<std::size_t>(slot) * kTileFloats;
    const auto t = static_cast<std::size_t>(tile);
    if (flagged_clear_[t] != 0) {
        for (std::size_t i = 0; i < kTileFloats; i += 4)
            std::copy(clear_.begin(), clear_.end(), dst + i);
        flagged_clear_[t] = 0;
    } else {
        const int x0 = (tile % tiles_x_) * kTileSize;
        const int y0 = (tile / tiles_x_) * kTileSize;
        for (int y = y0; y < std::min(y0 + kTileSize, static_cast<int>(fb_.height)); ++y) {
            for (int x = x0; x < std::min(x0 + kTileSize, static_cast<int>(fb_.width)); ++x) {
                float* c = dst + 4 * (static_cast<std::size_t>(y - y0) * kTileSize +
                                      static_cast<std::size_t>(x - x0));
                const std::size_t i =
                    4 * fb_.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
                for (std::size_t k = 0; k < 4; ++k) {
                    // ubyte_to_float: b * (1.0f / 255.0f).
                    c[k] = fb_.color_format == ColorFormat::Rgba8
                               ? static_cast<float>(fb_.color8[i + k]) * (1.0f / 255.0f)
                               : fb_.color32f[i + k];
                }
            }
        }
    }
    slot_tile_[static_cast<std::size_t>(slot)] = tile;
}

void SoftpipeTileCache::fetch(int x, int y) {
    const int tile = tile_of(x, y);
    const int slot = slot_of(tile);
    if (slot_tile_[static_cast<std::size_t>(slot)] == tile) return;
    write_back(slot);
    load(slot, tile);
}

float* SoftpipeTileCache::pixel(int x, int y) {
    const int slot = slot_of(tile_of(x, y));
    return data_.get() + static_cast<std::size_t>(slot) * kTileFloats +
           4 * (static_cast<std::size_t>(y % kTileSize) * kTileSize +
                static_cast<std::size_t>(x % kTileSize));
}

std::array<float, 4> SoftpipeTileCache::peek(int x, int y) const {
    const int tile = tile_of(x, y);
    const int slot = slot_of(tile);
    if (slot_tile_[static_cast<std::size_t>(slot)] == tile) {
        const float* c = data_.get() + static_cast<std::size_t>(slot) * kTileFloats +
                         4 * (static_cast<std::size_t>(y % kTileSize) * kTileSize +
                              static_cast<std::size_t>(x % kTileSize));
        return {c[0], c[1], c[2], c[3]};
    }
    if (flagged_clear_[static_cast<std::size_t>(tile)] != 0) return clear_;
    const std::size_t i =
        4 * fb_.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    std::array<float, 4> c{};
    for (std::size_t k = 0; k < 4; ++k) {
        c[k] = fb_.color_format == ColorFormat::Rgba8
                   ? static_cast<float>(fb_.color8[i + k]) * (1.0f / 255.0f)
                   : fb_.color32f[i + k];
    }
    return c;
}

void SoftpipeTileCache::flush() {
    for (int s = 0; s < kSlots; ++s) write_back(s);
    // sp_tile_cache_flush_clear: the clear colour into every tile still flagged.
    for (std::size_t t = 0; t < flagged_clear_.size(); ++t) {
        if (flagged_clear_[t] == 0) continue;
        const int tile = static_cast<int>(t);
        const int x0 = (tile % tiles_x_) * kTileSize;
        const int y0 = (tile / tiles_x_) * kTileSize;
        for (int y = y0; y < std::min(y0 + kTileSize, static_cast<int>(fb_.height)); ++y) {
            for (int x = x0; x < std::min(x0 + kTileSize, static_cast<int>(fb_.width)); ++x) {
                const std::size_t i =
                    4 * fb_.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
                for (std::size_t k = 0; k < 4; ++k) {
                    if (fb_.color_format == ColorFormat::Rgba8) {
                        fb_.color8[i + k] = to_unorm8(clear_[k]);
                    } else {
                        fb_.color32f[i + k] = clear_[k];
                    }
                }
            }
        }
        flagged_clear_[t] = 0;
    }
}

}  // namespace refraster::detail
