// image_io.hpp: image files, and nothing else (the only OpenImageIO user).
//
// Implements: writing a Framebuffer's colour as an 8-bit RGBA PNG (rgba8) or a float32 EXR
// (rgba32f), top row first as image files are, atomically (a temporary file renamed into
// place, so a failed write leaves nothing behind); reading such files back into bottom-up rows.
//
// Deliberately does not: compare files by their bytes. OpenImageIO stamps metadata into PNGs;
// comparisons work on decoded pixels.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <utility>
#include <vector>

#include "refraster/framebuffer.hpp"

namespace harness {

class ImageIoError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// The file extension a target's colour is written with: ".png" or ".exr".
std::string_view image_extension(refraster::ColorFormat f);

void write_color_image(const refraster::Framebuffer& fb, const std::filesystem::path& path);

// Writes every image or none: each is written to a hidden partial file beside its destination,
// and they are moved into place only once all are written. Every extension is checked first.
using ImageToWrite = std::pair<const refraster::Framebuffer*, std::filesystem::path>;
void write_color_images(const std::vector<ImageToWrite>& images);

// The files one image a sample goes to: PREFIX.s0.png .. PREFIX.s3.png (.exr for rgba32f).
std::vector<std::filesystem::path> sample_image_paths(const std::filesystem::path& prefix,
                                                      std::uint32_t samples,
                                                      refraster::ColorFormat format);

// Reads a PNG (as rgba8) or an EXR (as rgba32f). Depth is not stored in image files.
refraster::Framebuffer read_color_image(const std::filesystem::path& path);

}  // namespace harness
