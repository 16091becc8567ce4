// scene_loader_fuzzer: bytes -> harness::load_scene_text, the one code path behind every scene
// file the CLI reads.
//
// A refusal (SceneError) is the expected answer to almost every input; it must be one line
// that starts with the file label and holds no control character. Anything else is a bug:
// a crash, a sanitizer report, a leak, another exception type (it reaches std::terminate),
// or an accepted scene that breaks what the front end promises the renderers (draw.hpp):
// finite clip coordinates, indices below the vertex count, a draw list that matches the file.
// An accepted scene must also survive scene_to_json and load again into the same draw list.
//
// Deliberately does not: render (renderer_fuzzer does).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "harness/reduce.hpp"
#include "harness/scene.hpp"

namespace {

constexpr const char* kLabel = "fuzz.json";

[[noreturn]] void bug(const char* what, std::string_view detail) {
    std::fprintf(stderr, "scene_loader_fuzzer: %s: %.*s\n", what, static_cast<int>(detail.size()),
                 detail.data());
    std::abort();
}

void check_message(const harness::SceneError& e) {
    const std::string_view m = e.what();
    if (m.rfind(std::string(kLabel) + ":", 0) != 0) bug("message does not start with the file", m);
    for (const char c : m) {
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
            bug("control character in message", m);
    }
}

void check_scene(const harness::Scene& s) {
    const auto& list = s.draw_list;
    if (list.draws.size() != s.file.draws.size()) bug("draw count", "front end");
    if (list.target != s.file.target) bug("target", "front end");
    for (std::size_t d = 0; d < list.draws.size(); ++d) {
        const auto& draw = list.draws[d];
        const std::size_t n = draw.vertices.size();
        if (n != s.file.draws[d].vertices.size()) bug("vertex count", "front end");
        for (const float f : draw.vertices.data) {
            if (!std::isfinite(f)) bug("non-finite vertex data", "front end");
        }
        if (draw.indices) {
            for (const auto i : *draw.indices) {
                if (i >= n) bug("index past the vertex count", "loader");
            }
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    harness::Scene scene;
    try {
        scene = harness::load_scene_text(text, kLabel);
    } catch (const harness::SceneError& e) {
        check_message(e);
        return 0;
    }
    check_scene(scene);
    // What the reducer writes is a scene file: it must load, into the same draw list.
    const std::string again = harness::scene_to_json(scene.file);
    try {
        const harness::Scene reloaded = harness::load_scene_text(again, kLabel);
        if (!(reloaded.draw_list == scene.draw_list))
            bug("scene_to_json round trip differs", again);
    } catch (const harness::SceneError& e) {
        bug("scene_to_json output refused", e.what());
    }
    return 0;
}
