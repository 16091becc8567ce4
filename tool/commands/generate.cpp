// generate extreme|many-triangles: generated scenes. extreme: the seeded stiff and extreme
// scenes (harness/extreme_scenes.hpp), one DIR/<kind>.json per kind; many-triangles: one scene
// of many small triangles in a chosen vertex form.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "commands/commands.hpp"
#include "harness/encode.hpp"
#include "harness/extreme_scenes.hpp"
#include "harness/scene_text.hpp"

namespace tool {
namespace {

int run_generate_many(std::uint64_t triangles, std::uint64_t seed, const std::string& form,
                      const std::string& output) {
    const harness::VertexForm f = form == "values"   ? harness::VertexForm::Values
                                  : form == "base64" ? harness::VertexForm::Base64
                                                     : harness::VertexForm::Plain;
    const std::string text =
        harness::scene_json_text(harness::many_triangles_scene(triangles, seed), f);
    // Complete or absent: written beside the output, then renamed over it.
    const std::filesystem::path out(output);
    const std::filesystem::path tmp = out.string() + ".partial";
    {
        std::ofstream o(tmp, std::ios::binary);
        o.write(text.data(), static_cast<std::streamsize>(text.size()));
        if (!o) {
            std::cerr << harness::encode::terminal(output) << ": cannot write\n";
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            return kExitBadInput;
        }
    }
    std::filesystem::rename(tmp, out);
    std::cerr << harness::encode::terminal(output) << ": " << text.size() << " bytes\n";
    return kExitOk;
}

// Both generators' options: --seed and --output are declared on each.
struct GenerateArgs {
    std::uint64_t seed = 1;
    std::string output;
    std::uint64_t triangles = 1'000'000;
    std::string form = "plain";
};

}  // namespace

Command add_generate_command(CLI::App& app) {
    auto a = std::make_shared<GenerateArgs>();
    auto* cmd = app.add_subcommand("generate", "Write generated scenes");
    cmd->require_subcommand(1);

    // generate extreme --seed N --output DIR
    auto* extreme = cmd->add_subcommand("extreme", "Stiff and extreme scenes, one file per kind");
    extreme->add_option("--seed", a->seed, "Seed of the generator")->capture_default_str();
    extreme->add_option("-o,--output", a->output, "Directory for the scene files")->required();

    // generate many-triangles --triangles N [--form F] [--seed S] --output FILE
    auto* many = cmd->add_subcommand("many-triangles",
                                     "One scene of many small triangles, in a chosen vertex form");
    many->add_option("--triangles", a->triangles, "Number of triangles")
        ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{100'000'000}))
        ->capture_default_str();
    many->add_option("--form", a->form,
                     "plain (vertices), values or base64 (extension vertex_arrays)")
        ->check(CLI::IsMember({"plain", "values", "base64"}))
        ->capture_default_str();
    many->add_option("--seed", a->seed, "Seed of the generator")->capture_default_str();
    many->add_option("-o,--output", a->output, "The scene file")->required();

    return {cmd, [a, extreme, many] {
                if (many->parsed())
                    return run_generate_many(a->triangles, a->seed, a->form, a->output);
                if (extreme->parsed())
                    return harness::write_extreme_scenes(a->seed, a->output, std::cerr);
                return kExitBadInput;
            }};
}

}  // namespace tool
