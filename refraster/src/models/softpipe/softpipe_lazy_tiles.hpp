// softpipe_lazy_tiles.hpp: softpipe's colour tile cache for the fast path, the same values
// without copying whole tiles.
//
// Implements the cache of softpipe_tiles.hpp (sp_tile_cache.c: 50 direct-mapped slots of
// 64x64 float pixels, tile (tx, ty) in slot (tx + 5*ty) % 50, clear flags, write-back on
// eviction and flush) so that every pixel reads and ends with the values that cache gives it,
// at a cost proportional to the pixels written rather than to the tiles touched:
//  - a slot keeps floats only for the pixels written since its tile was loaded (a bit a
//    pixel); any other pixel reads what the model's load would have put there: the raw clear
//    colour for a tile loaded while flagged clear, else the surface's value as the load
//    converts it (rgba8 byte * (1.0f / 255.0f), rgba32f the float);
//  - a write-back stores the written pixels (float_to_ubyte: clamp, then RNE(fl(c * 255)), as
//    the model's) and, for a tile loaded while flagged clear, the clear colour into the rest.
//    The model also writes back the pixels nobody wrote; for rgba8 each becomes
//    RNE(fl(fl(b * fl(1/255)) * 255)) = b again (every byte b survives the round trip:
//    softpipe_sameness_test.cpp checks all 256), and rgba32f is copied unchanged, so leaving
//    them alone gives the same surface.
// The order of loads and evictions is the model's, so which floats have been quantised when a
// blend reads them is the model's too.
//
// Deliberately does not: support color_rounding=truncate (a truncated byte does not survive
// the round trip: that profile keeps the model's cache, renderer.cpp), or peek for the trace
// (traced renders take the model's path).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "refraster/framebuffer.hpp"

namespace refraster::detail {

class SoftpipeLazyTiles {
  public:
    static constexpr int kTileSize = 64;  // TILE_SIZE
    static constexpr int kSlots = 50;     // NUM_ENTRIES

    // As SoftpipeTileCache's constructor (without truncation).
    SoftpipeLazyTiles(Framebuffer& fb, const std::optional<std::array<float, 4>>& clear);

    struct Slot {
        int tile = -1;  // -1: empty
        bool from_clear = false;
        std::array<std::uint64_t, kTileSize> written{};  // a row of the tile a word
        // 64 * 64 * 4, allocated at the slot's first load and never cleared: only the pixels
        // `written` marks are read, so a draw that touches one tile pays for one slot.
        std::unique_ptr<float[]> data;
    };

    // The blend stage touches the tile holding pixel (x, y) (SoftpipeTileCache::fetch); the
    // slot that holds it now, for the pixels of that tile.
    Slot& fetch(int x, int y) {
        const int tile = tile_of(x, y);
        const int slot = slot_of(tile);
        Slot& s = slots_[static_cast<std::size_t>(slot)];
        if (s.tile != tile) {
            write_back(s);
            load(s, tile);
        }
        return s;
    }
    // The four channels pixel (x, y) of the slot's tile holds in the cache.
    void read(const Slot& s, int x, int y, float* rgba) const {
        const int ox = x & (kTileSize - 1);
        const int oy = y & (kTileSize - 1);
        if (((s.written[static_cast<std::size_t>(oy)] >> ox) & 1u) != 0) {
            const float* c = s.data.get() + 4 * static_cast<std::size_t>(oy * kTileSize + ox);
            for (std::size_t k = 0; k < 4; ++k) rgba[k] = c[k];
            return;
        }
        read_unwritten(s, x, y, rgba);
    }
    // Where pixel (x, y) of the slot's tile is written; it counts as written from now on.
    static float* written(Slot& s, int x, int y) {
        const int ox = x & (kTileSize - 1);
        const int oy = y & (kTileSize - 1);
        s.written[static_cast<std::size_t>(oy)] |= std::uint64_t{1} << ox;
        return s.data.get() + 4 * static_cast<std::size_t>(oy * kTileSize + ox);
    }
    // Everything written back into the framebuffer; the cache is empty afterwards.
    void flush();

  private:
    int tile_of(int x, int y) const { return (y / kTileSize) * tiles_x_ + x / kTileSize; }
    int slot_of(int tile) const { return (tile % tiles_x_ + 5 * (tile / tiles_x_)) % kSlots; }
    void write_back(Slot& s);
    void load(Slot& s, int tile);
    // A pixel not written since its tile was loaded: what the model's load put there.
    void read_unwritten(const Slot& s, int x, int y, float* rgba) const;
    // The clear colour into pixels [x0, x1) of row y, as a write-back stores it.
    void store_clear(int y, int x0, int x1);

    Framebuffer& fb_;
    std::array<float, 4> clear_{};
    std::array<std::uint8_t, 4> clear8_{};  // the clear colour as a write-back stores it
    int tiles_x_ = 1;
    std::vector<std::uint8_t> flagged_clear_;  // a tile
    std::array<Slot, kSlots> slots_;
};

}  // namespace refraster::detail
