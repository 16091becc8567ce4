// render_scene: load a scene file, render it through the reference, write the image and print
// its hash (the one conformance/expectations/ref-hashes.txt holds for the shipped scenes).
//
//   render_scene SCENE.json OUT.png [key=value ...]   (profile overrides, as --profile-set)
#include <cstdio>
#include <exception>

#include "harness/api.hpp"
#include "harness/image_hash.hpp"

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s SCENE.json OUT.png [key=value ...]\n", argv[0]);
        return 2;
    }
    try {
        const harness::Scene scene = harness::load_scene_file(argv[1]);
        harness::ReferenceOptions options;
        for (int i = 3; i < argc; ++i) options.profile_overrides.emplace_back(argv[i]);
        const auto reference = harness::make_reference(options);
        const harness::RenderResult r = reference->render(scene);
        if (r.status != harness::RenderStatus::Ok) {
            std::fprintf(stderr, "%s: %s\n", argv[1], r.message.c_str());
            return 3;
        }
        harness::write_color_image(r.image, argv[2]);
        std::printf("%s %ux%u hash %s\n", argv[2], r.image.width, r.image.height,
                    harness::render_hash(r.image, r.samples).c_str());
        return 0;
    } catch (const harness::SceneError& e) {
        std::fprintf(stderr, "%s\n", e.what());  // FILE: JSON.PATH: what was expected
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 3;
    }
}
