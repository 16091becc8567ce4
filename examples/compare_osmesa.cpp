// compare_osmesa: render a scene through the reference and through OSMesa llvmpipe (a worker
// process) and compare them as `refraster compare` does. Exit 0 when they agree within the
// scene's expectation, 1 when they do not.
//
//   compare_osmesa SCENE.json [WORKER_DIR]
//
// WORKER_DIR holds refraster-worker-osmesa; without it the harness looks beside this program
// and in ../libexec/refraster (an installed package names it in refraster_WORKER_DIR, which
// this example's CMakeLists.txt compiles in).
#include <cstdio>
#include <exception>
#include <string>

#include "harness/api.hpp"

#ifndef REFRASTER_EXAMPLE_WORKER_DIR
#define REFRASTER_EXAMPLE_WORKER_DIR ""
#endif

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SCENE.json [WORKER_DIR]\n", argv[0]);
        return 2;
    }
    try {
        const harness::Scene scene = harness::load_scene_file(argv[1]);
        const auto reference = harness::make_reference();
        const auto osmesa =
            harness::make_gl_backend(harness::BackendKind::OSMesa, harness::Driver::Llvmpipe,
                                     argc > 2 ? argv[2] : REFRASTER_EXAMPLE_WORKER_DIR);
        const harness::CaseResult r =
            harness::run_case(scene, scene.file.name, *reference, *osmesa);
        std::printf("%s: %s", std::string(harness::to_string(r.status)).c_str(), r.name.c_str());
        if (r.comparison) std::printf(": %s", r.comparison->summary().c_str());
        if (!r.message.empty()) std::printf(" (%s)", r.message.c_str());
        std::printf("\n");
        if (r.actual) {
            for (const auto& [key, value] : r.actual->provenance) {
                if (key == "renderer" || key == "mesa_version") {
                    std::printf("  %s: %s\n", key.c_str(), value.c_str());
                }
            }
        }
        return r.status == harness::CaseStatus::Pass ? 0 : 1;
    } catch (const harness::SceneError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 3;
    }
}
