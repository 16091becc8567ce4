// Image files: rows are flipped to top-first on disk and back on reading; writes are atomic.
#include "harness/image_io.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <cstdio>
#include <vector>

#include "test_util.hpp"

namespace {

TEST(ImageIo, PngRoundTripKeepsBottomUpRows) {
    testutil::TempDir dir;
    refraster::Framebuffer fb(2, 3, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None);
    for (std::size_t i = 0; i < fb.color8.size(); ++i)
        fb.color8[i] = static_cast<std::uint8_t>(i * 7);
    const auto p = dir.path() / "a.png";
    harness::write_color_image(fb, p);
    const auto back = harness::read_color_image(p);
    EXPECT_EQ(back.width, 2u);
    EXPECT_EQ(back.height, 3u);
    EXPECT_EQ(back.color8, fb.color8);
    // Nothing but the image is left in the directory (the temporary file was renamed).
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()),
                            std::filesystem::directory_iterator{}),
              1);
}

TEST(ImageIo, ExrRoundTripIsExactFloat) {
    testutil::TempDir dir;
    refraster::Framebuffer fb(2, 2, refraster::ColorFormat::Rgba32f, refraster::DepthFormat::None);
    for (std::size_t i = 0; i < fb.color32f.size(); ++i)
        fb.color32f[i] = 0.1f * static_cast<float>(i) - 0.3f;
    const auto p = dir.path() / "a.exr";
    harness::write_color_image(fb, p);
    EXPECT_EQ(harness::read_color_image(p).color32f, fb.color32f);
}

// A PNG of another writer: `channels` 8-bit samples a pixel (1 grey, 3 RGB), rows top first.
void write_png_with_libpng(const std::filesystem::path& p, std::uint32_t width,
                           std::uint32_t height, int channels,
                           const std::vector<std::uint8_t>& samples) {
    std::FILE* f = std::fopen(p.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, f);
    png_set_IHDR(png, info, width, height, 8,
                 channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (std::uint32_t r = 0; r < height; ++r) {
        png_write_row(png,
                      samples.data() + std::size_t{r} * width * static_cast<std::size_t>(channels));
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    ASSERT_EQ(std::fclose(f), 0);
}

// An RGB PNG is read with libpng, opaque; a grey one goes through the OpenImageIO codec module
// (its only channel into red, as OpenImageIO reads it), bottom row first either way.
TEST(ImageIo, RgbPngIsReadOpaqueAndGreyPngThroughTheCodecModule) {
    testutil::TempDir dir;
    const std::vector<std::uint8_t> rgb = {10, 20, 30, 40, 50, 60};  // top row, then bottom
    write_png_with_libpng(dir.path() / "rgb.png", 1, 2, 3, rgb);
    const auto a = harness::read_color_image(dir.path() / "rgb.png");
    EXPECT_EQ(a.color8, (refraster::PixelVector<std::uint8_t>{40, 50, 60, 255, 10, 20, 30, 255}));
    write_png_with_libpng(dir.path() / "grey.png", 2, 1, 1, {7, 200});
    const auto g = harness::read_color_image(dir.path() / "grey.png");
    EXPECT_EQ(g.color8, (refraster::PixelVector<std::uint8_t>{7, 0, 0, 255, 200, 0, 0, 255}));
    EXPECT_THROW(harness::read_color_image(dir.path() / "none.png"), harness::ImageIoError);
}

TEST(ImageIo, WrongExtensionIsRefusedBeforeWriting) {
    testutil::TempDir dir;
    refraster::Framebuffer fb(1, 1, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None);
    EXPECT_THROW(harness::write_color_image(fb, dir.path() / "a.exr"), harness::ImageIoError);
    EXPECT_THROW(harness::write_color_image(fb, dir.path() / "missing-dir" / "a.png"),
                 harness::ImageIoError);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace

namespace {

// Several images are written together or not at all: one that cannot be written leaves none of
// the others behind, and no partial file.
TEST(ImageIo, ImagesAreWrittenAllOrNone) {
    testutil::TempDir dir;
    refraster::Framebuffer a(2, 1, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None);
    refraster::Framebuffer b = a;
    a.color8[0] = 10;
    b.color8[0] = 20;
    const auto pa = dir.path() / "a.png";
    const auto pb = dir.path() / "b.png";
    EXPECT_THROW(
        harness::write_color_images({{&a, pa}, {&b, pb}, {&a, dir.path() / "no" / "c.png"}}),
        harness::ImageIoError);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
    // A wrong extension anywhere is refused before anything is written.
    EXPECT_THROW(harness::write_color_images({{&a, pa}, {&b, dir.path() / "b.exr"}}),
                 harness::ImageIoError);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
    harness::write_color_images({{&a, pa}, {&b, pb}});
    EXPECT_EQ(harness::read_color_image(pa).color8[0], 10);
    EXPECT_EQ(harness::read_color_image(pb).color8[0], 20);
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()),
                            std::filesystem::directory_iterator{}),
              2);
}

TEST(ImageIo, SampleImagePathsFollowThePrefix) {
    const auto png = harness::sample_image_paths("out/x", 4, refraster::ColorFormat::Rgba8);
    ASSERT_EQ(png.size(), 4u);
    EXPECT_EQ(png[0], std::filesystem::path("out/x.s0.png"));
    EXPECT_EQ(png[3], std::filesystem::path("out/x.s3.png"));
    const auto exr = harness::sample_image_paths("y", 4, refraster::ColorFormat::Rgba32f);
    EXPECT_EQ(exr[2], std::filesystem::path("y.s2.exr"));
}

// The texture decoder reads the PNG its writer makes, and refuses everything else without a
// word on stderr (libpng's own messages are kept): the caller reports it once.
TEST(ImageIo, TexturePngDecoderReadsPngOnlyAndPrintsNothing) {
    testutil::TempDir dir;
    refraster::Framebuffer fb(2, 2, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None);
    for (std::size_t i = 0; i < fb.color8.size(); ++i)
        fb.color8[i] = static_cast<std::uint8_t>(i * 11);
    harness::write_color_image(fb, dir.path() / "a.png");
    refraster::Framebuffer f32(1, 1, refraster::ColorFormat::Rgba32f, refraster::DepthFormat::None);
    harness::write_color_image(f32, dir.path() / "a.exr");
    const auto bytes = [&](const char* name) {
        const std::string text = testutil::read_text(dir.path() / name);
        return std::vector<std::uint8_t>(text.begin(), text.end());
    };
    const std::vector<std::uint8_t> png = bytes("a.png");
    const auto image = harness::read_texture_png(png);
    EXPECT_EQ(image.width, 2u);
    EXPECT_EQ(image.height, 2u);
    // Rows bottom to top, as the framebuffer holds them.
    EXPECT_EQ(image.rgba, std::vector<std::uint8_t>(fb.color8.begin(), fb.color8.end()));
    // Broken copies: the compressed data's header, a cut inside the image data, IHDR's CRC.
    const std::string text(png.begin(), png.end());
    const std::size_t idat = text.find("IDAT");
    ASSERT_NE(idat, std::string::npos);
    std::vector<std::uint8_t> bad_zlib = png;
    bad_zlib[idat + 4] = 0x7f;
    const std::vector<std::uint8_t> cut(png.begin(), png.begin() + static_cast<long>(idat) + 8);
    std::vector<std::uint8_t> bad_crc = png;
    bad_crc[29] ^= 1;
    // stderr into a file while the decoder runs.
    const auto err = dir.path() / "stderr.txt";
    std::fflush(stderr);
    const int saved = ::dup(2);
    const int file = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ASSERT_GE(file, 0);
    ::dup2(file, 2);
    ::close(file);
    int refused = 0;
    const std::vector<const std::vector<std::uint8_t>*> broken = {&bad_zlib, &cut, &bad_crc};
    for (const auto* b : broken) {
        try {
            (void)harness::read_texture_png(*b);
        } catch (const harness::ImageIoError&) {
            ++refused;
        }
    }
    const std::vector<std::uint8_t> exr = bytes("a.exr");
    EXPECT_THROW((void)harness::read_texture_png(exr), harness::ImageIoError);
    std::fflush(stderr);
    ::dup2(saved, 2);
    ::close(saved);
    EXPECT_EQ(refused, 3);
    EXPECT_EQ(testutil::read_text(err), "");
}

}  // namespace
