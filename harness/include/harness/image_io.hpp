// image_io.hpp: image files, and nothing else (the only OpenImageIO user).
//
// Implements: writing a Framebuffer's colour as an 8-bit RGBA PNG (rgba8) or a float32 EXR
// (rgba32f), top row first as image files are, atomically (a temporary file renamed into
// place, so a failed write leaves nothing behind); reading such files back into bottom-up rows;
// reading 8-bit PNGs as texture images for the scene loader (extension "textures"), which this
// library installs as the loader's texture file reader (scene.hpp, set_texture_file_reader).
//
// Deliberately does not: compare files by their bytes. OpenImageIO stamps metadata into PNGs;
// comparisons work on decoded pixels.
#pragma once

#include <filesystem>
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

// The files one image a sample goes to: PREFIX.s0.png .. PREFIX.s3.png (.exr for rgba32f).
std::vector<std::filesystem::path> sample_image_paths(const std::filesystem::path& prefix,
                                                      std::uint32_t samples,
                                                      refraster::ColorFormat format);

// Reads a PNG (as rgba8) or an EXR (as rgba32f). Depth is not stored in image files.
refraster::Framebuffer read_color_image(const std::filesystem::path& path);

// Reads a PNG of 8-bit channels as RGBA8 texels, rows bottom to top as glTexImage2D takes them
// (the file's top row last). RGBA as stored (alpha not multiplied in), RGB with alpha 255, grey
// g as (g, g, g, 255), grey and alpha as (g, g, g, a); a palette image as the RGB or RGBA its
// palette gives. Any other file, and channels of 1, 2, 4 or 16 bits, are refused
// (ImageIoError, naming the file). `check_size(width, height)`, when given, runs once the
// header is read and before any pixel is decoded; what it throws passes through.
refraster::TextureImage read_texture_png(const std::filesystem::path& path,
                                         const TextureSizeCheck& check_size = {});

}  // namespace harness
