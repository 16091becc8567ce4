// api.cpp: the in-process API's own steps (api.hpp); everything else is the harness's.
#include "harness/api.hpp"

namespace harness {

Scene load_scene_file(const std::filesystem::path& path, const SceneLimits& limits) {
    // This file lives in the image library, so a program that loads scenes through it reads
    // PNG textures whatever else it links (image_io.cpp installs the reader; naming it here
    // keeps the installation explicit).
    set_texture_file_reader(&read_texture_png);
    return load_scene(path, limits);
}

std::unique_ptr<Backend> make_reference(const ReferenceOptions& options) {
    BackendOptions o;
    o.kind = BackendKind::Ref;
    o.profile = load_profile(options.profile);
    apply_profile_overrides(o.profile, options.profile_overrides);
    o.profile_source = profile_source(options.profile);
    o.profile_overrides = options.profile_overrides;
    o.threads = options.threads;
    return make_backend(o);
}

std::unique_ptr<Backend> make_gl_backend(BackendKind kind, Driver driver,
                                         const std::filesystem::path& worker_dir,
                                         double timeout_seconds) {
    if (kind == BackendKind::Ref) {
        throw std::runtime_error("make_gl_backend: the reference is not a GL backend");
    }
    BackendOptions o;
    o.kind = kind;
    o.driver = driver;
    o.worker_dir = worker_dir;
    o.timeout_seconds = timeout_seconds;
    return make_backend(o);
}

}  // namespace harness
