#include "backend_ref.hpp"

#include <chrono>
#include <optional>

#include "harness/profile_io.hpp"
#include "no_answer.hpp"
#include "refraster/renderer.hpp"

namespace harness {
namespace {

// The deadline of a render that starts at `t0` and may take `seconds`: none for 0 or less, or
// for a limit of more than 30 years, which cannot pass and would overflow the clock's type.
std::optional<std::chrono::steady_clock::time_point> deadline_after(
    std::chrono::steady_clock::time_point t0, double seconds) {
    if (!(seconds > 0.0 && seconds < 1e9)) return std::nullopt;
    return t0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                    std::chrono::duration<double>(seconds));
}

class RefBackend final : public Backend {
  public:
    explicit RefBackend(const BackendOptions& o) : options_(o) {}

    BackendKind kind() const override { return BackendKind::Ref; }
    std::string name() const override { return "ref"; }

    RenderResult render(const Scene& scene) override { return run(scene, false); }
    RenderResult render_owners(const Scene& scene) override { return run(scene, true); }

  private:
    RenderResult run(const Scene& scene, bool owners) {
        RenderResult r;
        r.provenance = host_provenance();
        r.provenance["renderer"] = "refraster";
        r.provenance["profile"] = options_.profile.name;
        r.provenance["profile_source"] = options_.profile_source;
        r.provenance["profile_rules"] = profile_rules(options_.profile);
        std::string overrides;
        for (const auto& o : options_.profile_overrides)
            overrides += (overrides.empty() ? "" : ";") + o;
        if (!overrides.empty()) r.provenance["profile_overrides"] = overrides;
        const auto fma = options_.profile.gl.viewport_fma;
        r.provenance["fma"] = fma == refraster::FmaMode::On ||
                                      (fma == refraster::FmaMode::Auto && refraster::host_has_fma())
                                  ? "on"
                                  : "off";
        if (!scene.unsupported_extensions.empty()) {
            r.status = RenderStatus::NotSupported;
            r.message = "requires extension \"" +
                        escape_for_message(scene.unsupported_extensions.front()) +
                        "\", which the reference does not implement";
            return r;
        }
        const auto t0 = std::chrono::steady_clock::now();
        refraster::RenderOptions ro;
        ro.profile = options_.profile;
        ro.record_owners = owners;
        ro.threads = options_.threads;
        // The per-scene timeout, as a GL worker gets it: past it the render stops (every
        // shading thread returns) and the scene is a Timeout in the same words.
        refraster::RenderOutcome outcome;
        try {
            outcome = render_reference_within(scene, ro, options_.timeout_seconds, r.image);
        } catch (const refraster::RenderStopped& e) {
            r.seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            r.status = RenderStatus::Timeout;
            r.message = e.what();
            r.image = refraster::Framebuffer();
            return r;
        }
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (outcome.status == refraster::RenderStatus::NotSupported) {
            r.status = RenderStatus::NotSupported;
            r.message = outcome.message;
            return r;
        }
        if (r.image.samples > 1) {
            // The target keeps every sample; the image is its resolve, as glBlitFramebuffer
            // makes it.
            r.samples = std::move(r.image);
            r.image = refraster::resolve_samples(r.samples);
        }
        return r;
    }

    BackendOptions options_;
};

}  // namespace

std::unique_ptr<Backend> make_ref_backend(const BackendOptions& options) {
    return std::make_unique<RefBackend>(options);
}

refraster::RenderOutcome render_reference_within(const Scene& scene,
                                                 refraster::RenderOptions options,
                                                 double timeout_seconds,
                                                 refraster::Framebuffer& out) {
    options.deadline = deadline_after(std::chrono::steady_clock::now(), timeout_seconds);
    try {
        return refraster::render(scene.draw_list, options, out);
    } catch (const refraster::RenderStopped&) {
        throw refraster::RenderStopped(
            no_answer_message("the reference (" + options.profile.name + ")", timeout_seconds,
                              scene_label(scene), "stopped"));
    }
}

}  // namespace harness
