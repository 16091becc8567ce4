#include "conformance/suite.hpp"

#include <fcntl.h>
#include <fnmatch.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <new>
#include <nlohmann/json.hpp>
#include <ostream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "conformance/deqp_runner.hpp"
#include "conformance/reports.hpp"
#include "harness/case_result.hpp"
#include "harness/explain.hpp"
#include "harness/files.hpp"
#include "harness/gl_verdict.hpp"
#include "harness/image_io.hpp"

namespace conformance {

std::string case_name_for(const std::filesystem::path& root, const std::filesystem::path& file) {
    std::string rel = std::filesystem::relative(file, root).replace_extension("").generic_string();
    std::replace(rel.begin(), rel.end(), '/', '.');
    return rel;
}

std::vector<CaseFile> discover_cases(const std::filesystem::path& root) {
    if (!std::filesystem::is_directory(root)) {
        throw std::runtime_error(root.string() + ": not a directory of scenes");
    }
    std::vector<CaseFile> cases;
    for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
        if (!e.is_regular_file() || e.path().extension() != ".json") continue;
        cases.push_back({case_name_for(root, e.path()), e.path()});
    }
    std::sort(cases.begin(), cases.end(),
              [](const auto& a, const auto& b) { return a.name < b.name; });
    for (std::size_t i = 1; i < cases.size(); ++i) {
        if (cases[i].name == cases[i - 1].name) {
            throw std::runtime_error("duplicate case name " + cases[i].name + ": " +
                                     cases[i - 1].file.string() + " and " + cases[i].file.string());
        }
    }
    return cases;
}

bool matches_any(const std::string& name, const std::vector<std::string>& globs) {
    if (globs.empty()) return true;
    return std::any_of(globs.begin(), globs.end(),
                       [&](const auto& g) { return ::fnmatch(g.c_str(), name.c_str(), 0) == 0; });
}

namespace {

// The lines of a list file with their numbers: '#' starts a comment, blank lines are dropped,
// the rest trimmed.
std::vector<std::pair<std::size_t, std::string>> read_numbered_lines(
    const std::filesystem::path& file, const char* what) {
    std::ifstream in(file);
    if (!in) throw std::runtime_error(file.string() + ": cannot read the " + what);
    std::vector<std::pair<std::size_t, std::string>> out;
    std::size_t n = 0;
    for (std::string line; std::getline(in, line);) {
        ++n;
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        const auto b = line.find_first_not_of(" \t\r");
        const auto e = line.find_last_not_of(" \t\r");
        if (b == std::string::npos) continue;
        out.emplace_back(n, line.substr(b, e - b + 1));
    }
    return out;
}

std::vector<std::string> read_lines(const std::filesystem::path& file, const char* what) {
    std::vector<std::string> out;
    for (auto& [n, line] : read_numbered_lines(file, what)) out.push_back(std::move(line));
    return out;
}

}  // namespace

void NamePatterns::add_file(const std::filesystem::path& file) {
    for (const auto& [n, line] : read_numbered_lines(file, "pattern file")) {
        try {
            patterns_.emplace_back(std::regex(line, std::regex::ECMAScript),
                                   file.filename().string() + ":" + std::to_string(n));
        } catch (const std::regex_error& e) {
            throw std::runtime_error(file.string() + ":" + std::to_string(n) + ": '" + line +
                                     "' is not a regular expression (" + e.what() + ")");
        }
    }
}

std::optional<std::string> NamePatterns::match(const std::string& name) const {
    for (const auto& [re, where] : patterns_)
        if (std::regex_search(name, re)) return where;
    return std::nullopt;
}

std::vector<std::string> read_caselist(const std::filesystem::path& file) {
    return read_lines(file, "case list");
}

std::map<std::string, std::string> read_baseline(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw std::runtime_error(file.string() + ": cannot read the baseline");
    std::map<std::string, std::string> out;
    std::size_t n = 0;
    for (std::string line; std::getline(in, line);) {
        ++n;
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        const auto b = line.find_first_not_of(" \t\r");
        if (b == std::string::npos) continue;
        line = line.substr(b, line.find_last_not_of(" \t\r") - b + 1);
        // deqp-runner's RunnerResults::from_csv: a name, a comma, a status, and anything
        // after a further comma (results.csv's duration) is not read.
        const auto comma = line.find(',');
        const std::string status =
            comma == std::string::npos
                ? ""
                : line.substr(comma + 1, line.find(',', comma + 1) - comma - 1);
        const auto word = deqp_runner_word(status);
        if (comma == std::string::npos || comma == 0 || !word) {
            throw std::runtime_error(
                file.string() + ":" + std::to_string(n) +
                ": expected name,Status with one of deqp-runner's statuses (Pass, Fail, Skip, "
                "Crash, Timeout, Warn, Flake, KnownFlake, Missing, ExpectedFail, "
                "UnexpectedImprovement(Status), UnexpectedPass)");
        }
        if (out.count(line.substr(0, comma)) != 0) {
            throw std::runtime_error(file.string() + ":" + std::to_string(n) + ": " +
                                     line.substr(0, comma) + " is listed twice");
        }
        out[line.substr(0, comma)] = *word;
    }
    return out;
}

bool apply_baseline(harness::CaseResult& r, const std::map<std::string, std::string>* baseline) {
    using harness::CaseStatus;
    if (baseline == nullptr) return harness::counts_as_failure(r.status);
    const auto it = baseline->find(r.name);
    const std::string listed = it == baseline->end() ? "" : it->second;
    const CaseStatus result = r.status;
    const std::string verdict =
        deqp_runner_with_baseline(deqp_runner_status(harness::to_string(result), ""), listed);
    const auto change = [&](CaseStatus to) {
        r.raw_status = result;
        r.status = to;
    };
    if (verdict == "ExpectedFail") {
        change(CaseStatus::ExpectedFail);
    } else if (verdict == "UnexpectedImprovement(Pass)") {
        change(CaseStatus::UnexpectedPass);
    } else if (verdict.rfind("UnexpectedImprovement(", 0) == 0) {
        change(CaseStatus::UnexpectedImprovement);
    }
    return harness::counts_as_failure(r.status);
}

namespace {

// What a killed run left in results.jsonl. Records are appended one whole line at a time and
// made durable before the next case starts, so a kill can leave at most one torn line, at the
// end and without its newline. That line is cut off; every complete line stays byte for byte,
// and the new records are appended after them. Anything else that does not parse (a complete
// line that is not a record, a case recorded twice) means the file was not written by an
// interrupted run: resuming refuses rather than guess which records to trust.
struct Recovered {
    std::map<std::string, nlohmann::json> records;  // by case name
    std::size_t torn_bytes = 0;                     // the torn last line that was cut off
};

Recovered recover(const std::filesystem::path& jsonl) {
    Recovered r;
    if (!std::filesystem::exists(jsonl)) return r;
    std::ifstream in(jsonl, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    in.close();
    const std::string text = ss.str();
    std::size_t start = 0;
    std::size_t line_no = 0;
    while (start < text.size()) {
        const auto nl = text.find('\n', start);
        if (nl == std::string::npos) {
            r.torn_bytes = text.size() - start;
            break;
        }
        ++line_no;
        const auto where = jsonl.string() + ":" + std::to_string(line_no);
        nlohmann::json j;
        try {
            j = nlohmann::json::parse(text.substr(start, nl - start));
        } catch (const nlohmann::json::exception&) {
            throw std::runtime_error(
                where +
                ": not a result record; refusing to resume (only a torn last line "
                "is dropped)");
        }
        if (!j.is_object() || !j.contains("case") || !j["case"].is_string()) {
            throw std::runtime_error(where +
                                     ": a record without a \"case\" name; refusing to resume");
        }
        // The name is read before the record is moved into the map.
        std::string name = j["case"].get<std::string>();
        if (r.records.count(name) != 0) {
            throw std::runtime_error(where + ": case " + name +
                                     " is recorded twice; refusing to resume");
        }
        r.records.emplace(std::move(name), std::move(j));
        start = nl + 1;
    }
    if (r.torn_bytes > 0) std::filesystem::resize_file(jsonl, text.size() - r.torn_bytes);
    return r;
}

// A kept record must come from the same comparison as the run that continues it: the same
// reference (and profile) and the same backend and driver.
void check_same_run(const std::map<std::string, nlohmann::json>& records,
                    const std::string& reference, const std::string& profile,
                    const std::string& actual, const std::filesystem::path& jsonl) {
    for (const auto& [name, j] : records) {
        // Records of cases that never rendered (a bad scene file) carry no backends.
        const auto recorded = [&](const char* side, const char* key, const std::string& otherwise) {
            if (!j.contains(side) || !j[side].is_object()) return otherwise;
            const auto& s = j[side];
            if (std::string(key) == "profile") {
                return s.contains("provenance") && s["provenance"].is_object()
                           ? s["provenance"].value("profile", otherwise)
                           : otherwise;
            }
            return s.value(key, otherwise);
        };
        const std::string rec_ref = recorded("reference", "backend", reference);
        const std::string rec_profile = recorded("reference", "profile", profile);
        const std::string rec_actual = recorded("actual", "backend", actual);
        if (rec_ref != reference || rec_profile != profile || rec_actual != actual) {
            throw std::runtime_error(jsonl.string() + ": case " + name + " was run as " + rec_ref +
                                     " (" + rec_profile + ") against " + rec_actual +
                                     "; this run is " + reference + " (" + profile + ") against " +
                                     actual + ": refusing to resume into it");
        }
    }
}

harness::CaseResult run_one(const CaseFile& c, harness::Backend& reference,
                            harness::Backend& actual, const refraster::Profile& profile,
                            bool gl_verdict) {
    try {
        const harness::Scene scene = harness::load_scene(c.file);
        auto r = harness::run_case(scene, c.name, reference, actual);
        if (!scene.file.name.empty() && scene.file.name != c.name) {
            r.status = harness::CaseStatus::InternalError;
            r.message = c.file.string() + ": name \"" + scene.file.name +
                        "\" does not match its path (expected \"" + c.name + "\")";
        }
        // GL verdicts: differences GL allows pass, violations fail naming the rule.
        if (gl_verdict && r.status == harness::CaseStatus::Fail && r.comparison &&
            reference.kind() == harness::BackendKind::Ref && r.reference && r.actual) {
            const auto v = harness::gl_verdict(scene, profile, r.reference->image, r.actual->image);
            r.gl_verdict = v.summary();
            if (v.passes() && v.differing > 0) {
                r.status = harness::CaseStatus::Pass;
                r.message = r.gl_verdict;
                return r;
            }
            r.message += "; " + r.gl_verdict;
        }
        // A failure is explained at its pixel of largest difference (explain.hpp).
        if (r.status == harness::CaseStatus::Fail && r.comparison &&
            reference.kind() == harness::BackendKind::Ref) {
            if (const auto at = harness::pixel_of_largest_difference(r)) {
                const int x = (*at)[0];
                const int y = (*at)[1];
                try {
                    const auto e = harness::explain_pixel(scene, profile, x, y, &actual);
                    r.explained_pixel = std::array<int, 2>{x, y};
                    r.explanation = e.verdict;
                    r.explanation_difference = e.difference;
                    r.explanation_rule = e.rule;
                    r.explanation_text = harness::explanation_text(e);
                    r.explanation_svg = harness::explanation_svg(e);
                } catch (const std::bad_alloc&) {
                    throw;  // running out of memory: main reports it (exit 3)
                } catch (const std::exception&) {
                    // The case's result stands without an explanation.
                }
            }
        }
        return r;
    } catch (const harness::SceneError& e) {
        return harness::case_error(c.name, c.file.string(), e.what());
    }
}

void write_images(const harness::CaseResult& r, const std::filesystem::path& dir) {
    const auto save = [&](const std::optional<harness::RenderResult>& rr, const std::string& who) {
        if (!rr || rr->status != harness::RenderStatus::Ok) return;
        harness::write_color_image(
            rr->image, dir / (r.name + "." + who +
                              std::string(harness::image_extension(rr->image.color_format))));
    };
    save(r.reference, r.reference_name);
    save(r.actual, r.actual_name);
    if (r.comparison && r.comparison->mismatched_pixels > 0 && !r.comparison->size_mismatch) {
        harness::write_color_image(r.comparison->mask, dir / (r.name + ".mask.png"));
    }
    // The explain view of an explained failure: explain/NAME.svg and NAME.txt beside images/.
    if (!r.explanation_svg.empty()) {
        // An aid, not a result: a view that cannot be written is left out (the case page
        // links it only where it exists).
        try {
            const auto explain_dir = dir.parent_path() / "explain";
            std::filesystem::create_directories(explain_dir);
            harness::write_file_atomically(explain_dir / (r.name + ".svg"), r.explanation_svg);
            harness::write_file_atomically(explain_dir / (r.name + ".txt"), r.explanation_text);
        } catch (const std::bad_alloc&) {
            throw;  // running out of memory: main reports it (exit 3)
        } catch (const std::exception&) {
        }
    }
    // A 4x target's sample mask: each pixel a 2x2 block of its samples' classes.
    if (r.sample_comparison && r.sample_comparison->mismatched_samples > 0 &&
        !r.sample_comparison->size_mismatch) {
        harness::write_color_image(r.sample_comparison->mask, dir / (r.name + ".samples.png"));
    }
}

// Appends one line and makes it durable before the next case starts: a run killed at any
// moment leaves at most a half line, which recover() drops.
void append_line(const std::filesystem::path& path, const std::string& line) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error(path.string() + ": cannot write");
    const std::string data = line + "\n";
    std::size_t off = 0;
    while (off < data.size()) {
        const ssize_t n = ::write(fd, data.data() + off, data.size() - off);
        if (n < 0) {
            ::close(fd);
            throw std::runtime_error(path.string() + ": write failed");
        }
        off += static_cast<std::size_t>(n);
    }
    ::fdatasync(fd);
    ::close(fd);
}

std::string format_duration(double s) {
    const auto total = static_cast<long>(s + 0.5);
    std::ostringstream o;
    if (total >= 3600) o << total / 3600 << "h";
    if (total >= 60) o << (total / 60) % 60 << "m";
    o << total % 60 << "s";
    return o.str();
}

}  // namespace

RunSummary run_suite(const RunOptions& options, std::ostream& console) {
    if (options.shard_count < 1 || options.shard_index < 0 ||
        options.shard_index >= options.shard_count) {
        throw std::runtime_error("shard index " + std::to_string(options.shard_index) +
                                 " is not in [0, " + std::to_string(options.shard_count) + ")");
    }
    std::vector<std::string> listed;
    if (options.caselist) listed = read_caselist(*options.caselist);
    std::map<std::string, std::string> baseline;
    if (options.baseline) baseline = read_baseline(*options.baseline);
    NamePatterns skips, flakes;
    for (const auto& f : options.skips) skips.add_file(f);
    for (const auto& f : options.flakes) flakes.add_file(f);

    std::vector<CaseFile> cases;
    std::size_t index = 0;
    for (auto& c : discover_cases(options.scenes_root)) {
        if (!matches_any(c.name, options.case_globs) ||
            (!options.exclude_globs.empty() && matches_any(c.name, options.exclude_globs))) {
            continue;
        }
        if (options.caselist && !matches_any(c.name, listed)) continue;
        if (skips.match(c.name)) continue;
        if (index++ % static_cast<std::size_t>(options.shard_count) !=
            static_cast<std::size_t>(options.shard_index))
            continue;
        cases.push_back(std::move(c));
    }
    if (cases.empty()) throw std::runtime_error("no scene matched the selection");

    std::filesystem::create_directories(options.output / "images");
    const auto results_path = options.output / "results.jsonl";
    auto reference = harness::make_backend(options.reference);
    auto actual = harness::make_backend(options.against);

    std::map<std::string, nlohmann::json> done;
    if (options.resume) {
        auto recovered = recover(results_path);
        check_same_run(recovered.records, reference->name(), options.reference.profile.name,
                       actual->name(), results_path);
        done = std::move(recovered.records);
        console << "resume: kept " << done.size() << " finished case"
                << (done.size() == 1 ? "" : "s") << " of " << results_path.string();
        if (recovered.torn_bytes > 0)
            console << ", cut a torn last line of " << recovered.torn_bytes << " bytes";
        console << "\n" << std::flush;
    } else {
        std::ofstream(results_path, std::ios::trunc);
    }
    if (!std::filesystem::exists(results_path))
        throw std::runtime_error(results_path.string() + ": cannot write");

    RunSummary s;
    const auto count = [&](harness::CaseStatus st) {
        if (st == harness::CaseStatus::NotSupported) {
            ++s.skipped;
        } else if (harness::counts_as_failure(st)) {
            ++s.failed;
        } else {
            ++s.passed;
        }
    };
    std::size_t finished = 0;
    for (const auto& c : cases) {
        if (const auto it = done.find(c.name); it != done.end()) {
            const auto st = harness::case_status_from_string(it->second.value("status", ""));
            count(st.value_or(harness::CaseStatus::InternalError));
            ++finished;
        }
    }
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t resumed = finished;
    for (const auto& c : cases) {
        if (done.count(c.name) != 0) continue;
        harness::CaseResult r =
            run_one(c, *reference, *actual, options.reference.profile, options.gl_verdict);
        const bool failed = apply_baseline(r, options.baseline ? &baseline : nullptr);
        const auto known_flake = failed ? flakes.match(c.name) : std::nullopt;
        if (known_flake) {
            // A failure of a case the flakes files list is a KnownFlake, as deqp-runner's
            // --flakes makes it, and is not run again.
            r.raw_status = r.raw_status.value_or(r.status);
            r.status = harness::CaseStatus::KnownFlake;
            r.message =
                "known flake (" + *known_flake + ")" + (r.message.empty() ? "" : ": " + r.message);
        } else if (failed && options.baseline) {
            // An unexpected result runs once more: the same again is the result, anything
            // else was a flake.
            const std::string first(harness::to_string(r.raw_status.value_or(r.status)));
            harness::CaseResult again =
                run_one(c, *reference, *actual, options.reference.profile, options.gl_verdict);
            if (std::string(harness::to_string(again.status)) != first) {
                r.raw_status = r.raw_status.value_or(r.status);
                r.status = harness::CaseStatus::Flake;
                r.message = "unexpected " + first + ", then " +
                            std::string(harness::to_string(again.status)) + " on the re-run" +
                            (r.message.empty() ? "" : ": " + r.message);
            }
        }
        r.shard = std::array<int, 2>{options.shard_index, options.shard_count};
        r.shard_source = options.shard_source;
        try {
            write_images(r, options.output / "images");
        } catch (const harness::ImageIoError& e) {
            if (!harness::counts_as_failure(r.status)) {
                r.status = harness::CaseStatus::InternalError;
                r.message = e.what();
            }
        }
        append_line(results_path, harness::to_json_line(r));
        count(r.status);
        ++finished;
        if (options.progress) {
            const double elapsed =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            const double per = elapsed / static_cast<double>(finished - resumed);
            console << "\r\033[K[" << finished << "/" << cases.size() << "] " << s.passed
                    << " pass, " << s.failed << " fail, " << s.skipped << " skip, ETA "
                    << format_duration(per * static_cast<double>(cases.size() - finished)) << " "
                    << std::flush;
        }
        if (harness::counts_as_failure(r.status) || !options.progress) {
            if (options.progress) console << "\r\033[K";
            console << to_string(r.status) << " " << r.name;
            if (!r.message.empty()) console << ": " << r.message;
            if (!r.explanation_rule.empty()) console << " [" << r.explanation_rule << "]";
            console << '\n' << std::flush;
        }
    }
    if (options.progress) console << "\r\033[K";
    write_reports(options.output, cases.size());
    console << "results: " << results_path.string()
            << "; report: " << (options.output / "index.html").string() << "\n";
    console << s.passed << " passed, " << s.failed << " failed, " << s.skipped << " skipped\n";
    return s;
}

}  // namespace conformance
