// sameness_support.hpp: what the sameness tests share (sameness_test.cpp for the llvmpipe
// model, softpipe_sameness_test.cpp for the softpipe model): the seeds and scene counts, the
// random choices their scene makers draw from, where two renders first differ, and the loop
// that renders each scene through the model and through every other kernel path this CPU runs
// with 1, 2 and 3 threads, bit for bit.
//
// Deliberately does not: make scenes. Each test's scene maker aims at what its model's fast
// paths decide differently, and its draws from the generator are its own.
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>

#include "refraster/framebuffer.hpp"
#include "refraster/renderer.hpp"

namespace sameness {

// REFRASTER_TEST_SEED, 3 unless set.
inline std::uint64_t ci_seed() {
    const char* s = std::getenv("REFRASTER_TEST_SEED");
    return s != nullptr && *s != '\0' ? std::strtoull(s, nullptr, 10) : 3;
}

// REFRASTER_SAMENESS_SCENES, 60 unless set.
inline int scene_count() {
    const char* s = std::getenv("REFRASTER_SAMENESS_SCENES");
    return s != nullptr && *s != '\0' ? std::atoi(s) : 60;
}

// Where two renders first differ, or empty when they are the same bit for bit.
inline std::string first_difference(const refraster::Framebuffer& a,
                                    const refraster::Framebuffer& b) {
    if (a.color8.size() != b.color8.size() || a.color32f.size() != b.color32f.size() ||
        a.depth.size() != b.depth.size())
        return "sizes";
    for (std::size_t i = 0; i < a.color8.size(); ++i) {
        if (a.color8[i] != b.color8[i]) return "colour byte " + std::to_string(i);
    }
    for (std::size_t i = 0; i < a.color32f.size(); ++i) {
        if (std::bit_cast<std::uint32_t>(a.color32f[i]) !=
            std::bit_cast<std::uint32_t>(b.color32f[i]))
            return "colour float " + std::to_string(i);
    }
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        if (a.depth[i] != b.depth[i]) return "depth " + std::to_string(i);
    }
    if (a.owner != b.owner) return "owners";
    return {};
}

// The random choices of a scene maker, from one 64-bit Mersenne Twister.
class RandomChoices {
  protected:
    explicit RandomChoices(std::uint64_t seed) : rng_(seed) {}

    std::uint32_t pick(std::uint32_t n) { return static_cast<std::uint32_t>(rng_() % n); }
    float uniform(float lo, float hi) {
        return std::uniform_real_distribution<float>(lo, hi)(rng_);
    }
    // Mostly uniform in [lo, hi); one time in twelve each a positive denormal, a negative one,
    // or zero.
    float edge_value(float lo, float hi) {
        switch (pick(12)) {
            case 0:
                return 1e-40f;  // a denormal
            case 1:
                return -3e-39f;
            case 2:
                return 0.0f;
            default:
                return uniform(lo, hi);
        }
    }

    std::mt19937_64 rng_;
};

// Renders `scenes` scenes (next_scene()) through the model (model_for(n): the options of scene
// n, kernels KernelPath::Model) and through every other kernel path this CPU runs with 1, 2 and
// 3 threads, and expects the same bytes (colour, depth, owners). Expects more than half of the
// scenes to draw something (the comparisons are of drawn images, not of cleared targets).
template <class NextScene, class ModelFor>
void expect_every_path_gives_the_models_bytes(std::uint64_t seed, int scenes,
                                              NextScene&& next_scene, ModelFor&& model_for) {
    using refraster::KernelPath;
    int drawn = 0;
    int compared = 0;
    for (int n = 0; n < scenes; ++n) {
        const refraster::DrawList l = next_scene();
        const refraster::RenderOptions model = model_for(n);
        refraster::Framebuffer expected;
        ASSERT_EQ(refraster::render(l, model, expected).status, refraster::RenderStatus::Ok);
        refraster::DrawList empty = l;
        empty.draws.clear();
        refraster::Framebuffer cleared;
        ASSERT_EQ(refraster::render(empty, model, cleared).status, refraster::RenderStatus::Ok);
        drawn += !first_difference(expected, cleared).empty();
        for (const auto path : {KernelPath::Scalar, KernelPath::Avx2, KernelPath::Avx512}) {
            if (!refraster::kernel_path_available(path)) continue;
            for (const unsigned threads : {1u, 2u, 3u}) {
                refraster::RenderOptions fast = model;
                fast.kernels = path;
                fast.threads = threads;
                refraster::Framebuffer got;
                ASSERT_EQ(refraster::render(l, fast, got).status, refraster::RenderStatus::Ok);
                const std::string where = first_difference(expected, got);
                ASSERT_TRUE(where.empty())
                    << "seed " << seed << " scene " << n << " (" << l.target.width << "x"
                    << l.target.height << ", " << l.draws.size() << " draws): path "
                    << refraster::to_string(path) << " with " << threads
                    << " threads differs from the model at " << where;
                ++compared;
            }
        }
    }
    EXPECT_GT(drawn, scenes / 2);
    EXPECT_GT(compared, 0);
}

}  // namespace sameness
