// renderer_fuzzer: bytes -> scene loader -> the reference renderer, as `refraster render
// --backend ref` and `refraster explain` run it.
//
// Input: one control byte, then the scene file. Control bits: 0 selects the gl-exact profile
// instead of llvmpipe-22.3; 1 also renders the owner pass; 2 also traces one pixel with
// explain_pixel (the pixel from bits 3..7 and the target size; on a 4x target bit 3 also
// picks a sample to explain). A scene the loader refuses is skipped. Anything else is a bug: a
// crash, a sanitizer report, a leak, an exception, an image of the wrong size, an owner pass or a
// traced render whose pixels differ from the plain render.
//
// Per-input work is bounded by the loader's limits (docs/limits.md) lowered further here, so
// that an execution stays in milliseconds: at most 65,536 target pixels (e.g. 256x256) and the
// fuzz limits below. Scenes above them are skipped, not refused.
//
// Deliberately does not: run a GL backend, or judge whether the pixels are right.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>

#include "harness/backend.hpp"
#include "harness/explain.hpp"
#include "harness/scene.hpp"
#include "refraster/profile.hpp"

namespace {

[[noreturn]] void bug(const char* what, std::string_view detail = {}) {
    std::fprintf(stderr, "renderer_fuzzer: %s %.*s\n", what, static_cast<int>(detail.size()),
                 detail.data());
    std::abort();
}

harness::SceneLimits fuzz_limits() {
    harness::SceneLimits l;
    l.max_target_pixels = 65'536;
    l.max_draws = 16;
    l.max_vertices = 4'096;
    l.max_indices = 16'384;
    l.max_primitives = 4'096;
    l.max_fragments = 1u << 20;
    return l;
}

// Bit for bit: float colours compare by their bits, so that NaN equals the same NaN.
bool same_pixels(const refraster::Framebuffer& a, const refraster::Framebuffer& b) {
    if (a.width != b.width || a.height != b.height || a.color8 != b.color8 || a.depth != b.depth) {
        return false;
    }
    if (a.color32f.size() != b.color32f.size()) return false;
    return a.color32f.empty() || std::memcmp(a.color32f.data(), b.color32f.data(),
                                             a.color32f.size() * sizeof(float)) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const std::uint8_t control = data[0];
    const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
    static const harness::SceneLimits limits = fuzz_limits();
    harness::Scene scene;
    try {
        scene = harness::load_scene_text(text, "fuzz.json", limits);
    } catch (const harness::SceneError&) {
        return 0;
    }

    harness::BackendOptions options;
    options.kind = harness::BackendKind::Ref;
    options.profile =
        (control & 1) != 0 ? refraster::gl_exact_profile() : refraster::llvmpipe_22_3_profile();
    const auto backend = harness::make_backend(options);
    const harness::RenderResult plain = backend->render(scene);
    if (plain.status == harness::RenderStatus::NotSupported) return 0;
    if (plain.status != harness::RenderStatus::Ok) bug("status", plain.message);
    const auto& t = scene.draw_list.target;
    if (plain.image.width != t.width || plain.image.height != t.height) bug("image size");
    const bool multisampled = t.samples > 1;
    if (multisampled) {
        // A 4x target keeps every sample, and the image is their resolve.
        if (plain.samples.samples != t.samples || plain.samples.width != t.width ||
            plain.samples.height != t.height)
            bug("samples size");
        if (!same_pixels(refraster::resolve_samples(plain.samples), plain.image))
            bug("the image is not the resolve of the samples");
    } else if (plain.samples.width != 0) {
        bug("samples of a single-sample target");
    }

    if ((control & 2) != 0) {
        const harness::RenderResult owners = backend->render_owners(scene);
        if (owners.status != harness::RenderStatus::Ok) bug("owner pass status", owners.message);
        if (!same_pixels(owners.image, plain.image)) bug("owner pass changed the pixels");
        if (owners.image.owner.size() != owners.image.pixel_count()) bug("owner buffer size");
        if (multisampled && (!same_pixels(owners.samples, plain.samples) ||
                             owners.samples.owner.size() != owners.samples.pixel_count() * 4))
            bug("owner pass changed the samples, or no owner a sample");
    }
    if ((control & 4) != 0) {
        const unsigned pick = control >> 3;
        const int x = static_cast<int>((pick * 7u) % t.width);
        const int y = static_cast<int>((pick * 13u) % t.height);
        // On a 4x target, bit 3 of the pick also explains one sample (-1: the resolve).
        const int sample = multisampled && (pick & 1u) != 0 ? static_cast<int>(pick >> 1) % 4 : -1;
        harness::Explanation e;
        try {
            e = harness::explain_pixel(scene, options.profile, x, y, nullptr, sample);
        } catch (const std::exception& ex) {
            bug("explain_pixel threw", ex.what());
        }
        const auto& expected =
            sample >= 0 ? refraster::sample_plane(plain.samples, static_cast<std::uint32_t>(sample))
                        : plain.image;
        if (!same_pixels(e.reference_image, expected)) bug("the trace changed the pixels");
        (void)harness::explanation_text(e);
        (void)harness::explanation_json(e);
        (void)harness::explanation_svg(e);
    }
    return 0;
}
