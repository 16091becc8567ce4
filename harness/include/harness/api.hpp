// api.hpp: the harness from C++, in one include: load a scene file, render it through the
// reference or a GL backend, compare two renders, explain a pixel. The command-line tool is
// built from the same calls:
//  - load_scene_file (below), then Backend::render (backend.hpp) with make_reference or
//    make_gl_backend (below);
//  - run_case (case_result.hpp): two backends render a scene and compare it as
//    `refraster compare` does (images, every sample of a 4x target, the scene's expectation,
//    the pixel classes); compare_images (compare.hpp) for two framebuffers of your own;
//  - explain_pixel and explanation_text / _json / _svg (explain.hpp);
//  - gl_verdict (gl_verdict.hpp): differences judged against GL's freedoms;
//  - fingerprint (fingerprint.hpp): a backend's rules inferred from probe scenes;
//  - write_color_image (image_io.hpp);
//  - scenes written in code: SceneFile (scene.hpp), scene_to_json (scene_writer.hpp), camera
//    matrices (authoring.hpp).
//
// Link refraster::harness (find_package(refraster), docs/library.md). Deliberately does not:
// run the conformance suite (the runner's reports and resumable runs are the CLI's), or hide
// the types it returns: every result is the harness's own struct.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "harness/authoring.hpp"
#include "harness/backend.hpp"
#include "harness/case_result.hpp"
#include "harness/compare.hpp"
#include "harness/explain.hpp"
#include "harness/fingerprint.hpp"
#include "harness/gl_verdict.hpp"
#include "harness/image_io.hpp"
#include "harness/profile_io.hpp"
#include "harness/reduce.hpp"
#include "harness/scene.hpp"
#include "harness/scene_writer.hpp"

namespace harness {

// A scene file, parsed and through the front end, with PNG texture files readable. Bad input
// throws SceneError, whose what() is the one-line message naming the file and the JSON path.
Scene load_scene_file(const std::filesystem::path& path, const SceneLimits& limits = {});

struct ReferenceOptions {
    // A built-in profile name (refraster profile --list) or a profile JSON file.
    std::string profile = "llvmpipe-22.3";
    std::vector<std::string> profile_overrides;  // key=value, as --profile-set takes them
    unsigned threads = 0;                        // 0: one per core; the bytes are the same
};

// The reference renderer as a Backend (make_backend with kind Ref). Throws
// std::runtime_error for an unknown profile or a bad override.
std::unique_ptr<Backend> make_reference(const ReferenceOptions& options = {});

// A GL backend (osmesa or egl) for `driver`: a worker process started on the first render and
// kept for the next. Its executable (refraster-worker-osmesa, refraster-worker-egl) is looked up
// in `worker_dir` when given, else as make_backend does (REFRASTER_WORKER_DIR, then beside the
// running program, then ../libexec/refraster from it). An installed package names its worker
// directory in the CMake variable refraster_WORKER_DIR. Throws std::runtime_error when the
// backend was not built or its worker is not found.
std::unique_ptr<Backend> make_gl_backend(BackendKind kind, Driver driver = Driver::Llvmpipe,
                                         const std::filesystem::path& worker_dir = {},
                                         double timeout_seconds = 60.0);

}  // namespace harness
