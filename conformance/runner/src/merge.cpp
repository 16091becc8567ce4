#include "conformance/merge.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>

#include "conformance/records.hpp"
#include "conformance/reports.hpp"
#include "conformance/shard.hpp"
#include "conformance/suite.hpp"
#include "harness/encode.hpp"
#include "harness/files.hpp"
#include "record_check.hpp"

namespace conformance {

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

struct ShardInput {
    fs::path dir;
    int index = 0;
    int count = 1;
    std::vector<std::pair<std::string, std::string>> records;  // case, the line as written
    std::map<std::string, std::string> identity;
};

std::string shown(const fs::path& p) {
    return harness::encode::terminal(p.string());
}

ShardInput read_shard(const fs::path& dir) {
    ShardInput in;
    in.dir = dir;
    const fs::path file = dir / "results.jsonl";
    const std::string where = shown(file);
    ResultLines lines;
    try {
        lines = read_result_lines(file);
    } catch (const std::runtime_error& e) {
        throw MergeError(e.what());
    }
    if (lines.torn_bytes > 0)
        throw MergeError(where +
                         ": the last record is torn (a killed run: finish it with --resume)");
    bool first = true;
    for (const ResultLine& l : lines.lines) {
        const std::string at = where + ":" + std::to_string(l.number);
        if (l.text.empty()) continue;
        json r;
        try {
            r = json::parse(l.text);
        } catch (const json::exception&) {
            throw MergeError(at + ": not a JSON record");
        }
        if (const auto problem = record_problem(r)) throw MergeError(at + ": " + *problem);
        if (!r.contains("shard"))
            throw MergeError(at +
                             ": the record names no shard (written before shards were recorded: "
                             "run the shard again)");
        const int index = r["shard"]["index"].get<int>();
        const int count = r["shard"]["count"].get<int>();
        if (count < 1 || count > kMaxShardCount)
            throw MergeError(at + ": shard.count: " + std::to_string(count) + " is not in [1, " +
                             std::to_string(kMaxShardCount) + "] (docs/limits.md)");
        if (index < 0 || index >= count)
            throw MergeError(at + ": shard.index: " + std::to_string(index) + " is not in [0, " +
                             std::to_string(count) + ")");
        if (first) {
            in.index = index;
            in.count = count;
            first = false;
        } else if (index != in.index || count != in.count) {
            throw MergeError(at + ": shard " + std::to_string(index) + " of " +
                             std::to_string(count) + " among records of shard " +
                             std::to_string(in.index) + " of " + std::to_string(in.count));
        }
        // A case whose scene did not load rendered nothing and names no backend: it belongs to
        // any run.
        const auto id = identity_of(r);
        if (in.identity.empty()) {
            in.identity = id;
        } else if (const auto d = first_difference(id, in.identity); !id.empty() && !d.empty()) {
            throw MergeError(at + ": a record of another run than the file's first (" +
                             harness::encode::terminal(d) + ")");
        }
        in.records.emplace_back(r["case"].get<std::string>(), l.text);
    }
    if (in.records.empty()) throw MergeError(where + ": no results");
    return in;
}

// The files of `sub` (images/, explain/) a shard holds for its own cases: regular files named
// CASE.SOMETHING for a case of that shard. Anything else there was not written by the run and
// is not carried over.
std::vector<fs::path> case_files(const ShardInput& s, const char* sub) {
    std::vector<fs::path> out;
    const fs::path from = s.dir / sub;
    std::error_code ec;
    if (!fs::is_directory(fs::symlink_status(from, ec))) return out;
    std::set<std::string> names;
    for (const auto& [name, line] : s.records) names.insert(name);
    for (const auto& e : fs::directory_iterator(from)) {
        if (!fs::is_regular_file(e.symlink_status())) continue;
        const std::string file = e.path().filename().string();
        for (auto dot = file.find('.'); dot != std::string::npos; dot = file.find('.', dot + 1)) {
            if (names.count(file.substr(0, dot)) != 0) {
                out.push_back(e.path());
                break;
            }
        }
    }
    return out;
}

}  // namespace

MergeSummary merge_shards(const std::vector<fs::path>& shards, const fs::path& output,
                          std::ostream& console) {
    if (shards.empty()) throw MergeError("no shard directories given");
    std::error_code ec;
    for (const auto& s : shards) {
        if (fs::exists(output, ec) && fs::equivalent(s, output, ec))
            throw MergeError(shown(output) + ": the output is one of the shards");
    }
    std::vector<ShardInput> in;
    for (const auto& s : shards) in.push_back(read_shard(s));
    std::map<int, const ShardInput*> by_index;
    std::map<std::string, const ShardInput*> by_case;
    for (const ShardInput& s : in) {
        const ShardInput& first = in.front();
        if (s.count != first.count)
            throw MergeError(shown(s.dir) + ": shard " + std::to_string(s.index) + " of " +
                             std::to_string(s.count) + ", but " + shown(first.dir) + " is of " +
                             std::to_string(first.count));
        if (!s.identity.empty() && !first.identity.empty() && s.identity != first.identity)
            throw MergeError(
                shown(s.dir) + ": another run than " + shown(first.dir) + ": " +
                harness::encode::terminal(first_difference(s.identity, first.identity)));
        if (const auto [it, fresh] = by_index.emplace(s.index, &s); !fresh)
            throw MergeError(shown(s.dir) + " and " + shown(it->second->dir) + " are both shard " +
                             std::to_string(s.index) + " of " + std::to_string(s.count));
        for (const auto& rec : s.records) {
            if (const auto [it, fresh] = by_case.emplace(rec.first, &s); !fresh)
                throw MergeError("case " + rec.first + " is in " + shown(s.dir) + " and in " +
                                 shown(it->second->dir));
        }
    }
    MergeSummary summary;
    summary.shard_count = in.front().count;
    summary.cases = by_case.size();
    for (int i = 0; i < summary.shard_count; ++i)
        if (by_index.count(i) == 0) summary.missing_shards.push_back(i);

    // The records in case order, each line as its shard wrote it; the files each carries over.
    std::vector<std::pair<std::string, std::string>> all;
    for (const ShardInput& s : in) all.insert(all.end(), s.records.begin(), s.records.end());
    std::sort(all.begin(), all.end());
    std::string text;
    std::vector<std::string> lines;
    for (const auto& [name, line] : all) {
        text += line + "\n";
        lines.push_back(line);
        // Every record was read and checked with its shard (read_shard), status included.
        const auto status = harness::case_status_from_string(
            nlohmann::json::parse(line).value("status", std::string()));
        summary.counts.add(status.value_or(harness::CaseStatus::InternalError));
    }
    std::vector<std::pair<fs::path, fs::path>> copies;  // from, to
    std::set<std::string> carried;                      // "images/NAME.ref.png"
    for (const ShardInput& s : in) {
        for (const char* sub : {"images", "explain"}) {
            for (const fs::path& f : case_files(s, sub)) {
                const std::string file = f.filename().string();
                carried.insert(std::string(sub) + "/" + file);
                copies.emplace_back(f, output_file(output, sub, file));
            }
        }
    }
    // The run's inputs (baseline, skips, flakes) as the first shard recorded them: the shards
    // of one run share them (their identity includes the files' hashes).
    std::string setup;
    const fs::path setup_file = in.front().dir / "run.json";
    if (fs::is_regular_file(fs::symlink_status(setup_file, ec))) {
        for (auto& l : read_result_lines(setup_file).lines) setup += l.text + "\n";
        if (fs::is_directory(fs::symlink_status(in.front().dir / "inputs", ec))) {
            static const std::regex copy_name(R"((baseline\.csv|(skips|flakes)-[0-9]+\.txt))");
            for (const auto& entry : fs::directory_iterator(in.front().dir / "inputs", ec)) {
                const std::string file = entry.path().filename().string();
                if (!std::regex_match(file, copy_name) ||
                    !fs::is_regular_file(fs::symlink_status(entry.path(), ec)))
                    continue;
                carried.insert("inputs/" + file);
                copies.emplace_back(entry.path(), output_file(output, "inputs", file));
            }
        }
    }
    try {
        check_output_folders(output);
    } catch (const std::runtime_error& e) {
        throw MergeError(e.what());
    }
    // Every report built before anything is written: a record the reports cannot read stops
    // the merge here.
    std::vector<ReportFile> reports;
    try {
        reports = build_reports(
            lines, "merged records", summary.cases,
            [&](const std::string& relative) { return carried.count(relative) != 0; }, setup,
            shown(setup_file));
    } catch (const std::runtime_error& e) {
        throw MergeError(e.what());
    }
    std::string note = "merged " + std::to_string(in.size()) + " of " +
                       std::to_string(summary.shard_count) + " shards, " +
                       std::to_string(summary.cases) + " cases, from:\n";
    for (const ShardInput& s : in)
        note += "  shard " + std::to_string(s.index) + ": " + shown(s.dir) + "\n";
    for (int i : summary.missing_shards)
        note += "missing: shard " + std::to_string(i) + " of " +
                std::to_string(summary.shard_count) + " (its cases are not in this report)\n";

    // Everything checked: clear what an earlier run or merge left there, then write.
    clear_run_output(output);
    fs::create_directories(output);
    harness::write_file_atomically(output_file(output, "", "results.jsonl"), text);
    for (const auto& copy : copies) {
        const fs::path& from = copy.first;
        fs::create_directories(copy.second.parent_path());
        harness::write_atomically(copy.second, [&](const fs::path& partial) {
            fs::copy_file(from, partial, fs::copy_options::overwrite_existing);
        });
    }
    write_report_files(output, reports);
    harness::write_file_atomically(output_file(output, "", "merge.txt"), note);
    console << note;
    return summary;
}

}  // namespace conformance
