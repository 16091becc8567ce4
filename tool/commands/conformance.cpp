// conformance run|merge|hashes: the conformance suite against a GL backend, one run's report
// from its shards' directories, and the reference's image hash of every scene.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <vector>

#include "commands/commands.hpp"
#include "conformance/merge.hpp"
#include "conformance/shard.hpp"
#include "conformance/suite.hpp"
#include "harness/encode.hpp"
#include "harness/image_hash.hpp"

namespace tool {
namespace {

// ---- conformance run ---------------------------------------------------------------------

struct ConformanceArgs {
    std::string cases;
    std::string exclude;
    std::string caselist;
    std::string baseline;
    std::string scenes;
    SceneArgs scene_args;  // --texture-root
    std::optional<int> shard_index;
    std::optional<int> shard_count;
    std::vector<std::string> skips;
    std::vector<std::string> flakes;
    bool resume = false;
    BackendArgs against{"osmesa"};
    ProfileArgs profile;
    unsigned threads = 0;
    std::string output;
    std::string verdict = "exact";
};

int run_conformance(const ConformanceArgs& a) {
    conformance::RunOptions o;
    o.scenes_root = a.scenes.empty() ? default_scenes_root() : std::filesystem::path(a.scenes);
    o.scene_limits = a.scene_args.limits();
    o.case_globs = split_globs(a.cases);
    o.exclude_globs = split_globs(a.exclude);
    if (!a.caselist.empty()) o.caselist = a.caselist;
    if (!a.baseline.empty()) o.baseline = a.baseline;
    try {
        const conformance::Shard shard = conformance::resolve_shard(
            a.shard_index, a.shard_count, conformance::process_environment());
        o.shard_index = shard.index;
        o.shard_count = shard.count;
        o.shard_source = shard.source;
    } catch (const conformance::ShardError& e) {
        std::cerr << "refraster conformance run: " << harness::encode::terminal(e.what()) << "\n";
        return exit_code(e.exit_class());
    }
    o.skips.assign(a.skips.begin(), a.skips.end());
    o.flakes.assign(a.flakes.begin(), a.flakes.end());
    o.resume = a.resume;
    o.gl_verdict = a.verdict == "gl";
    const char* ci = std::getenv("CI");
    o.progress = ::isatty(STDOUT_FILENO) != 0 && !(ci != nullptr && std::string(ci) == "true");
    o.output = a.output;
    try {
        BackendArgs ref{"ref"};
        ref.profile = a.profile;
        ref.threads = a.threads;
        ref.timeout = a.against.timeout;  // one limit a scene, for either side
        o.reference = ref.options();
        o.against = a.against.options();
        const auto s = conformance::run_suite(o, std::cout);
        return s.failed == 0 ? kExitOk : kExitMismatch;
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const std::exception& e) {
        // Whatever stops a run before its verdict (a profile, a scene, a results directory
        // that cannot be resumed) is reported as the run's bad input.
        std::cerr << "refraster conformance run: " << harness::encode::terminal(e.what()) << "\n";
        return kExitBadInput;
    }
}

// ---- conformance merge -------------------------------------------------------------------

// merge SHARD_DIR... --output DIR: as `run`, exit 0 when every case passed and 1 when some
// failed, and 1 too when some shards are missing (the report of the others is written and says
// so); 2 for shards that cannot be one run. Its last line is run's summary.
int run_merge(const std::vector<std::string>& shards, const std::string& output) {
    std::vector<std::filesystem::path> dirs(shards.begin(), shards.end());
    try {
        const auto summary = conformance::merge_shards(dirs, output, std::cout);
        std::cout << "report: " << (std::filesystem::path(output) / "index.html").string() << "\n";
        std::cout << summary.counts.line()
                  << (summary.missing_shards.empty()
                          ? ""
                          : "; " + std::to_string(summary.missing_shards.size()) + " of " +
                                std::to_string(summary.shard_count) + " shards missing")
                  << "\n";
        return summary.missing_shards.empty() && summary.counts.failed == 0 ? kExitOk
                                                                            : kExitMismatch;
    } catch (const conformance::MergeError& e) {
        std::cerr << "refraster conformance merge: " << harness::encode::terminal(e.what()) << "\n";
        return exit_code(e.exit_class());
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const std::exception& e) {
        std::cerr << "refraster conformance merge: " << harness::encode::terminal(output) << ": "
                  << harness::encode::terminal(e.what()) << "\n";
        return kExitBadInput;
    }
}

// ---- conformance hashes ------------------------------------------------------------------

// One line per scene, "case hash", of the reference's render (or its status when it does not
// render): the golden file conformance/expectations/ref-hashes.txt.
int run_hashes(const std::string& scenes, const SceneArgs& scene_args, const ProfileArgs& profile) {
    try {
        BackendArgs ref{"ref"};
        ref.profile = profile;
        // Fused arithmetic wherever llvmpipe fuses, whatever this CPU has: std::fma gives the
        // same result everywhere, so the hashes do not depend on the host.
        ref.profile.overrides.insert(ref.profile.overrides.begin(), "viewport_fma=on");
        auto backend = harness::make_backend(ref.options());
        const auto root = scenes.empty() ? default_scenes_root() : std::filesystem::path(scenes);
        std::cout << "# refraster reference image hashes (FNV-1a 64 of decoded colour and depth), "
                     "profile "
                  << ref.profile.load().name << "\n"
                  << "# regenerate: build/bin/refraster conformance hashes > "
                     "conformance/expectations/ref-hashes.txt\n";
        for (const auto& c : conformance::discover_cases(root)) {
            const auto r = backend->render(harness::load_scene(c.file, scene_args.limits()));
            std::cout << c.name << " "
                      << (r.status == harness::RenderStatus::Ok
                              ? harness::render_hash(r.image, r.samples)
                              : std::string(harness::to_string(r.status)))
                      << "\n";
        }
        return kExitOk;
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const std::exception& e) {
        std::cerr << "refraster conformance hashes: " << harness::encode::terminal(e.what())
                  << "\n";
        return kExitBadInput;
    }
}

// The variables the three subcommands' options are bound to.
struct ConformanceCommandArgs {
    std::vector<std::string> merge_shards;
    std::string merge_output;
    ConformanceArgs run;
    std::string hash_scenes;
    SceneArgs hash_scene_args;
    ProfileArgs hash_profile;
};

}  // namespace

Command add_conformance_command(CLI::App& app) {
    auto a = std::make_shared<ConformanceCommandArgs>();
    auto* conf_cmd = app.add_subcommand("conformance", "The conformance suite");
    conf_cmd->require_subcommand(1);

    auto* merge_cmd = conf_cmd->add_subcommand(
        "merge", "One run's results and reports from the output directories of its shards");
    merge_cmd->add_option("shards", a->merge_shards, "The shards' output directories")->required();
    merge_cmd->add_option("-o,--output", a->merge_output, "Directory for the merged run")
        ->required();

    ConformanceArgs& conf = a->run;
    auto* run_cmd = conf_cmd->add_subcommand("run", "Run the scenes against a GL backend");
    run_cmd->add_option("--cases", conf.cases, "Comma-separated globs on case names (smoke.*)");
    run_cmd->add_option("--exclude", conf.exclude, "Comma-separated globs of cases to leave out");
    run_cmd
        ->add_option("--caselist", conf.caselist,
                     "File of case names or globs, one a line, '#' comments")
        ->check(CLI::ExistingFile);
    run_cmd
        ->add_option(
            "--baseline", conf.baseline,
            "Expected failures, deqp-runner style name,Status lines (a previous failures.csv)")
        ->check(CLI::ExistingFile);
    run_cmd
        ->add_option("--skips", conf.skips,
                     "deqp-runner skips file: regular expressions, one a line, of cases to "
                     "leave out (repeatable)")
        ->check(CLI::ExistingFile);
    run_cmd
        ->add_option("--flakes", conf.flakes,
                     "deqp-runner flakes file: regular expressions of cases whose failures are "
                     "Flake (repeatable)")
        ->check(CLI::ExistingFile);
    run_cmd
        ->add_option("--shard-index", conf.shard_index,
                     "This shard, 0-based (default: from GTEST_SHARD_INDEX, GitLab's "
                     "CI_NODE_INDEX, Kubernetes' JOB_COMPLETION_INDEX or Slurm's "
                     "SLURM_ARRAY_TASK_ID; else 0)")
        ->check(CLI::NonNegativeNumber);
    run_cmd
        ->add_option("--shard-count", conf.shard_count,
                     "Number of shards (default: GTEST_TOTAL_SHARDS, CI_NODE_TOTAL, "
                     "REFRASTER_SHARD_COUNT, SLURM_ARRAY_TASK_COUNT; else 1)")
        ->check(CLI::PositiveNumber);
    run_cmd->add_flag("--resume", conf.resume,
                      "Continue a run killed part way, keeping its finished cases");
    run_cmd->add_option("--scenes", conf.scenes, "Scene root (default conformance/scenes)");
    add_scene_options(run_cmd, conf.scene_args);
    add_backend_option(run_cmd, "--against", conf.against.backend,
                       "GL backend compared with the reference", {"ref", "osmesa", "egl"});
    add_driver_options(run_cmd, conf.against);
    add_profile_options(run_cmd, conf.profile);
    run_cmd
        ->add_option("--verdict", conf.verdict,
                     "exact: any difference from the profile fails; gl: differences GL allows "
                     "(sub-pixel precision, tie rule, clipping, line and point rules, "
                     "interpolation precision) pass and violations fail, the rule named")
        ->check(CLI::IsMember({"exact", "gl"}))
        ->capture_default_str();
    add_threads_option(run_cmd, conf.threads);
    run_cmd->add_option("-o,--output", conf.output, "Directory for results.jsonl and images")
        ->required();

    auto* hash_cmd =
        conf_cmd->add_subcommand("hashes", "Print the reference's image hash for every scene");
    hash_cmd->add_option("--scenes", a->hash_scenes, "Scene root (default conformance/scenes)");
    add_scene_options(hash_cmd, a->hash_scene_args);
    add_profile_options(hash_cmd, a->hash_profile);

    return {conf_cmd, [a, merge_cmd, run_cmd, hash_cmd] {
                if (merge_cmd->parsed()) return run_merge(a->merge_shards, a->merge_output);
                if (run_cmd->parsed()) return run_conformance(a->run);
                if (hash_cmd->parsed())
                    return run_hashes(a->hash_scenes, a->hash_scene_args, a->hash_profile);
                return kExitBadInput;
            }};
}

}  // namespace tool
