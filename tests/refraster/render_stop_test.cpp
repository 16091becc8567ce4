// A render's deadline and stop flag (RenderOptions::deadline, ::stop): a render that passes
// them throws RenderStopped on every path (the band threads, the model's quad packets, the
// scanline model), and one that does not is byte for byte the render without them.
#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "refraster/profile.hpp"
#include "refraster/renderer.hpp"

namespace {

using Clock = std::chrono::steady_clock;

// `layers` blended triangles, each covering the whole `size` x `size` target: every layer
// shades every pixel, so the work grows with the layers and nothing is skipped.
refraster::DrawList layered(std::uint32_t size, int layers) {
    refraster::DrawList l;
    l.target = {size, size, refraster::ColorFormat::Rgba8, refraster::DepthFormat::Z24, 1};
    l.clear.color = {0.1f, 0.2f, 0.3f, 1.0f};
    refraster::Draw d;
    d.primitive = refraster::PrimitiveType::Triangles;
    const auto s = static_cast<std::int32_t>(size);
    d.state.viewport = {0, 0, s, s};
    d.state.blend = refraster::BlendPreset::Alpha;
    d.state.depth_test = refraster::CompareFunc::Always;
    d.vertices.attributes = {{"color", 4}};
    for (int k = 0; k < layers; ++k) {
        const float c = static_cast<float>(k % 17) / 17.0f;
        for (const auto& [x, y] : {std::pair{-1.0f, -1.0f}, {3.0f, -1.0f}, {-1.0f, 3.0f}}) {
            d.vertices.data.insert(d.vertices.data.end(),
                                   {x, y, 0.5f * c, 1.0f, c, 1.0f - c, 0.5f, 0.25f + 0.5f * c});
        }
    }
    l.draws.push_back(std::move(d));
    return l;
}

struct Path {
    const char* name;
    std::string profile;
    refraster::KernelPath kernels;
    unsigned threads;
};

// The row-block kernels on one thread and on three (each band thread stops), the model's quad
// packets (the traversal's own loop), and the scanline (softpipe) model.
const std::vector<Path>& paths() {
    static const std::vector<Path> p{
        {"fastest, 1 thread", "llvmpipe-22.3", refraster::KernelPath::Fastest, 1},
        {"fastest, 3 threads", "llvmpipe-22.3", refraster::KernelPath::Fastest, 3},
        {"model", "llvmpipe-22.3", refraster::KernelPath::Model, 1},
        {"softpipe", "softpipe-22.3", refraster::KernelPath::Fastest, 1},
    };
    return p;
}

refraster::RenderOptions options_for(const Path& p) {
    refraster::RenderOptions o;
    o.profile = refraster::builtin_profile(p.profile);
    o.kernels = p.kernels;
    o.threads = p.threads;
    return o;
}

bool same_bytes(const refraster::Framebuffer& a, const refraster::Framebuffer& b) {
    return a.color8 == b.color8 && a.depth == b.depth && a.owner == b.owner;
}

// Hundreds of millions of fragments (many seconds on any path) stop at a deadline a fraction
// of a second away: the outcome is RenderStopped, whichever path shades.
TEST(RenderStop, AHeavyRenderStopsAtItsDeadline) {
    const auto list = layered(1024, 600);
    for (const auto& p : paths()) {
        SCOPED_TRACE(p.name);
        auto o = options_for(p);
        o.deadline = Clock::now() + std::chrono::milliseconds(300);
        refraster::Framebuffer fb;
        EXPECT_THROW(refraster::render(list, o, fb), refraster::RenderStopped);
    }
}

// The caller's flag stops a render the same way; a deadline already past stops it before it
// draws. Both are backend failures (exit code 3), not bad input.
TEST(RenderStop, AFlagOrAPastDeadlineStopsTheRender) {
    const auto list = layered(64, 4);
    for (const auto& p : paths()) {
        SCOPED_TRACE(p.name);
        refraster::Framebuffer fb;
        auto o = options_for(p);
        o.deadline = Clock::now() - std::chrono::seconds(1);
        EXPECT_THROW(refraster::render(list, o, fb), refraster::RenderStopped);
        const std::atomic<bool> stop{true};
        o = options_for(p);
        o.stop = &stop;
        try {
            refraster::render(list, o, fb);
            ADD_FAILURE() << "the render did not stop";
        } catch (const refraster::RenderStopped& e) {
            EXPECT_EQ(e.exit_class(), refraster::ExitClass::BackendFailure);
        }
    }
}

// A render that ends before its deadline, with a flag that stays down, gives the bytes of the
// render without either (owners included).
TEST(RenderStop, ARenderThatEndsIsUnchanged) {
    const auto list = layered(200, 24);
    for (const auto& p : paths()) {
        SCOPED_TRACE(p.name);
        auto plain = options_for(p);
        plain.record_owners = true;
        refraster::Framebuffer want;
        ASSERT_EQ(refraster::render(list, plain, want).status, refraster::RenderStatus::Ok);
        auto bounded = plain;
        const std::atomic<bool> stop{false};
        bounded.deadline = Clock::now() + std::chrono::hours(1);
        bounded.stop = &stop;
        refraster::Framebuffer got;
        ASSERT_EQ(refraster::render(list, bounded, got).status, refraster::RenderStatus::Ok);
        EXPECT_TRUE(same_bytes(want, got));
    }
}

}  // namespace
