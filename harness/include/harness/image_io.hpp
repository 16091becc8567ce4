// image_io.hpp: image files, and nothing else (the only libpng user, and the only user of the
// OpenImageIO codec module: src/io/oiio_codec.hpp).
//
// Implements: writing a Framebuffer's colour as an 8-bit RGBA PNG (rgba8) or a float32 EXR
// (rgba32f), top row first as image files are, atomically (a temporary file renamed into
// place, so a failed write leaves nothing behind); reading such files back into bottom-up rows;
// decoding 8-bit PNGs as texture images for the scene loader (extension "textures") with libpng
// alone, which this library installs as the loader's texture file reader (scene.hpp,
// set_texture_file_reader).
//
// PNGs are written and 8-bit RGB(A) PNGs read with libpng in the program itself; EXRs, GIFs and
// every other file read back go through OpenImageIO in a module loaded the first time one is met
// (docs/library.md), so a program that only writes PNGs never loads OpenImageIO.
//
// Deliberately does not: compare files by their bytes (comparisons work on decoded pixels).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "harness/scene.hpp"
#include "refraster/draw.hpp"
#include "refraster/error.hpp"
#include "refraster/framebuffer.hpp"

namespace harness {

class ImageIoError : public refraster::Error {
  public:
    explicit ImageIoError(const std::string& message)
        : refraster::Error(refraster::ExitClass::BadInput, message) {}
};

// The file extension a target's colour is written with: ".png" or ".exr".
std::string_view image_extension(refraster::ColorFormat f);

void write_color_image(const refraster::Framebuffer& fb, const std::filesystem::path& path);

// Writes every image or none: each is written to a hidden partial file beside its destination,
// and they are moved into place only once all are written. Every extension is checked first.
using ImageToWrite = std::pair<const refraster::Framebuffer*, std::filesystem::path>;
void write_color_images(const std::vector<ImageToWrite>& images);

// Writes RGBA8 `frames` of one size as an animated GIF (its extension must be ".gif") that
// shows `frames_per_second` frames a second and loops forever; written atomically like every
// image. Throws ImageIoError for no frames, frames of another format or size, or a failed write.
void write_color_animation(const std::vector<refraster::Framebuffer>& frames,
                           const std::filesystem::path& path, int frames_per_second);

// The files one image a sample goes to: PREFIX.s0.png .. PREFIX.s3.png (.exr for rgba32f).
std::vector<std::filesystem::path> sample_image_paths(const std::filesystem::path& prefix,
                                                      std::uint32_t samples,
                                                      refraster::ColorFormat format);

// Reads a PNG (as rgba8) or an EXR (as rgba32f). Depth is not stored in image files.
refraster::Framebuffer read_color_image(const std::filesystem::path& path);

// Decodes `png`, the bytes of a PNG file of 8-bit channels, as RGBA8 texels, rows bottom to top
// as glTexImage2D takes them (the file's top row last), with libpng's PNG decoder alone (no
// other format is ever tried, and libpng prints nothing). RGBA as stored (alpha not multiplied
// in), RGB with alpha 255, grey g as (g, g, g, 255), grey and alpha as (g, g, g, a), a palette
// image as its palette's colours; a tRNS chunk makes an RGB or grey pixel that equals its
// colour exactly transparent (alpha 0) and gives palette entries their alpha (255 past its
// end), as PNG means it. Gamma, colour profiles and every chunk but IHDR, PLTE, tRNS, IDAT and
// IEND are ignored. Anything but a PNG, channels of 1, 2, 4 (grey) or 16 bits, a side past
// 4096, a palette index past the palette and any fault of the file are refused (ImageIoError).
refraster::TextureImage read_texture_png(std::span<const std::uint8_t> png);

}  // namespace harness
