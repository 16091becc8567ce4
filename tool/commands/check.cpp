// check SCENE.json [--rounds N]: loads the scene as every subcommand does and says what it
// holds and how long loading took (the best of N loads): the loader's speed in MB of file a
// second (docs/performance.md, "Loading").
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "commands/commands.hpp"
#include "harness/scene.hpp"

namespace tool {
namespace {

int run_check(const std::string& path, const SceneArgs& scene_args, int rounds) {
    double best = 0;
    std::optional<harness::Scene> scene;
    for (int r = 0; r < rounds; ++r) {
        scene.reset();  // one scene in memory at a time
        const auto start = std::chrono::steady_clock::now();
        scene = load_or_report(path, scene_args);
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!scene) return kExitBadInput;
        best = r == 0 ? s : std::min(best, s);
    }
    std::uint64_t vertices = 0;
    for (const auto& d : scene->draw_list.draws) vertices += d.vertices.size();
    const auto work = harness::estimate_work(scene->draw_list);
    const auto bytes = std::filesystem::file_size(path);
    std::printf("%s: %zu draws, %llu vertices, %llu primitives, %llu estimated fragments",
                path.c_str(), scene->draw_list.draws.size(),
                static_cast<unsigned long long>(vertices),
                static_cast<unsigned long long>(work.primitives),
                static_cast<unsigned long long>(work.fragments));
    if (!scene->draw_list.textures.empty()) {
        std::uint64_t texel_bytes = 0;
        for (const auto& t : scene->draw_list.textures) {
            for (const auto& level : t.levels) texel_bytes += level.rgba.size();
        }
        std::printf(", %zu textures (%llu bytes of texels given)", scene->draw_list.textures.size(),
                    static_cast<unsigned long long>(texel_bytes));
    }
    std::printf("\n");
    std::printf("loaded %llu bytes in %.3f s (best of %d): %.1f MB/s\n",
                static_cast<unsigned long long>(bytes), best, rounds,
                static_cast<double>(bytes) / 1e6 / best);
    return scene->unsupported_extensions.empty() ? kExitOk : kExitNotSupported;
}

struct CheckArgs {
    std::string scene;
    SceneArgs scene_args;  // --texture-root
    int rounds = 1;
};

}  // namespace

Command add_check_command(CLI::App& app) {
    auto a = std::make_shared<CheckArgs>();
    auto* cmd = app.add_subcommand("check",
                                   "Load a scene, say what it holds and how fast it loaded (MB/s)");
    cmd->add_option("scene", a->scene, "Scene file")->required();
    add_scene_options(cmd, a->scene_args);
    cmd->add_option("--rounds", a->rounds, "Loads; the best time is reported")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    return {cmd, [a] { return run_check(a->scene, a->scene_args, a->rounds); }};
}

}  // namespace tool
