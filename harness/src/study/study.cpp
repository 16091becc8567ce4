#include "harness/study.hpp"

#include <chrono>
#include <ctime>
#include <sstream>

#include "harness/bench.hpp"
#include "refraster_git_commit.hpp"  // generated at build time (cmake/GitCommit.cmake)
#include "study_common.hpp"

namespace harness {

std::vector<std::string> study_names() {
    return {"precision", "antialiasing", "stability"};
}

StudyOutput run_study(const std::string& name, const StudyOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    StudyOutput out;
    if (name == "precision") {
        out = run_precision_study(options);
    } else if (name == "antialiasing") {
        out = run_antialiasing_study(options);
    } else if (name == "stability") {
        out = run_stability_study(options);
    } else {
        throw StudyError("unknown study '" + name +
                         "' (known: precision, antialiasing, stability)");
    }
    const double seconds = study::seconds_since(t0);
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", &utc);
    std::ostringstream secs;
    secs.precision(3);
    secs << seconds;
    out.provenance = {{"study", name},
                      {"seed", std::to_string(options.seed)},
                      {"quick", options.quick ? "yes" : "no"},
                      {"commit", REFRASTER_GIT_COMMIT},
                      {"cpu_flags", bench_cpu_flags()},
                      {"kernels", "scalar study kernels, -O2 -ffp-contract=off, one thread"},
                      {"date", date},
                      {"seconds", secs.str()}};
    return out;
}

std::string study_summary_markdown(const StudyOutput& out, const std::string& command) {
    std::ostringstream o;
    o << "# refraster study " << out.name << "\n\n";
    if (!out.decisions.empty()) o << "## Decisions\n\n" << out.decisions << "\n";
    if (!out.conclusions.empty()) {
        o << "## Conclusions\n\n";
        for (const std::string& line : out.conclusions) o << "- " << line << "\n";
        o << "\n";
    }
    o << "## Provenance\n\nReproduce with `" << command << "`.\n\n";
    o << "| | |\n|---|---|\n";
    for (const auto& [k, v] : out.provenance) o << "| " << k << " | " << v << " |\n";
    o << "\n## Every number\n\n";
    for (const std::string& line : out.summary) o << "- " << line << "\n";
    o << "\nThe table: study.csv. The figure: study.svg. What every column means: "
         "docs/precision-study.md.\n";
    return o.str();
}

}  // namespace harness
