// study NAME --output DIR: runs the study, then writes study.csv, study.svg and summary.md into
// DIR, each file whole or not at all; prints the conclusions (docs/precision-study.md).
#include "harness/study.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <new>

#include "commands/commands.hpp"
#include "harness/encode.hpp"
#include "harness/files.hpp"

namespace tool {
namespace {

struct StudyArgs {
    std::string name;
    std::string output;
    std::uint64_t seed = 1;
    bool quick = false;
    bool quiet = false;
};

int run_study(const StudyArgs& a) {
    const std::filesystem::path dir(a.output);
    std::error_code ec;
    if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec)) {
        std::cerr << harness::encode::terminal(a.output)
                  << ": --output names a file, not a directory\n";
        return kExitBadInput;
    }
    harness::StudyOptions o;
    o.seed = a.seed;
    o.quick = a.quick;
    if (!a.quiet) o.progress = [](const std::string& line) { std::cerr << line << "\n"; };
    harness::StudyOutput out;
    try {
        out = harness::run_study(a.name, o);
    } catch (const harness::StudyError& e) {
        std::cerr << "refraster study: " << harness::encode::terminal(e.what()) << "\n";
        return exit_code(e.exit_class());
    }
    std::string command = "refraster study " + a.name + " --output " + a.output;
    if (a.seed != 1) command += " --seed " + std::to_string(a.seed);
    if (a.quick) command += " --quick";
    try {
        std::filesystem::create_directories(dir);
        harness::write_file_atomically(dir / "study.csv", out.csv);
        harness::write_file_atomically(dir / "study.svg", out.svg);
        harness::write_file_atomically(dir / "summary.md",
                                       harness::study_summary_markdown(out, command));
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const std::exception& e) {
        std::cerr << harness::encode::terminal(a.output) << ": "
                  << harness::encode::terminal(e.what()) << "\n";
        return kExitBadInput;
    }
    for (const std::string& line : out.summary) std::cout << line << "\n";
    if (!out.decisions.empty()) std::cout << "\n" << out.decisions;
    if (!out.conclusions.empty()) std::cout << "\n";
    for (const std::string& line : out.conclusions) std::cout << "- " << line << "\n";
    std::cout << "wrote " << (dir / "study.csv").string() << ", study.svg and summary.md\n";
    return kExitOk;
}

}  // namespace

Command add_study_command(CLI::App& app) {
    auto a = std::make_shared<StudyArgs>();
    auto* cmd =
        app.add_subcommand("study",
                           "Measure error against run time for precision choices, antialiasing and "
                           "stiff cases, against exact answers (docs/precision-study.md)");
    cmd->add_option("study", a->name, "precision, antialiasing or stability")
        ->required()
        ->check(CLI::IsMember(harness::study_names()));
    cmd->add_option("-o,--output", a->output, "Directory for study.csv, study.svg, summary.md")
        ->required();
    cmd->add_option("--seed", a->seed, "Seed of the workloads")->capture_default_str();
    cmd->add_flag("--quick", a->quick, "Small sizes (seconds, for CI)");
    cmd->add_flag("--quiet", a->quiet, "No progress lines on stderr");
    return {cmd, [a] { return run_study(*a); }};
}

}  // namespace tool
