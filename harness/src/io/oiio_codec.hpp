// oiio_codec.hpp: the interface between image_io.cpp and the OpenImageIO codec module
// (oiio_codec.cpp, built as a module of its own and loaded by image_io.cpp on first use).
//
// Implements: the table of functions the module exports under one C name, and its version. PNG
// files of 8-bit RGB or RGBA are written and read by image_io.cpp with libpng; everything else
// (EXR, animated GIF, PNGs of other kinds, any other file read back) goes through here, so a
// program that writes only PNGs never loads OpenImageIO and the libraries it pulls in.
//
// Deliberately does not: throw across the module boundary (every function returns its error
// as a message), or know about Framebuffer (the module links no part of refraster).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace harness::detail {

// Four values a pixel, rows bottom to top (a window's row order): 8-bit or float.
struct CodecImage {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    bool is8 = true;
    std::vector<std::uint8_t> rgba8;
    std::vector<float> rgba32f;
};

// Raised whenever a function's signature or meaning changes: a module of another version is
// refused rather than called.
inline constexpr std::uint32_t kOiioCodecVersion = 1;

struct OiioCodec {
    std::uint32_t version = kOiioCodecVersion;
    // Each returns "" on success, else the reason (without the file's name).
    // `pixels`: width * height * 4 bytes (is8) or floats, rows bottom to top; written to
    // `file`, whose extension chooses the format.
    std::string (*write_image)(const char* file, std::uint32_t width, std::uint32_t height,
                               bool is8, const void* pixels);
    // RGBA8 frames of one size, rows bottom to top, as an animated GIF looping forever.
    std::string (*write_animation)(const char* file, std::uint32_t width, std::uint32_t height,
                                   const std::uint8_t* const* frames, std::size_t count,
                                   int frames_per_second);
    // Any file OpenImageIO reads: 8-bit files as rgba8, anything else as float; channels past
    // the file's own are 0, alpha 1 (255) when the file has none.
    std::string (*read_image)(const char* file, CodecImage& out);
};

}  // namespace harness::detail

// The module's one export.
extern "C" const harness::detail::OiioCodec* refraster_oiio_codec();
