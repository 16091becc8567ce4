// Image files: rows are flipped to top-first on disk and back on reading; writes are atomic.
#include "harness/image_io.hpp"

#include <gtest/gtest.h>

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

}  // namespace
