#include "backend_ref.hpp"

#include <chrono>

#include "refraster/renderer.hpp"

namespace harness {
namespace {

class RefBackend final : public Backend {
public:
    BackendKind kind() const override { return BackendKind::Ref; }
    std::string name() const override { return "ref"; }

    RenderResult render(const Scene& scene) override {
        RenderResult r;
        r.provenance = host_provenance();
        r.provenance["renderer"] = "refraster";
        r.provenance["profile"] = "none (primitives not implemented)";
        if (!scene.unsupported_extensions.empty()) {
            r.status = RenderStatus::NotSupported;
            r.message = "requires extension \"" + scene.unsupported_extensions.front() +
                        "\", which the reference does not implement";
            return r;
        }
        const auto t0 = std::chrono::steady_clock::now();
        const auto outcome = refraster::render(scene.draw_list, r.image);
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (outcome.status == refraster::RenderStatus::NotSupported) {
            r.status = RenderStatus::NotSupported;
            r.message = outcome.message;
        }
        return r;
    }
};

}  // namespace

std::unique_ptr<Backend> make_ref_backend() { return std::make_unique<RefBackend>(); }

}  // namespace harness
