// oiio_codec.cpp: the OpenImageIO codec module (oiio_codec.hpp), loaded by image_io.cpp the
// first time a program writes or reads an image that is not a PNG of 8-bit RGB or RGBA.
#include "oiio_codec.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <exception>

namespace {

namespace OIIO = OIIO_NAMESPACE;
using harness::detail::CodecImage;

std::string write_image(const char* file, std::uint32_t width, std::uint32_t height, bool is8,
                        const void* pixels) {
    try {
        auto out = OIIO::ImageOutput::create(file);
        if (!out) return "cannot create an image writer for this extension";
        const OIIO::TypeDesc type = is8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
        OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height), 4, type);
        // Pixels are stored as rendered: PNG alpha is unassociated, and without this attribute
        // OpenImageIO would divide the colour by alpha on the way out.
        spec.attribute("oiio:UnassociatedAlpha", 1);
        if (!out->open(file, spec)) return "cannot write: " + out->geterror();
        // Image files store the top row first: file row 0 is window row height-1.
        const std::size_t row_bytes = std::size_t{width} * 4 * type.size();
        const auto* bytes = static_cast<const std::uint8_t*>(pixels);
        bool ok = true;
        for (std::uint32_t row = 0; ok && row < height; ++row) {
            ok = out->write_scanline(static_cast<int>(row), 0, type,
                                     bytes + std::size_t{height - 1 - row} * row_bytes);
        }
        ok = out->close() && ok;
        return ok ? std::string() : "cannot write: " + out->geterror();
    } catch (const std::exception& e) {
        return std::string("cannot write: ") + e.what();
    }
}

std::string write_animation(const char* file, std::uint32_t width, std::uint32_t height,
                            const std::uint8_t* const* frames, std::size_t count,
                            int frames_per_second) {
    try {
        auto out = OIIO::ImageOutput::create(file);
        if (!out || !out->supports("multiimage")) return "cannot create an animated GIF writer";
        OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height), 4,
                             OIIO::TypeDesc::UINT8);
        spec.attribute("oiio:UnassociatedAlpha", 1);
        const int rate[2] = {std::max(1, frames_per_second), 1};
        spec.attribute("FramesPerSecond", OIIO::TypeRational, rate);
        spec.attribute("gif:LoopCount", 0);  // forever
        const std::size_t row_bytes = std::size_t{width} * 4;
        for (std::size_t k = 0; k < count; ++k) {
            const auto mode =
                k == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendSubimage;
            bool ok = out->open(file, spec, mode);
            for (std::uint32_t row = 0; ok && row < height; ++row) {
                ok = out->write_scanline(static_cast<int>(row), 0, OIIO::TypeDesc::UINT8,
                                         frames[k] + std::size_t{height - 1 - row} * row_bytes);
            }
            if (!ok) return "cannot write: " + out->geterror();
        }
        return out->close() ? std::string() : "cannot write: " + out->geterror();
    } catch (const std::exception& e) {
        return std::string("cannot write: ") + e.what();
    }
}

std::string read_image(const char* file, CodecImage& out) {
    try {
        // Keep the colour as stored: without this, PNG colour is multiplied by alpha.
        OIIO::ImageSpec config;
        config.attribute("oiio:UnassociatedAlpha", 1);
        auto in = OIIO::ImageInput::open(file, &config);
        if (!in) return "cannot read: " + OIIO::geterror();
        const OIIO::ImageSpec& spec = in->spec();
        if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < 1) return "empty image";
        out.width = static_cast<std::uint32_t>(spec.width);
        out.height = static_cast<std::uint32_t>(spec.height);
        out.is8 = spec.format == OIIO::TypeDesc::UINT8;
        const std::size_t values = std::size_t{out.width} * out.height * 4;
        if (out.is8) {
            out.rgba8.assign(values, 0);
        } else {
            out.rgba32f.assign(values, 0.0f);
        }
        const int nch = std::min(spec.nchannels, 4);
        const OIIO::TypeDesc type = out.is8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
        const std::size_t row_values = std::size_t{out.width} * 4;
        const auto pixel_stride = static_cast<OIIO::stride_t>(4 * type.size());
        const auto row_stride = static_cast<OIIO::stride_t>(row_values * type.size());
        // Read the top file row into the last buffer row: a negative row stride flips.
        const std::size_t last = (out.height - 1) * row_values;
        void* last_row = out.is8 ? static_cast<void*>(out.rgba8.data() + last)
                                 : static_cast<void*>(out.rgba32f.data() + last);
        if (!in->read_image(0, 0, 0, nch, type, last_row, pixel_stride, -row_stride)) {
            return "cannot read: " + in->geterror();
        }
        if (nch < 4) {  // a file without alpha is opaque
            for (std::size_t i = 3; i < values; i += 4) {
                if (out.is8) {
                    out.rgba8[i] = 255;
                } else {
                    out.rgba32f[i] = 1.0f;
                }
            }
        }
        in->close();
        return {};
    } catch (const std::exception& e) {
        return std::string("cannot read: ") + e.what();
    }
}

const harness::detail::OiioCodec kCodec{harness::detail::kOiioCodecVersion, &write_image,
                                        &write_animation, &read_image};

}  // namespace

extern "C" __attribute__((visibility("default"))) const harness::detail::OiioCodec*
refraster_oiio_codec() {
    return &kCodec;
}
