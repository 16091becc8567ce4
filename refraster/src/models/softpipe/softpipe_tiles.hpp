// softpipe_tiles.hpp: softpipe's colour tile cache, where colours stay float until written back.
//
// Implements (gallium/drivers/softpipe/sp_tile_cache.c; docs/precision.md "softpipe"): the
// colour buffer seen through 50 cached tiles of 64x64 pixels, direct mapped (tile (tx, ty) in
// slot (tx + 5*ty) % 50), each holding float colours:
//  - a clear flags every tile clear and drops every slot without writing it back; a flagged
//    tile, when fetched, is filled with the raw clear colour (not converted, not clamped);
//  - the blend stage fetches the tile of each batch of quads it shades; fetching a tile whose
//    slot holds another writes that one back first (rgba8 through float_to_ubyte: clamp, then
//    RNE(fl(c * 255)); rgba32f unchanged) and loads the new one (a flagged tile from the clear
//    colour, otherwise from the surface: rgba8 byte * (1.0f / 255.0f));
//  - a flush (glReadPixels, and the blit of glGenerateMipmap) writes back every slot, then
//    the clear colour into every tile still flagged, and leaves the cache empty.
// So fragments and blending read and write unquantised floats in between: blending reads a
// raw clear colour of 0.3 as 0.3f, not 77/255, unless a write-back came between.
//
// Deliberately does not: cache depth (softpipe's depth tiles hold the stored values
// themselves, so caching them changes nothing), or know about quads.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "refraster/framebuffer.hpp"

namespace refraster::detail {

class SoftpipeTileCache {
  public:
    static constexpr int kTileSize = 64;  // TILE_SIZE
    static constexpr int kSlots = 50;     // NUM_ENTRIES

    // After a clear of `fb` to `clear` (fb's bytes or floats are not read until a tile is
    // loaded from the surface), or over fb as it is (no clear: every tile loads from it).
    // `truncate`: write rgba8 back by truncation (a profile's color_rounding=truncate).
    SoftpipeTileCache(Framebuffer& fb, const std::optional<std::array<float, 4>>& clear,
                      bool truncate = false);

    // The blend stage touches the tile holding pixel (x, y).
    void fetch(int x, int y);
    // The four float channels of pixel (x, y), whose tile must be fetched.
    float* pixel(int x, int y);
    // The four float channels pixel (x, y) would have when fetched, without fetching.
    std::array<float, 4> peek(int x, int y) const;
    // Everything written back into the framebuffer; the cache is empty afterwards.
    void flush();

  private:
    int tile_of(int x, int y) const { return (y / kTileSize) * tiles_x_ + x / kTileSize; }
    int slot_of(int tile) const { return (tile % tiles_x_ + 5 * (tile / tiles_x_)) % kSlots; }
    void write_back(int slot);
    std::uint8_t to_unorm8(float c) const;
    void load(int slot, int tile);

    Framebuffer& fb_;
    std::array<float, 4> clear_{};
    bool truncate_ = false;
    int tiles_x_ = 1;
    std::vector<std::uint8_t> flagged_clear_;  // a tile
    std::array<int, kSlots> slot_tile_{};      // -1: empty
    // kSlots tiles of 64 * 64 * 4 floats, never cleared: a load writes every pixel the tile
    // has in the surface before anything reads it, so untouched slots cost no page.
    std::unique_ptr<float[]> data_;
};

}  // namespace refraster::detail
