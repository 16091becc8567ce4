#include "command.hpp"

#include <exception>
#include <iostream>
#include <new>

#include "harness/encode.hpp"

namespace tool {

std::optional<harness::Scene> load_or_report(const std::string& path, const SceneArgs& scene) {
    try {
        return harness::load_scene(path, scene.limits());
    } catch (const harness::SceneError& e) {
        std::cerr << harness::encode::terminal(e.what()) << "\n";
        return std::nullopt;
    }
}

std::unique_ptr<harness::Backend> backend_or_report(const BackendArgs& a,
                                                    const std::string& scene) {
    try {
        return harness::make_backend(a.options());
    } catch (const refraster::Error& e) {
        // Bad input is the user's to fix, and main says so whatever the scene; anything else
        // is this backend failing on it.
        if (e.exit_class() == refraster::ExitClass::BadInput) throw;
        std::cerr << harness::encode::terminal(scene) << ": backend " << a.backend << ": "
                  << harness::encode::terminal(e.what()) << "\n";
        return nullptr;
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const std::exception& e) {
        std::cerr << harness::encode::terminal(scene) << ": backend " << a.backend << ": "
                  << harness::encode::terminal(e.what()) << "\n";
        return nullptr;
    }
}

std::optional<int> profile_and_backend(const BackendArgs& against, const std::string& scene,
                                       bool want_backend, refraster::Profile& profile,
                                       std::unique_ptr<harness::Backend>& backend) {
    profile = against.profile.load();
    if (!want_backend) return std::nullopt;
    BackendArgs gl = against;
    gl.profile = ProfileArgs{};
    backend = backend_or_report(gl, scene);
    if (!backend) return kExitBackendFailure;
    return std::nullopt;
}

int exit_code_for(harness::RenderStatus s) {
    switch (s) {
        case harness::RenderStatus::Ok:
            return kExitOk;
        case harness::RenderStatus::NotSupported:
            return kExitNotSupported;
        default:
            return kExitBackendFailure;
    }
}

}  // namespace tool
