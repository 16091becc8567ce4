#include "conformance/merge.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "conformance/reports.hpp"
#include "harness/files.hpp"

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

// What must be equal for records to be one run: per side, the backend and the provenance
// that decides pixels (not the host's CPU flags or timings).
std::map<std::string, std::string> identity_of(const json& r) {
    std::map<std::string, std::string> id;
    for (const char* side : {"reference", "actual"}) {
        if (!r.contains(side)) continue;
        const json& s = r[side];
        if (s.contains("backend")) id[std::string(side) + " backend"] = s["backend"].dump();
        if (!s.contains("provenance")) continue;
        for (const char* k : {"commit", "profile", "profile_rules", "renderer", "driver",
                              "mesa_version", "gl_version", "fma"}) {
            if (s["provenance"].contains(k))
                id[std::string(side) + " " + k] = s["provenance"][k].dump();
        }
    }
    return id;
}

ShardInput read_shard(const fs::path& dir) {
    ShardInput in;
    in.dir = dir;
    const fs::path file = dir / "results.jsonl";
    std::ifstream f(file, std::ios::binary);
    if (!f) throw MergeError(file.string() + ": cannot read (not a conformance run's output)");
    std::string line;
    std::size_t n = 0;
    bool first = true;
    std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (!text.empty() && text.back() != '\n')
        throw MergeError(file.string() +
                         ": the last record is torn (a killed run: finish it with --resume)");
    std::size_t pos = 0;
    while (pos < text.size()) {
        const std::size_t end = text.find('\n', pos);
        line = text.substr(pos, end - pos);
        pos = end + 1;
        ++n;
        if (line.empty()) continue;
        json r;
        try {
            r = json::parse(line);
        } catch (const json::exception&) {
            throw MergeError(file.string() + ":" + std::to_string(n) + ": not a JSON record");
        }
        if (!r.contains("case") || !r["case"].is_string())
            throw MergeError(file.string() + ":" + std::to_string(n) + ": a record without a case");
        if (!r.contains("shard") || !r["shard"].contains("index") || !r["shard"].contains("count"))
            throw MergeError(file.string() + ":" + std::to_string(n) +
                             ": the record names no shard (written before shards were recorded: "
                             "run the shard again)");
        const int index = r["shard"]["index"].get<int>();
        const int count = r["shard"]["count"].get<int>();
        if (first) {
            in.index = index;
            in.count = count;
            in.identity = identity_of(r);
            first = false;
        } else if (index != in.index || count != in.count) {
            throw MergeError(file.string() + ":" + std::to_string(n) + ": shard " +
                             std::to_string(index) + " of " + std::to_string(count) +
                             " among records of shard " + std::to_string(in.index) + " of " +
                             std::to_string(in.count));
        } else if (identity_of(r) != in.identity) {
            throw MergeError(file.string() + ":" + std::to_string(n) +
                             ": a record of another run (commit, profile or driver) than the "
                             "file's first");
        }
        in.records.emplace_back(r["case"].get<std::string>(), line);
    }
    if (in.records.empty()) throw MergeError(file.string() + ": no results");
    return in;
}

// The first key whose values differ, as "actual renderer \"a\" here, \"b\" in DIR".
std::string first_difference(const std::map<std::string, std::string>& a,
                             const std::map<std::string, std::string>& b) {
    std::set<std::string> keys;
    for (const auto& [k, v] : a) keys.insert(k);
    for (const auto& [k, v] : b) keys.insert(k);
    for (const auto& k : keys) {
        const auto ia = a.find(k), ib = b.find(k);
        const std::string va = ia == a.end() ? "(none)" : ia->second;
        const std::string vb = ib == b.end() ? "(none)" : ib->second;
        if (va != vb) return k + " " + va + " against " + vb;
    }
    return "";
}

void copy_tree(const fs::path& from, const fs::path& to) {
    if (!fs::is_directory(from)) return;
    fs::create_directories(to);
    for (const auto& e : fs::directory_iterator(from)) {
        if (e.is_regular_file())
            fs::copy_file(e.path(), to / e.path().filename(), fs::copy_options::overwrite_existing);
    }
}

}  // namespace

MergeSummary merge_shards(const std::vector<fs::path>& shards, const fs::path& output,
                          std::ostream& console) {
    if (shards.empty()) throw MergeError("no shard directories given");
    std::error_code ec;
    for (const auto& s : shards) {
        if (fs::exists(output, ec) && fs::equivalent(s, output, ec))
            throw MergeError(output.string() + ": the output is one of the shards");
    }
    std::vector<ShardInput> in;
    for (const auto& s : shards) in.push_back(read_shard(s));
    std::map<int, const ShardInput*> by_index;
    std::map<std::string, const ShardInput*> by_case;
    for (const ShardInput& s : in) {
        const ShardInput& first = in.front();
        if (s.count != first.count)
            throw MergeError(s.dir.string() + ": shard " + std::to_string(s.index) + " of " +
                             std::to_string(s.count) + ", but " + first.dir.string() + " is of " +
                             std::to_string(first.count));
        if (s.identity != first.identity)
            throw MergeError(s.dir.string() + ": another run than " + first.dir.string() + ": " +
                             first_difference(s.identity, first.identity));
        if (const auto [it, fresh] = by_index.emplace(s.index, &s); !fresh)
            throw MergeError(s.dir.string() + " and " + it->second->dir.string() +
                             " are both shard " + std::to_string(s.index) + " of " +
                             std::to_string(s.count));
        for (const auto& rec : s.records) {
            if (const auto [it, fresh] = by_case.emplace(rec.first, &s); !fresh)
                throw MergeError("case " + rec.first + " is in " + s.dir.string() + " and in " +
                                 it->second->dir.string());
        }
    }
    MergeSummary summary;
    summary.shard_count = in.front().count;
    summary.cases = by_case.size();
    for (int i = 0; i < summary.shard_count; ++i)
        if (by_index.count(i) == 0) summary.missing_shards.push_back(i);

    // Everything checked: write. The records in case order, each line as its shard wrote it.
    fs::create_directories(output);
    std::vector<std::pair<std::string, std::string>> all;
    for (const ShardInput& s : in) all.insert(all.end(), s.records.begin(), s.records.end());
    std::sort(all.begin(), all.end());
    std::string lines;
    for (const auto& [name, line] : all) lines += line + "\n";
    harness::write_file_atomically(output / "results.jsonl", lines);
    for (const ShardInput& s : in) {
        copy_tree(s.dir / "images", output / "images");
        copy_tree(s.dir / "explain", output / "explain");
    }
    write_reports(output, summary.cases);
    std::string note = "merged " + std::to_string(in.size()) + " of " +
                       std::to_string(summary.shard_count) + " shards, " +
                       std::to_string(summary.cases) + " cases, from:\n";
    for (const ShardInput& s : in)
        note += "  shard " + std::to_string(s.index) + ": " + s.dir.string() + "\n";
    for (int i : summary.missing_shards)
        note += "missing: shard " + std::to_string(i) + " of " +
                std::to_string(summary.shard_count) + " (its cases are not in this report)\n";
    harness::write_file_atomically(output / "merge.txt", note);
    console << note;
    return summary;
}

}  // namespace conformance
