// texture_file.hpp: the files a scene may read as textures (docs/scene-format.md, "Texture
// files"): where they may lie, what they must be, and the PNG header read before any decoder
// runs. Used by the loader (scene_reader.cpp) only.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace harness::texture_file {

// The folders texture files may lie under, as real paths (every symlink resolved, absolute, no
// `.` or `..`). A folder that does not resolve (it does not exist) contributes nothing.
std::vector<std::string> real_roots(const std::vector<std::filesystem::path>& folders);

// Whether the real path `real` lies strictly inside the real folder `root`, component by
// component ("/a/bc" is not inside "/a/b").
bool inside(const std::string& real, const std::string& root);

// What reading a texture file gave.
enum class Status {
    Ok,        // `bytes` holds the whole file, which starts with PNG's signature
    Unusable,  // missing, unreadable, not a regular file, outside every root, or not a PNG
    TooLarge,  // a PNG under a root, of `size` bytes, more than the limit
};
struct FileBytes {
    Status status = Status::Unusable;
    std::uint64_t size = 0;
    std::vector<std::uint8_t> bytes;
};

// Reads `path` (relative names start from the working directory) when its real path lies inside
// one of `roots` (real_roots): a regular file, opened without blocking (a FIFO never blocks) and
// checked again once open, whose first 8 bytes are PNG's signature and whose size is at most
// `max_bytes`. Nothing is opened outside the roots, and nothing but the signature is read
// before the size is checked. Never throws for a file that cannot be used: every such file is
// Unusable alike, so that the caller's message cannot tell which one it was.
FileBytes read_png_file(const std::filesystem::path& path, const std::vector<std::string>& roots,
                        std::uint64_t max_bytes);

// The header (IHDR, the first chunk) of a PNG file.
struct PngHeader {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::uint8_t bit_depth = 0;
    std::uint8_t color_type = 0;  // 0 grey, 2 RGB, 3 palette, 4 grey and alpha, 6 RGBA
};

// The header of `bytes` when they start with PNG's signature and an IHDR chunk of 13 bytes
// whose values PNG allows (ISO/IEC 15948, 11.2.2: width and height 1 to 2^31 - 1, a bit depth
// the colour type allows, compression and filter method 0, interlace method 0 or 1); nullopt
// otherwise. The chunk's CRC is the decoder's to check.
std::optional<PngHeader> png_header(std::span<const std::uint8_t> bytes);

}  // namespace harness::texture_file
