#include "harness/image_io.hpp"

#include <dlfcn.h>
#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <system_error>

#include "harness/files.hpp"
#include "oiio_codec.hpp"

namespace harness {

namespace {

// The OpenImageIO codec module (oiio_codec.hpp), loaded the first time it is needed and kept.
// It is looked for in $REFRASTER_CODEC_DIR when that is set, beside the running program (a build
// tree keeps it in bin/ with the tools), at REFRASTER_CODEC_RELATIVE_DIR from the program's
// directory (an installation: lib/refraster beside bin/) and in the directory the build was
// configured to install it to (programs installed elsewhere that link this library).
struct LoadedCodec {
    const detail::OiioCodec* codec = nullptr;
    std::string error;
};

LoadedCodec load_codec() {
    std::vector<std::filesystem::path> dirs;
    if (const char* dir = std::getenv("REFRASTER_CODEC_DIR"); dir != nullptr && *dir != '\0') {
        dirs.emplace_back(dir);
    } else {
        std::error_code ec;
        const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
        if (!ec) {
            dirs.push_back(self.parent_path());
            dirs.push_back(self.parent_path() / REFRASTER_CODEC_RELATIVE_DIR);
        }
        dirs.emplace_back(REFRASTER_CODEC_INSTALL_DIR);
    }
    std::string looked;
    for (const auto& dir : dirs) {
        const auto file = (dir / REFRASTER_CODEC_NAME).lexically_normal();
        looked += (looked.empty() ? "" : ", ") + file.string();
        if (::access(file.c_str(), R_OK) != 0) continue;
        void* module = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (module == nullptr)
            return {nullptr, "cannot load " + file.string() + ": " + ::dlerror()};
        using Entry = const detail::OiioCodec* (*)();
        auto entry = reinterpret_cast<Entry>(::dlsym(module, "refraster_oiio_codec"));
        const detail::OiioCodec* codec = entry != nullptr ? entry() : nullptr;
        if (codec == nullptr || codec->version != detail::kOiioCodecVersion) {
            return {nullptr, file.string() + " is not this build's image codec module"};
        }
        return {codec, {}};
    }
    return {nullptr, "this image format needs the OpenImageIO codec module " +
                         std::string(REFRASTER_CODEC_NAME) + ", found in none of " + looked +
                         " (set REFRASTER_CODEC_DIR to the directory that holds it)"};
}

const detail::OiioCodec& oiio_codec(const std::filesystem::path& file) {
    static const LoadedCodec loaded = load_codec();
    if (loaded.codec == nullptr) throw ImageIoError(file.string() + ": " + loaded.error);
    return *loaded.codec;
}

}  // namespace

namespace {

// libpng's messages are not printed: a file that cannot be decoded is reported once, by the
// caller. The error handler keeps the message and returns to png_decode's setjmp.
struct PngSource {
    std::span<const std::uint8_t> bytes;
    std::size_t at = 0;
    const char* error = nullptr;  // libpng's message, a literal of its own
};

[[noreturn]] void png_error_handler(png_structp png, png_const_charp message) {
    static_cast<PngSource*>(png_get_error_ptr(png))->error = message;
    png_longjmp(png, 1);
}

void png_warning_handler(png_structp /*png*/, png_const_charp /*message*/) {}

void png_read_from_memory(png_structp png, png_bytep out, std::size_t n) {
    auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
    if (source->bytes.size() - source->at < n) png_error(png, "the file ends early");
    std::memcpy(out, source->bytes.data() + source->at, n);
    source->at += n;
}

// The PNG's samples as stored, 8 bits each (palette images: one index a byte), into `rows`
// (one pointer a row, in file order); its palette and transparency into `palette` (256 RGBA
// entries) and `trns` (the grey or RGB colour that is transparent, when tRNS gives one).
// Everything that owns memory lives in the caller: a libpng error returns here by longjmp.
// Returns libpng's message, nullptr on success.
struct PngTransparency {
    bool has_colour = false;
    std::array<std::uint16_t, 3> colour{};  // grey in [0], or red, green, blue
};

const char* png_decode(PngSource& source, std::uint32_t width, std::uint32_t height, int channels,
                       png_bytep* rows, std::array<std::array<std::uint8_t, 4>, 256>& palette,
                       int& palette_entries, PngTransparency& trns) {
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &source, png_error_handler,
                                             png_warning_handler);
    if (png == nullptr) return "cannot allocate a decoder";
    png_infop info = png_create_info_struct(png);
    if (info == nullptr) {
        png_destroy_read_struct(&png, nullptr, nullptr);
        return "cannot allocate a decoder";
    }
    if (setjmp(png_jmpbuf(png))) {  // NOLINT(cert-err52-cpp): libpng's error return
        png_destroy_read_struct(&png, &info, nullptr);
        return source.error != nullptr ? source.error : "cannot decode";
    }
    png_set_read_fn(png, &source, png_read_from_memory);
    // Only the chunks a texture needs: IHDR, PLTE, tRNS, IDAT, IEND; every other chunk, known
    // or not, is skipped unread (no text or colour profile is decompressed).
    png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, nullptr, -1);
    png_set_user_limits(png, width, height);
    png_set_chunk_malloc_max(png, std::size_t{1} << 20);
    png_read_info(png, info);
    if (png_get_image_width(png, info) != width || png_get_image_height(png, info) != height ||
        png_get_bit_depth(png, info) > 8 || png_get_channels(png, info) != channels) {
        png_error(png, "the header changed");
    }
    const int color_type = png_get_color_type(png, info);
    if (color_type == PNG_COLOR_TYPE_PALETTE) {
        png_colorp entries = nullptr;
        if (png_get_PLTE(png, info, &entries, &palette_entries) == 0) {
            png_error(png, "a palette image without a palette");
        }
        for (int i = 0; i < palette_entries && i < 256; ++i) {
            palette[static_cast<std::size_t>(i)] = {entries[i].red, entries[i].green,
                                                    entries[i].blue, 255};
        }
        png_set_packing(png);  // 1, 2 and 4-bit indices one a byte
    }
    png_bytep alpha = nullptr;
    int alpha_entries = 0;
    png_color_16p colour = nullptr;
    if (png_get_tRNS(png, info, &alpha, &alpha_entries, &colour) != 0) {
        if (color_type == PNG_COLOR_TYPE_PALETTE) {
            for (int i = 0; i < alpha_entries && i < 256; ++i) {
                palette[static_cast<std::size_t>(i)][3] = alpha[i];
            }
        } else if (colour != nullptr) {
            trns.has_colour = true;
            trns.colour =
                color_type == PNG_COLOR_TYPE_GRAY
                    ? std::array<std::uint16_t, 3>{colour->gray, 0, 0}
                    : std::array<std::uint16_t, 3>{colour->red, colour->green, colour->blue};
        }
    }
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    if (png_get_rowbytes(png, info) != std::size_t{width} * static_cast<std::size_t>(channels)) {
        png_error(png, "unexpected row size");
    }
    png_read_image(png, rows);
    png_destroy_read_struct(&png, &info, nullptr);
    return nullptr;
}

}  // namespace

namespace {

// The fields of a PNG's IHDR that choose how it is read; nullopt when the bytes do not start
// with the PNG signature and an IHDR chunk (always the first).
struct PngHeader {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    int depth = 0;
    int color_type = 0;
};

std::optional<PngHeader> png_header(std::span<const std::uint8_t> png) {
    static constexpr std::array<std::uint8_t, 8> kSignature = {0x89, 'P',  'N',  'G',
                                                               '\r', '\n', 0x1a, '\n'};
    if (png.size() < 33 || !std::equal(kSignature.begin(), kSignature.end(), png.begin()) ||
        std::memcmp(png.data() + 12, "IHDR", 4) != 0) {
        return std::nullopt;
    }
    const auto u32 = [&](std::size_t at) {
        return (std::uint32_t{png[at]} << 24) | (std::uint32_t{png[at + 1]} << 16) |
               (std::uint32_t{png[at + 2]} << 8) | std::uint32_t{png[at + 3]};
    };
    return PngHeader{u32(16), u32(20), png[24], png[25]};
}

// A PNG's samples as stored, `channels` a pixel in file row order, with its palette and
// transparency (png_decode); libpng's message, prefixed, in ImageIoError on a fault.
struct PngSamples {
    std::vector<std::uint8_t> stored;
    std::array<std::array<std::uint8_t, 4>, 256> palette{};
    int palette_entries = 0;
    PngTransparency trns;
};

PngSamples png_samples(std::span<const std::uint8_t> png, const PngHeader& h, int channels,
                       const std::string& error_prefix) {
    PngSamples out;
    const auto nch = static_cast<std::size_t>(channels);
    out.stored.resize(std::size_t{h.width} * h.height * nch);
    std::vector<png_bytep> rows(h.height);
    for (std::uint32_t r = 0; r < h.height; ++r) rows[r] = out.stored.data() + r * h.width * nch;
    PngSource source{png};
    if (const char* error = png_decode(source, h.width, h.height, channels, rows.data(),
                                       out.palette, out.palette_entries, out.trns)) {
        throw ImageIoError(error_prefix + error);
    }
    return out;
}

// libpng's write callbacks report through the same handler as its reads (PngSource::error).
const char* png_encode(std::FILE* file, PngSource& errors, std::uint32_t width,
                       std::uint32_t height, png_bytep* rows) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &errors, png_error_handler,
                                              png_warning_handler);
    if (png == nullptr) return "cannot allocate an encoder";
    png_infop info = png_create_info_struct(png);
    if (info == nullptr) {
        png_destroy_write_struct(&png, nullptr);
        return "cannot allocate an encoder";
    }
    if (setjmp(png_jmpbuf(png))) {  // NOLINT(cert-err52-cpp): libpng's error return
        png_destroy_write_struct(&png, &info);
        return errors.error != nullptr ? errors.error : "cannot encode";
    }
    png_init_io(png, file);
    // zlib's fastest level: writing a smooth-shaded 1024 x 1024 render took a third of the time
    // of the default level (6), for a file 27% larger (docs/performance.md, "Process start").
    png_set_compression_level(png, 1);
    png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return nullptr;
}

// An rgba8 target as an 8-bit RGBA PNG (alpha unassociated, as rendered), top row first.
void write_png_rgba8(const refraster::Framebuffer& fb, const std::filesystem::path& path,
                     const std::filesystem::path& tmp) {
    std::vector<png_bytep> rows(fb.height);
    const std::size_t row_bytes = std::size_t{fb.width} * 4;
    for (std::uint32_t r = 0; r < fb.height; ++r) {
        // const_cast: libpng's row type is not const, and writing only reads the rows.
        rows[r] = const_cast<png_bytep>(fb.color8.data() + (fb.height - 1 - r) * row_bytes);
    }
    std::FILE* file = std::fopen(tmp.c_str(), "wb");
    if (file == nullptr) {
        throw ImageIoError(path.string() + ": cannot write: " + std::strerror(errno));
    }
    PngSource errors;
    const char* error = png_encode(file, errors, fb.width, fb.height, rows.data());
    const bool closed = std::fclose(file) == 0;
    if (error == nullptr && !closed) error = "cannot close the file";
    if (error != nullptr) throw ImageIoError(path.string() + ": cannot write: " + error);
}

// A PNG of 8-bit RGB or RGBA (without a transparent colour) decoded with libpng, rows bottom
// to top; nullopt for any other file, which the codec module reads.
std::optional<refraster::Framebuffer> read_plain_png(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::error_code ec;
        throw ImageIoError(
            path.string() + ": cannot read: " +
            (std::filesystem::exists(path, ec) ? "cannot open the file" : "no such file"));
    }
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                    std::istreambuf_iterator<char>());
    const auto h = png_header(bytes);
    const int channels = !h ? 0 : h->color_type == 6 ? 4 : h->color_type == 2 ? 3 : 0;
    constexpr std::uint32_t kMaxSide = 16384;
    if (!h || h->depth != 8 || channels == 0 || h->width < 1 || h->height < 1 ||
        h->width > kMaxSide || h->height > kMaxSide) {
        return std::nullopt;
    }
    const PngSamples samples = png_samples(bytes, *h, channels, path.string() + ": cannot read: ");
    if (samples.trns.has_colour) return std::nullopt;
    const std::uint32_t width = h->width;
    const std::uint32_t height = h->height;
    const auto nch = static_cast<std::size_t>(channels);
    const std::vector<std::uint8_t>& stored = samples.stored;
    refraster::Framebuffer fb(width, height, refraster::ColorFormat::Rgba8,
                              refraster::DepthFormat::None);
    for (std::uint32_t r = 0; r < height; ++r) {
        const std::uint8_t* src = stored.data() + std::size_t{r} * width * nch;
        std::uint8_t* dst = fb.color8.data() + std::size_t{height - 1 - r} * width * 4;
        for (std::uint32_t x = 0; x < width; ++x, src += nch, dst += 4) {
            std::copy_n(src, nch, dst);
            if (nch == 3) dst[3] = 255;  // a file without alpha is opaque
        }
    }
    return fb;
}

}  // namespace

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

// Writes `fb` into the file `tmp`; messages name `path`, the file it becomes. PNGs go through
// libpng here, EXRs through the codec module.
void write_image_file(const refraster::Framebuffer& fb, const std::filesystem::path& path,
                      const std::filesystem::path& tmp) {
    if (fb.color_format == refraster::ColorFormat::Rgba8) {
        write_png_rgba8(fb, path, tmp);
        return;
    }
    const std::string error =
        oiio_codec(path).write_image(tmp.c_str(), fb.width, fb.height, false, fb.color32f.data());
    if (!error.empty()) throw ImageIoError(path.string() + ": " + error);
}

// Writes images[k..] inside one another's write_atomically: every file is written before the
// first is moved into place, and a failure removes every partial file.
void write_nested(const std::vector<ImageToWrite>& images, std::size_t k) {
    if (k == images.size()) return;
    const refraster::Framebuffer& fb = *images[k].first;
    const std::filesystem::path& path = images[k].second;
    write_atomically(path, [&](const std::filesystem::path& tmp) {
        write_image_file(fb, path, tmp);
        write_nested(images, k + 1);
    });
}

}  // namespace

void write_color_animation(const std::vector<refraster::Framebuffer>& frames,
                           const std::filesystem::path& path, int frames_per_second) {
    if (path.extension() != ".gif")
        throw ImageIoError(path.string() + ": an animation is written as .gif");
    if (frames.empty()) throw ImageIoError(path.string() + ": an animation of no frames");
    for (const auto& f : frames) {
        if (f.color_format != refraster::ColorFormat::Rgba8 || f.width != frames[0].width ||
            f.height != frames[0].height || f.width == 0 || f.height == 0)
            throw ImageIoError(path.string() +
                               ": the frames of an animation are rgba8 images "
                               "of one size");
    }
    const detail::OiioCodec& codec = oiio_codec(path);
    std::vector<const std::uint8_t*> pixels;
    for (const auto& f : frames) pixels.push_back(f.color8.data());
    write_atomically(path, [&](const std::filesystem::path& tmp) {
        const std::string error =
            codec.write_animation(tmp.c_str(), frames[0].width, frames[0].height, pixels.data(),
                                  pixels.size(), frames_per_second);
        if (!error.empty()) throw ImageIoError(path.string() + ": " + error);
    });
}

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
    if (auto fb = read_plain_png(path)) return std::move(*fb);
    detail::CodecImage image;
    const std::string error = oiio_codec(path).read_image(path.c_str(), image);
    if (!error.empty()) throw ImageIoError(path.string() + ": " + error);
    refraster::Framebuffer fb(
        image.width, image.height,
        image.is8 ? refraster::ColorFormat::Rgba8 : refraster::ColorFormat::Rgba32f,
        refraster::DepthFormat::None);
    if (image.is8) {
        std::copy(image.rgba8.begin(), image.rgba8.end(), fb.color8.begin());
    } else {
        std::copy(image.rgba32f.begin(), image.rgba32f.end(), fb.color32f.begin());
    }
    return fb;
}

refraster::TextureImage read_texture_png(std::span<const std::uint8_t> png) {
    // The signature and IHDR (always the first chunk), checked here so that nothing but a PNG
    // reaches the decoder.
    const auto h = png_header(png);
    if (!h) throw ImageIoError("not a PNG file");
    const std::uint32_t width = h->width;
    const std::uint32_t height = h->height;
    const int depth = h->depth;
    const int color_type = h->color_type;
    constexpr std::uint32_t kMaxSide = 4096;  // the scene format's texture limit
    if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide) {
        throw ImageIoError("a PNG of " + std::to_string(width) + " x " + std::to_string(height) +
                           " pixels; textures are 1 to 4096 pixels a side");
    }
    constexpr int kPalette = 3;
    if (depth != 8 && color_type != kPalette) {
        throw ImageIoError(std::to_string(depth) +
                           "-bit channels; textures are read from PNGs of 8-bit channels");
    }
    // Samples a pixel as stored: grey 1, palette index 1, grey and alpha 2, RGB 3, RGBA 4.
    const int channels = color_type == 0 || color_type == kPalette ? 1
                         : color_type == 4                         ? 2
                         : color_type == 2                         ? 3
                         : color_type == 6                         ? 4
                                                                   : 0;
    if (channels == 0) throw ImageIoError("a PNG of unknown colour type");
    const std::size_t pixels = std::size_t{width} * height;
    const auto nch = static_cast<std::size_t>(channels);
    const PngSamples samples = png_samples(png, *h, channels, "cannot decode the PNG: ");
    const auto& [stored, palette, palette_entries, trns] = samples;
    refraster::TextureImage image;
    image.width = width;
    image.height = height;
    image.rgba.resize(pixels * 4);
    // The file's top row is the texture's last.
    for (std::uint32_t r = 0; r < height; ++r) {
        const std::uint8_t* in = stored.data() + std::size_t{r} * width * nch;
        std::uint8_t* out = image.rgba.data() + std::size_t{height - 1 - r} * width * 4;
        for (std::uint32_t x = 0; x < width; ++x, in += nch, out += 4) {
            switch (color_type) {
                case kPalette:
                    if (in[0] >= palette_entries) {
                        throw ImageIoError("cannot decode the PNG: palette index " +
                                           std::to_string(in[0]) + " past its " +
                                           std::to_string(palette_entries) + " entries");
                    }
                    std::copy_n(palette[in[0]].begin(), 4, out);
                    break;
                case 0:  // grey; transparent where it equals tRNS's grey
                    out[0] = out[1] = out[2] = in[0];
                    out[3] = trns.has_colour && in[0] == trns.colour[0] ? 0 : 255;
                    break;
                case 4:  // grey and alpha
                    out[0] = out[1] = out[2] = in[0];
                    out[3] = in[1];
                    break;
                case 2:  // RGB; transparent where all three equal tRNS's colour
                    std::copy_n(in, 3, out);
                    out[3] = trns.has_colour && in[0] == trns.colour[0] &&
                                     in[1] == trns.colour[1] && in[2] == trns.colour[2]
                                 ? 0
                                 : 255;
                    break;
                default:  // RGBA, alpha not multiplied in
                    std::copy_n(in, 4, out);
                    break;
            }
        }
    }
    return image;
}

namespace {

// The loader decodes texture files through read_texture_png in every program that links this
// library (scene.hpp). Every such program uses this file's writers or readers too, so the
// linker always keeps it and this registration.
const bool kTextureReaderInstalled = [] {
    set_texture_file_reader(&read_texture_png);
    return true;
}();

}  // namespace

}  // namespace harness
