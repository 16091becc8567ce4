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
#include <regex>
#include <set>
#include <span>
#include <sstream>
#include <stdexcept>

#include "conformance/deqp_runner.hpp"
#include "conformance/records.hpp"
#include "conformance/reports.hpp"
#include "conformance/shard.hpp"
#include "harness/case_result.hpp"
#include "harness/encode.hpp"
#include "harness/explain.hpp"
#include "harness/files.hpp"
#include "harness/gl_verdict.hpp"
#include "harness/image_io.hpp"
#include "harness/profile_io.hpp"
#include "harness/scene_text.hpp"
#include "record_check.hpp"
#include "refraster/renderer.hpp"

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
        std::string name = case_name_for(root, e.path());
        // Checked once, here: every file a run writes for the case is named after it.
        if (const auto problem = case_name_problem(name)) {
            throw std::runtime_error(harness::encode::terminal(e.path().string()) + ": " +
                                     *problem + "; a scene's path below " +
                                     harness::encode::terminal(root.string()) +
                                     " is its case name");
        }
        cases.push_back({std::move(name), e.path()});
    }
    std::sort(cases.begin(), cases.end(),
              [](const auto& a, const auto& b) { return a.name < b.name; });
    for (std::size_t i = 1; i < cases.size(); ++i) {
        if (cases[i].name == cases[i - 1].name) {
            throw std::runtime_error("duplicate case name " + cases[i].name + ": " +
                                     harness::encode::terminal(cases[i - 1].file.string()) +
                                     " and " + harness::encode::terminal(cases[i].file.string()));
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

using json = nlohmann::json;

std::string shown(const std::filesystem::path& p) {
    return harness::encode::terminal(p.string());
}

// FNV-1a 64 of a file's bytes, in hex: a run's baseline or flakes file, for its run.json.
std::string file_hash(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::uint64_t h = 1469598103934665603ull;
    for (char c; in.get(c);) {
        h ^= static_cast<unsigned char>(c);
        h *= 1099511628211ull;
    }
    std::ostringstream o;
    o << std::hex << h;
    return o.str();
}

// What a killed run left in results.jsonl. Records are appended one whole line at a time and
// made durable before the next case starts, so a kill can leave at most one torn line, at the
// end and without its newline. That line is cut off (once every check has passed); every
// complete line stays byte for byte, and the new records are appended after them. Anything
// else that does not parse (a complete line that is not a record, a case recorded twice)
// means the file was not written by an interrupted run: resuming refuses rather than guess
// which records to trust.
struct Recovered {
    std::map<std::string, json> records;  // by case name
    std::size_t torn_bytes = 0;           // the torn last line to cut off
    std::uint64_t size = 0;
    std::map<std::string, std::string> identity;  // of every kept record that rendered
};

// The keys of run.json that must be equal for a run to continue another.
const char* const kSetupKeys[] = {"format",   "commit", "reference", "against",  "verdict",
                                  "baseline", "flakes", "shard",     "selection"};

Recovered recover(const std::filesystem::path& output, const json& setup,
                  const std::set<std::string>& selected) {
    Recovered r;
    const auto header_path = output / "run.json";
    const auto jsonl = output / "results.jsonl";
    const std::string refuse = "; refusing to resume (run again without --resume)";
    std::error_code ec;
    if (!std::filesystem::exists(std::filesystem::symlink_status(header_path, ec))) {
        if (!std::filesystem::exists(std::filesystem::symlink_status(jsonl, ec))) return r;
        throw std::runtime_error(shown(header_path) +
                                 ": missing: results.jsonl was written by an older refraster or "
                                 "by a merge" +
                                 refuse);
    }
    json header;
    {
        const ResultLines h = read_result_lines(header_path);
        std::string text;
        for (const auto& l : h.lines) text += l.text + "\n";
        try {
            header = json::parse(text);
        } catch (const json::exception&) {
            throw std::runtime_error(shown(header_path) + ": not a run's setup" + refuse);
        }
    }
    for (const char* key : kSetupKeys) {
        if (!header.is_object() || !header.contains(key) || header[key] != setup[key]) {
            const std::string was =
                header.is_object() && header.contains(key) ? dump_text(header[key]) : "(none)";
            throw std::runtime_error(
                shown(header_path) + ": " + key + ": the run in this directory had " +
                harness::encode::terminal(was.substr(0, 300)) + ", this one has " +
                harness::encode::terminal(dump_text(setup[key]).substr(0, 300)) + refuse);
        }
    }
    if (!std::filesystem::exists(std::filesystem::symlink_status(jsonl, ec))) return r;
    const ResultLines lines = read_result_lines(jsonl);
    r.torn_bytes = lines.torn_bytes;
    r.size = lines.size;
    const std::string ref_backend = setup["reference"]["backend"].get<std::string>();
    const std::string act_backend = setup["against"]["backend"].get<std::string>();
    bool first = true;
    for (const ResultLine& l : lines.lines) {
        const auto where = shown(jsonl) + ":" + std::to_string(l.number);
        json j;
        try {
            j = json::parse(l.text);
        } catch (const json::exception&) {
            throw std::runtime_error(
                where +
                ": not a result record; refusing to resume (only a torn last line "
                "is dropped)");
        }
        if (const auto problem = record_problem(j))
            throw std::runtime_error(where + ": " + *problem + "; refusing to resume");
        // The name is read before the record is moved into the map.
        std::string name = j["case"].get<std::string>();
        if (r.records.count(name) != 0) {
            throw std::runtime_error(where + ": case " + name +
                                     " is recorded twice; refusing to resume");
        }
        if (selected.count(name) == 0) {
            throw std::runtime_error(where + ": case " + name +
                                     " is not in this run's selection (or no longer in the "
                                     "scenes)" +
                                     refuse);
        }
        const json shard = j.value("shard", json::object());
        if (shard.value("index", -1) != setup["shard"]["index"] ||
            shard.value("count", -1) != setup["shard"]["count"]) {
            throw std::runtime_error(where + ": case " + name + " was run as shard " +
                                     dump_text(shard.value("index", json())) + " of " +
                                     dump_text(shard.value("count", json())) + refuse);
        }
        // A kept record must come from the same comparison as the run that continues it: the
        // same commit, reference and profile, backend and driver. Records of cases that never
        // rendered (a bad scene file) carry no sides.
        const auto side = [&](const char* s, const char* key) -> std::string {
            if (!j.contains(s)) return "";
            if (std::string(key) == "backend") return j[s].value("backend", "");
            return j[s].value("provenance", json::object()).value(key, "");
        };
        if (j.contains("reference")) {
            const std::string commit = side("reference", "commit");
            const std::string profile = side("reference", "profile");
            const std::string rules = side("reference", "profile_rules");
            const std::string rec_ref = side("reference", "backend");
            const std::string rec_act = side("actual", "backend");
            const json& ref = setup["reference"];
            if (commit != setup["commit"] || profile != ref["profile"] ||
                rules != ref["profile_rules"] || rec_ref != ref_backend ||
                (j.contains("actual") && rec_act != act_backend)) {
                throw std::runtime_error(
                    where + ": case " + name + " was run as " +
                    harness::encode::terminal(rec_ref + " (" + profile + ") against " + rec_act +
                                              " at commit " + commit) +
                    "; this run is " +
                    harness::encode::terminal(
                        ref_backend + " (" + ref["profile"].get<std::string>() + ") against " +
                        act_backend + " at commit " + setup["commit"].get<std::string>()) +
                    refuse);
            }
            const auto id = identity_of(j);
            if (first) {
                r.identity = id;
                first = false;
            } else if (const auto d = first_difference(id, r.identity); !d.empty()) {
                throw std::runtime_error(where + ": case " + name +
                                         " is of another run than the records before it (" +
                                         harness::encode::terminal(d) + ")" + refuse);
            }
        }
        r.records.emplace(std::move(name), std::move(j));
    }
    return r;
}

// The GL verdict of a failing case (gl_verdict.hpp): true when every difference is a variation
// GL allows, and the case then passes with the verdict as its message.
bool judge_by_gl(harness::CaseResult& r, const harness::Scene& scene,
                 const harness::Backend& reference, const refraster::Profile& profile,
                 double timeout_seconds) {
    if (r.status != harness::CaseStatus::Fail || !r.comparison ||
        reference.kind() != harness::BackendKind::Ref || !r.reference || !r.actual)
        return false;
    // A multisampled target sample by sample; otherwise its image.
    const bool multisampled = r.reference->samples.width > 0 && r.actual->samples.width > 0;
    const auto v = harness::gl_verdict(
        scene, profile, multisampled ? r.reference->samples : r.reference->image,
        multisampled ? r.actual->samples : r.actual->image, std::nullopt, timeout_seconds);
    r.gl_verdict = v.summary();
    if (v.passes() && v.differing > 0) {
        r.status = harness::CaseStatus::Pass;
        r.message = r.gl_verdict;
        return true;
    }
    r.message += "; " + r.gl_verdict;
    return false;
}

// `alone`: the options of a backend like `actual`; a failure is run again by a backend made
// from them (a fresh worker that drew nothing before), to tell a failure of the case from one
// that depends on the cases before it.
harness::CaseResult run_one(const CaseFile& c, const harness::SceneLimits& limits,
                            harness::Backend& reference, harness::Backend& actual,
                            const refraster::Profile& profile, bool gl_verdict,
                            double timeout_seconds, const harness::BackendOptions* alone) {
    try {
        const harness::Scene scene = harness::load_scene(c.file, limits);
        auto r = harness::run_case(scene, c.name, reference, actual);
        if (!scene.file.name.empty() && scene.file.name != c.name) {
            r.status = harness::CaseStatus::InternalError;
            r.message = c.file.string() + ": name \"" + scene.file.name +
                        "\" does not match its path (expected \"" + c.name + "\")";
        }
        // GL verdicts: differences GL allows pass, violations fail naming the rule. Each render
        // of the diagnosis below (a variation, the explanation's alternatives, the run alone)
        // gets the scene's timeout of its own, so that a case's time stays bounded.
        if (gl_verdict && judge_by_gl(r, scene, reference, profile, timeout_seconds)) return r;
        if (alone != nullptr && r.status == harness::CaseStatus::Fail && r.comparison) {
            // The workers' test hooks are the run's first worker's alone.
            harness::BackendOptions fresh_options = *alone;
            for (const char* hook : {"REFRASTER_WORKER_KILL_AT=0", "REFRASTER_WORKER_HANG_AT=0",
                                     "REFRASTER_WORKER_STALE_AT=0"})
                fresh_options.environment.emplace_back(hook);
            auto fresh = harness::make_backend(fresh_options);
            auto again = harness::run_case(scene, c.name, reference, *fresh);
            if (gl_verdict) judge_by_gl(again, scene, reference, profile, timeout_seconds);
            r.alone_status = again.status;
            r.alone_mismatched_pixels = again.comparison ? again.comparison->mismatched_pixels : 0;
        }
        // A failure is explained at its pixel of largest difference (explain.hpp), from the
        // render that failed.
        if (r.status == harness::CaseStatus::Fail && r.comparison &&
            reference.kind() == harness::BackendKind::Ref) {
            if (const auto at = harness::pixel_of_largest_difference(r)) {
                const int x = (*at)[0];
                const int y = (*at)[1];
                try {
                    const auto e =
                        harness::explain_pixel(scene, profile, x, y, &actual, -1, timeout_seconds,
                                               r.actual ? &*r.actual : nullptr);
                    r.explained_pixel = std::array<int, 2>{x, y};
                    r.explanation = e.verdict;
                    r.explanation_difference = e.difference;
                    r.explanation_rule = e.rule;
                    r.explanation_text = harness::explanation_text(e);
                    r.explanation_svg = harness::explanation_svg(e);
                } catch (const std::bad_alloc&) {
                    throw;  // running out of memory: main reports it (exit 3)
                } catch (const refraster::RenderStopped& e) {
                    // The case's result stands; the message says why it is not explained.
                    r.message +=
                        std::string(r.message.empty() ? "" : "; ") + "not explained: " + e.what();
                } catch (const std::exception&) {
                    // The case's result stands without an explanation.
                }
            }
        }
        if (r.alone_status == harness::CaseStatus::Pass) {
            r.raw_status = r.status;
            r.status = harness::CaseStatus::Flake;
            r.message =
                "order dependent: fails after the cases before it in the same worker, "
                "passes alone in a fresh worker; " +
                r.message;
        }
        return r;
    } catch (const harness::SceneError& e) {
        return harness::case_error(c.name, c.file.string(), e.what());
    }
}

// The case's images and explain view, each path checked to lie inside the output
// (records.hpp).
// A failed case's pixel values for its page's pointer readout (a page opened from file:// cannot
// read its PNGs' pixels): both sides' colour and depth of every pixel, base64 in a script that
// calls refrasterCaseValues({...}). Bounded to targets of up to 256 x 256 pixels (about 0.7 MB
// for rgba8 with depth).
constexpr std::size_t kMaxValuePixels = 256 * 256;

std::string values_script(const refraster::Framebuffer& ref, const refraster::Framebuffer& act) {
    const auto bytes = [](const auto& v) {
        return harness::base64_text(std::span<const std::uint8_t>(
            reinterpret_cast<const std::uint8_t*>(v.data()), v.size() * sizeof(v[0])));
    };
    const auto side = [&](const refraster::Framebuffer& fb) {
        nlohmann::json j;
        j["color"] = fb.color_format == refraster::ColorFormat::Rgba8 ? bytes(fb.color8)
                                                                      : bytes(fb.color32f);
        if (fb.depth_format != refraster::DepthFormat::None) j["depth"] = bytes(fb.depth);
        return j;
    };
    nlohmann::json j;
    j["width"] = ref.width;
    j["height"] = ref.height;
    j["color_format"] = std::string(refraster::to_string(ref.color_format));
    j["depth_format"] = std::string(refraster::to_string(ref.depth_format));
    j["reference"] = side(ref);
    j["backend"] = side(act);
    // dump() escapes nothing a script could break out with: base64 and plain words only.
    return "refrasterCaseValues(" + j.dump() + ");\n";
}

void write_images(const harness::CaseResult& r, const std::filesystem::path& output) {
    const auto image = [&](const std::string& suffix) {
        const auto p = case_file(output, "images", r.name, suffix);
        std::filesystem::create_directories(p.parent_path());
        return p;
    };
    const auto save = [&](const std::optional<harness::RenderResult>& rr, const std::string& who) {
        if (!rr || rr->status != harness::RenderStatus::Ok) return;
        harness::write_color_image(
            rr->image,
            image("." + who + std::string(harness::image_extension(rr->image.color_format))));
    };
    save(r.reference, r.reference_name);
    save(r.actual, r.actual_name);
    if (r.comparison && r.comparison->mismatched_pixels > 0 && !r.comparison->size_mismatch) {
        harness::write_color_image(r.comparison->mask, image(".mask.png"));
    }
    // The explain view of an explained failure: explain/NAME.svg and NAME.txt beside images/.
    if (!r.explanation_svg.empty()) {
        // An aid, not a result: a view that cannot be written is left out (the case page
        // links it only where it exists).
        try {
            const auto svg = case_file(output, "explain", r.name, ".svg");
            const auto txt = case_file(output, "explain", r.name, ".txt");
            std::filesystem::create_directories(svg.parent_path());
            harness::write_file_atomically(svg, r.explanation_svg);
            harness::write_file_atomically(txt, r.explanation_text);
        } catch (const std::bad_alloc&) {
            throw;  // running out of memory: main reports it (exit 3)
        } catch (const std::exception&) {
        }
    }
    if (harness::counts_as_failure(r.status) && r.comparison && !r.comparison->size_mismatch &&
        r.reference && r.actual && r.reference->status == harness::RenderStatus::Ok &&
        r.actual->status == harness::RenderStatus::Ok &&
        r.reference->image.pixel_count() <= kMaxValuePixels &&
        r.reference->image.depth_format == r.actual->image.depth_format) {
        harness::write_file_atomically(case_file(output, "images", r.name, ".values.js"),
                                       values_script(r.reference->image, r.actual->image));
    }
    // A 4x target's sample mask: each pixel a 2x2 block of its samples' classes.
    if (r.sample_comparison && r.sample_comparison->mismatched_samples > 0 &&
        !r.sample_comparison->size_mismatch) {
        harness::write_color_image(r.sample_comparison->mask, image(".samples.png"));
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

void clear_run_output(const std::filesystem::path& output) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const auto present = [&](const fs::path& p) { return fs::exists(fs::symlink_status(p, ec)); };
    const fs::path jsonl = output / "results.jsonl";
    if (!present(jsonl) && !present(output / "run.json")) return;
    // Nothing is removed through a link that leads out of the output.
    check_output_folders(output);
    // Which files are the earlier run's: read everything before removing anything.
    std::vector<fs::path> owned;
    for (const char* f : {"results.csv", "failures.csv", "samples.csv", "results.json", "junit.xml",
                          "index.html", "merge.txt", "run.json", "results.jsonl"}) {
        owned.push_back(output / f);
    }
    if (present(jsonl)) {
        for (const ResultLine& l : read_result_lines(jsonl).lines) {
            const auto where = shown(jsonl) + ":" + std::to_string(l.number);
            json j;
            try {
                j = json::parse(l.text);
            } catch (const json::exception&) {
                throw std::runtime_error(where +
                                         ": not a result record, so the files of the run there "
                                         "are unknown: remove them or choose another --output");
            }
            if (!j.is_object() || !j.contains("case") || !j["case"].is_string() ||
                case_name_problem(j["case"].get<std::string>())) {
                throw std::runtime_error(where +
                                         ": no case name, so the files of the run there are "
                                         "unknown: remove them or choose another --output");
            }
            const std::string name = j["case"].get<std::string>();
            owned.push_back(output / "cases" / (name + ".html"));
            owned.push_back(output / "explain" / (name + ".svg"));
            owned.push_back(output / "explain" / (name + ".txt"));
            owned.push_back(output / "images" / (name + ".mask.png"));
            owned.push_back(output / "images" / (name + ".values.js"));
            owned.push_back(output / "images" / (name + ".samples.png"));
            for (const char* side : {"reference", "actual"}) {
                if (!j.contains(side) || !j[side].is_object() || !j[side].contains("backend") ||
                    !j[side]["backend"].is_string())
                    continue;
                const std::string backend = j[side]["backend"].get<std::string>();
                if (backend.empty() || backend.find('/') != std::string::npos) continue;
                for (const char* ext : {".png", ".exr"})
                    owned.push_back(output / "images" / (name + "." + backend + ext));
            }
        }
    }
    // The copies of the run's inputs: inputs/baseline.csv, skips-N.txt, flakes-N.txt.
    if (fs::is_directory(fs::symlink_status(output / "inputs", ec))) {
        static const std::regex copy_name(R"((baseline\.csv|(skips|flakes)-[0-9]+\.txt))");
        for (const auto& entry : fs::directory_iterator(output / "inputs", ec))
            if (std::regex_match(entry.path().filename().string(), copy_name))
                owned.push_back(entry.path());
    }
    for (const fs::path& p : owned) {
        const auto st = fs::symlink_status(p, ec);
        // A file or a link of the run's name; never a directory.
        if (fs::is_regular_file(st) || fs::is_symlink(st)) fs::remove(p, ec);
    }
    for (const char* d : {"cases", "images", "explain", "inputs"}) {
        if (fs::is_directory(fs::symlink_status(output / d, ec)) && fs::is_empty(output / d, ec))
            fs::remove(output / d, ec);
    }
}

RunSummary run_suite(const RunOptions& options, std::ostream& console) {
    if (options.shard_count < 1 || options.shard_count > kMaxShardCount ||
        options.shard_index < 0 || options.shard_index >= options.shard_count) {
        throw std::runtime_error("shard index " + std::to_string(options.shard_index) +
                                 " is not in [0, " + std::to_string(options.shard_count) + ")");
    }
    std::vector<std::string> listed;
    if (options.caselist) listed = read_caselist(*options.caselist);
    std::map<std::string, std::string> baseline;
    if (options.baseline) baseline = read_baseline(*options.baseline);
    // One set of patterns per skips file, so that each file's skipped cases are counted.
    std::vector<NamePatterns> skips(options.skips.size());
    NamePatterns flakes;
    // The run's inputs, for run.json and the report: each file as given, the copy the run
    // keeps of it under inputs/, its hash and what it holds.
    json inputs = {{"baseline", nullptr}, {"skips", json::array()}, {"flakes", json::array()}};
    if (options.baseline)
        inputs["baseline"] = {{"file", options.baseline->string()},
                              {"copy", "inputs/baseline.csv"},
                              {"fnv1a64", file_hash(*options.baseline)},
                              {"cases", baseline.size()}};
    for (std::size_t i = 0; i < options.skips.size(); ++i) {
        skips[i].add_file(options.skips[i]);
        inputs["skips"].push_back({{"file", options.skips[i].string()},
                                   {"copy", "inputs/skips-" + std::to_string(i + 1) + ".txt"},
                                   {"fnv1a64", file_hash(options.skips[i])},
                                   {"patterns", skips[i].size()},
                                   {"skipped_cases", 0}});
    }
    for (std::size_t i = 0; i < options.flakes.size(); ++i) {
        const std::size_t before = flakes.size();
        flakes.add_file(options.flakes[i]);
        inputs["flakes"].push_back({{"file", options.flakes[i].string()},
                                    {"copy", "inputs/flakes-" + std::to_string(i + 1) + ".txt"},
                                    {"fnv1a64", file_hash(options.flakes[i])},
                                    {"patterns", flakes.size() - before}});
    }

    std::vector<CaseFile> cases;
    std::size_t index = 0;
    for (auto& c : discover_cases(options.scenes_root)) {
        if (!matches_any(c.name, options.case_globs) ||
            (!options.exclude_globs.empty() && matches_any(c.name, options.exclude_globs))) {
            continue;
        }
        if (options.caselist && !matches_any(c.name, listed)) continue;
        const auto skipped_by = std::find_if(
            skips.begin(), skips.end(), [&](const auto& p) { return p.match(c.name).has_value(); });
        if (skipped_by != skips.end()) {
            auto& n = inputs["skips"][static_cast<std::size_t>(skipped_by - skips.begin())]
                            ["skipped_cases"];
            n = n.get<std::size_t>() + 1;
            continue;
        }
        if (index++ % static_cast<std::size_t>(options.shard_count) !=
            static_cast<std::size_t>(options.shard_index))
            continue;
        cases.push_back(std::move(c));
    }
    if (cases.empty()) throw std::runtime_error("no scene matched the selection");

    const auto results_path = options.output / "results.jsonl";
    auto reference = harness::make_backend(options.reference);
    auto actual = harness::make_backend(options.against);

    // The run's setup, for run.json: what a resumed run must share with it.
    json setup;
    setup["format"] = 1;
    setup["commit"] = harness::host_provenance()["commit"];
    setup["reference"] = {{"backend", reference->name()},
                          {"profile", options.reference.profile.name},
                          {"profile_rules", harness::profile_rules(options.reference.profile)},
                          {"profile_source", options.reference.profile_source},
                          {"profile_overrides", options.reference.profile_overrides}};
    setup["against"] = {{"backend", actual->name()},
                        {"environment", options.against.environment},
                        {"driver_environment", harness::worker_driver_variables(options.against)},
                        {"mesa_prefix", options.against.mesa_prefix.string()},
                        {"egl_device", options.against.egl_device.value_or(-1)}};
    setup["verdict"] = options.gl_verdict ? "gl" : "exact";
    setup["baseline"] = options.baseline ? file_hash(*options.baseline) : "";
    setup["flakes"] = json::array();
    for (const auto& f : options.flakes) setup["flakes"].push_back(file_hash(f));
    setup["shard"] = {{"index", options.shard_index}, {"count", options.shard_count}};
    setup["inputs"] = inputs;
    std::set<std::string> selected;
    json names = json::array();
    for (const auto& c : cases) {
        selected.insert(c.name);
        names.push_back(c.name);
    }
    setup["selection"] = {
        {"cases", options.case_globs}, {"exclude", options.exclude_globs}, {"names", names}};

    check_output_folders(options.output);
    std::map<std::string, json> done;
    std::map<std::string, std::string> kept_identity;
    if (options.resume) {
        // Every check before the first write: the torn line is cut only then.
        auto recovered = recover(options.output, setup, selected);
        if (recovered.torn_bytes > 0)
            std::filesystem::resize_file(results_path, recovered.size - recovered.torn_bytes);
        done = std::move(recovered.records);
        kept_identity = std::move(recovered.identity);
        console << "resume: kept " << done.size() << " finished case"
                << (done.size() == 1 ? "" : "s") << " of " << shown(results_path);
        if (recovered.torn_bytes > 0)
            console << ", cut a torn last line of " << recovered.torn_bytes << " bytes";
        console << "\n" << std::flush;
        std::filesystem::create_directories(options.output);
        if (!std::filesystem::exists(options.output / "run.json"))
            harness::write_file_atomically(output_file(options.output, "", "run.json"),
                                           dump_text(setup) + "\n");
    } else {
        clear_run_output(options.output);
        std::filesystem::create_directories(options.output);
        harness::write_file_atomically(output_file(options.output, "", "run.json"),
                                       dump_text(setup) + "\n");
        harness::write_file_atomically(output_file(options.output, "", "results.jsonl"), "");
    }
    // The copies of the inputs, as they were when the run began (a resumed run keeps the ones
    // it finds: run.json's hashes said they are the same files).
    {
        std::vector<std::pair<std::filesystem::path, std::string>> copies;
        if (options.baseline) copies.emplace_back(*options.baseline, "baseline.csv");
        for (std::size_t i = 0; i < options.skips.size(); ++i)
            copies.emplace_back(options.skips[i], "skips-" + std::to_string(i + 1) + ".txt");
        for (std::size_t i = 0; i < options.flakes.size(); ++i)
            copies.emplace_back(options.flakes[i], "flakes-" + std::to_string(i + 1) + ".txt");
        for (const auto& copy : copies) {
            const auto& from = copy.first;
            const auto to = output_file(options.output, "inputs", copy.second);
            if (options.resume && std::filesystem::exists(to)) continue;
            std::filesystem::create_directories(to.parent_path());
            harness::write_atomically(to, [&](const std::filesystem::path& partial) {
                std::filesystem::copy_file(from, partial,
                                           std::filesystem::copy_options::overwrite_existing);
            });
        }
    }
    if (!std::filesystem::exists(results_path)) harness::write_file_atomically(results_path, "");

    RunSummary s;
    const auto count = [&](harness::CaseStatus st) { s.add(st); };
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
            run_one(c, options.scene_limits, *reference, *actual, options.reference.profile,
                    options.gl_verdict, options.reference.timeout_seconds, &options.against);
        // An order-dependent failure is a Flake whatever the baseline lists.
        const bool failed = r.status != harness::CaseStatus::Flake &&
                            apply_baseline(r, options.baseline ? &baseline : nullptr);
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
                run_one(c, options.scene_limits, *reference, *actual, options.reference.profile,
                        options.gl_verdict, options.reference.timeout_seconds, nullptr);
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
        if (!kept_identity.empty() && r.reference) {
            // The kept records and this run must be one comparison down to the driver's
            // version, which only a render tells: checked before this case writes anything.
            const auto d =
                first_difference(identity_of(json::parse(harness::to_json_line(r))), kept_identity);
            if (!d.empty())
                throw std::runtime_error(shown(results_path) +
                                         ": the kept records are of another run than this one (" +
                                         harness::encode::terminal(d) +
                                         "); refusing to resume (run again without --resume)");
            kept_identity.clear();
        }
        try {
            write_images(r, options.output);
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
            // The name is a checked case name; the message may quote a path or a scene's text.
            console << reported_status(harness::to_string(r.status),
                                       r.raw_status ? harness::to_string(*r.raw_status) : "")
                    << " " << r.name;
            if (!r.message.empty()) console << ": " << harness::encode::terminal(r.message);
            if (!r.explanation_rule.empty())
                console << " [" << harness::encode::terminal(r.explanation_rule) << "]";
            console << '\n' << std::flush;
        }
    }
    if (options.progress) console << "\r\033[K";
    write_reports(options.output, cases.size());
    console << "results: " << shown(results_path)
            << "; report: " << shown(options.output / "index.html") << "\n";
    console << s.line() << "\n";
    return s;
}

void RunSummary::add(harness::CaseStatus st) {
    using harness::CaseStatus;
    if (st == CaseStatus::NotSupported) {
        ++skipped;
    } else if (harness::counts_as_failure(st)) {
        ++failed;
    } else if (st == CaseStatus::ExpectedFail) {
        ++expected;
    } else if (st == CaseStatus::Flake || st == CaseStatus::KnownFlake) {
        ++flaky;
    } else {
        ++passed;
    }
}

std::string RunSummary::line() const {
    std::string s = std::to_string(passed) + " passed, " + std::to_string(failed) + " failed, " +
                    std::to_string(skipped) + " skipped";
    if (expected > 0) s += ", " + std::to_string(expected) + " failed as the baseline expects";
    if (flaky > 0) s += ", " + std::to_string(flaky) + " flaky";
    return s;
}

}  // namespace conformance
