#include "harness/image_io.hpp"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <array>
#include <fstream>
#include <system_error>

#include "harness/files.hpp"

namespace harness {

namespace OIIO = OIIO_NAMESPACE;

std::string_view image_extension(refraster::ColorFormat f) {
    return f == refraster::ColorFormat::Rgba8 ? ".png" : ".exr";
}

namespace {

void check_extension(const refraster::Framebuffer& fb, const std::filesystem::path& path) {
    const std::string ext = path.extension().string();
    if (ext != std::string(image_extension(fb.color_format))) {
        throw ImageIoError(path.string() + ": a " + std::string(to_string(fb.color_format)) +
                           " target is written as " +
                           std::string(image_extension(fb.color_format)) + ", not " +
                           (ext.empty() ? "a file without extension" : ext));
    }
}

// Writes `fb` into the file `tmp`; messages name `path`, the file it becomes.
void write_image_file(const refraster::Framebuffer& fb, const std::filesystem::path& path,
                      const std::filesystem::path& tmp) {
    const bool is8 = fb.color_format == refraster::ColorFormat::Rgba8;
    const std::string ext = path.extension().string();
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out) throw ImageIoError(path.string() + ": cannot create an image writer for " + ext);
    const OIIO::TypeDesc type = is8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
    OIIO::ImageSpec spec(static_cast<int>(fb.width), static_cast<int>(fb.height), 4, type);
    // Pixels are stored as rendered: PNG alpha is unassociated, and without this attribute
    // OpenImageIO would divide the colour by alpha on the way out.
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!out->open(tmp.string(), spec)) {
        throw ImageIoError(path.string() + ": cannot write: " + out->geterror());
    }
    // Image files store the top row first: file row 0 is window row height-1.
    const std::size_t row_floats = std::size_t{fb.width} * 4;
    bool ok = true;
    for (std::uint32_t row = 0; ok && row < fb.height; ++row) {
        const std::uint32_t src = fb.height - 1 - row;
        const void* data = is8 ? static_cast<const void*>(fb.color8.data() + src * row_floats)
                               : static_cast<const void*>(fb.color32f.data() + src * row_floats);
        ok = out->write_scanline(static_cast<int>(row), 0, type, data);
    }
    ok = out->close() && ok;
    if (!ok) throw ImageIoError(path.string() + ": cannot write: " + out->geterror());
}

// Writes images[k..] inside one another's write_atomically: every file is written before the
// first is moved into place, and a failure removes every partial file.
void write_nested(const std::vector<ImageToWrite>& images, std::size_t k) {
    if (k == images.size()) return;
    const auto& [fb, path] = images[k];
    write_atomically(path, [&](const std::filesystem::path& tmp) {
        write_image_file(*fb, path, tmp);
        write_nested(images, k + 1);
    });
}

}  // namespace

void write_color_image(const refraster::Framebuffer& fb, const std::filesystem::path& path) {
    check_extension(fb, path);
    // Written beside the destination and moved into place (files.hpp): never a partial image.
    write_atomically(path,
                     [&](const std::filesystem::path& tmp) { write_image_file(fb, path, tmp); });
}

void write_color_images(const std::vector<ImageToWrite>& images) {
    for (const auto& [fb, path] : images) check_extension(*fb, path);
    write_nested(images, 0);
}

std::vector<std::filesystem::path> sample_image_paths(const std::filesystem::path& prefix,
                                                      std::uint32_t samples,
                                                      refraster::ColorFormat format) {
    std::vector<std::filesystem::path> out;
    for (std::uint32_t s = 0; s < samples; ++s) {
        out.emplace_back(prefix.string() + ".s" + std::to_string(s) +
                         std::string(image_extension(format)));
    }
    return out;
}

refraster::Framebuffer read_color_image(const std::filesystem::path& path) {
    // Keep the colour as stored: without this, PNG colour is multiplied by alpha on reading.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path.string(), &config);
    if (!in) throw ImageIoError(path.string() + ": cannot read: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < 1) {
        throw ImageIoError(path.string() + ": empty image");
    }
    const bool is8 = spec.format == OIIO::TypeDesc::UINT8;
    refraster::Framebuffer fb(static_cast<std::uint32_t>(spec.width),
                              static_cast<std::uint32_t>(spec.height),
                              is8 ? refraster::ColorFormat::Rgba8 : refraster::ColorFormat::Rgba32f,
                              refraster::DepthFormat::None);
    const int nch = std::min(spec.nchannels, 4);
    const OIIO::TypeDesc type = is8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
    const std::size_t row_values = std::size_t{fb.width} * 4;
    const auto pixel_stride = static_cast<OIIO::stride_t>(4 * type.size());
    const auto row_stride = static_cast<OIIO::stride_t>(row_values * type.size());
    // Read the top file row into the last buffer row: a negative row stride flips.
    void* last_row = is8 ? static_cast<void*>(fb.color8.data() + (fb.height - 1) * row_values)
                         : static_cast<void*>(fb.color32f.data() + (fb.height - 1) * row_values);
    if (!in->read_image(0, 0, 0, nch, type, last_row, pixel_stride, -row_stride)) {
        throw ImageIoError(path.string() + ": cannot read: " + in->geterror());
    }
    if (nch < 4) {  // a file without alpha is opaque
        for (std::size_t i = 0; i < fb.pixel_count(); ++i) {
            if (is8) {
                fb.color8[i * 4 + 3] = 255;
            } else {
                fb.color32f[i * 4 + 3] = 1.0f;
            }
        }
    }
    in->close();
    return fb;
}

namespace {

// The bit depth and colour type of a PNG's header (IHDR, always the first chunk: the 8-byte
// signature, the chunk's length and type, width, height, then these two bytes). OpenImageIO
// expands 1, 2 and 4-bit grey to 8 bits without saying so in its spec.
std::pair<int, int> png_depth_and_color_type(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::array<char, 26> h{};
    if (!in.read(h.data(), h.size()) || std::string_view(h.data() + 12, 4) != "IHDR") {
        throw ImageIoError(path.string() + ": cannot read the PNG header");
    }
    return {static_cast<unsigned char>(h[24]), static_cast<unsigned char>(h[25])};
}

}  // namespace

refraster::TextureImage read_texture_png(const std::filesystem::path& path,
                                         const TextureSizeCheck& check_size) {
    // Keep the colour as stored: without this, PNG colour is multiplied by alpha on reading.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path.string(), &config);
    if (!in) throw ImageIoError(path.string() + ": cannot read: " + OIIO::geterror());
    if (std::string_view(in->format_name()) != "png") {
        throw ImageIoError(path.string() + ": a file of format " + in->format_name() +
                           "; textures are read from PNG files");
    }
    const OIIO::ImageSpec& spec = in->spec();
    const auto [depth, color_type] = png_depth_and_color_type(path);
    constexpr int kPalette = 3;
    if (spec.format != OIIO::TypeDesc::UINT8 || (depth != 8 && color_type != kPalette)) {
        throw ImageIoError(path.string() + ": " + std::to_string(depth) +
                           "-bit channels; textures are read from PNGs of 8-bit channels");
    }
    const int nch = spec.nchannels;
    if (spec.width <= 0 || spec.height <= 0 || nch < 1 || nch > 4) {
        throw ImageIoError(path.string() + ": " + std::to_string(nch) +
                           " channels; expected grey, grey and alpha, RGB or RGBA");
    }
    const auto width = static_cast<std::uint32_t>(spec.width);
    const auto height = static_cast<std::uint32_t>(spec.height);
    if (check_size) check_size(width, height);
    refraster::TextureImage image;
    image.width = width;
    image.height = height;
    const auto channels = static_cast<std::size_t>(nch);
    const std::size_t pixels = std::size_t{width} * height;
    std::vector<std::uint8_t> stored(pixels * channels);
    const std::size_t row_bytes = std::size_t{width} * channels;
    // The file's top row into the last row: a negative row stride flips.
    std::uint8_t* last_row = stored.data() + (std::size_t{height} - 1) * row_bytes;
    if (!in->read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT8, last_row,
                        static_cast<OIIO::stride_t>(channels),
                        -static_cast<OIIO::stride_t>(row_bytes))) {
        throw ImageIoError(path.string() + ": cannot read: " + in->geterror());
    }
    in->close();
    image.rgba.resize(pixels * 4);
    for (std::size_t i = 0; i < pixels; ++i) {
        const std::uint8_t* p = stored.data() + i * channels;
        std::uint8_t* t = image.rgba.data() + i * 4;
        if (nch <= 2) {
            t[0] = t[1] = t[2] = p[0];
            t[3] = nch == 2 ? p[1] : 255;
        } else {
            t[0] = p[0];
            t[1] = p[1];
            t[2] = p[2];
            t[3] = nch == 4 ? p[3] : 255;
        }
    }
    return image;
}

namespace {

// The loader reads texture files through read_texture_png in every program that links this
// library (scene.hpp). Every such program uses this file's writers or readers too, so the
// linker always keeps it and this registration.
const bool kTextureReaderInstalled = [] {
    set_texture_file_reader(&read_texture_png);
    return true;
}();

}  // namespace

}  // namespace harness
