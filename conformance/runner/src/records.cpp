// records.cpp: case names, results.jsonl bounds, the files of a case (records.hpp) and the
// record checks (record_check.hpp).
#include "conformance/records.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "harness/case_result.hpp"
#include "harness/encode.hpp"
#include "record_check.hpp"

namespace conformance {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

bool name_char(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
}

// Shown in a message: the name itself when it is printable, escaped otherwise, and cut.
std::string shown(std::string_view text) {
    std::string t = harness::encode::terminal(text.substr(0, 80));
    if (text.size() > 80) t += "...";
    return t;
}

}  // namespace

std::optional<std::string> case_name_problem(std::string_view name) {
    if (name.empty()) return "an empty case name";
    if (name.size() > kMaxCaseNameBytes) {
        return "case name of " + std::to_string(name.size()) + " bytes, over the limit of " +
               std::to_string(kMaxCaseNameBytes) + " (docs/limits.md)";
    }
    bool component_start = true;
    for (std::size_t i = 0; i < name.size(); ++i) {
        const char c = name[i];
        if (c == '.') {
            if (component_start) {
                return "case name \"" + shown(name) + "\" has an empty component at byte " +
                       std::to_string(i) + " (names are dot-separated parts of letters, " +
                       "digits, '_' and '-')";
            }
            component_start = true;
            continue;
        }
        if (!name_char(c) || (component_start && c == '-')) {
            return "case name \"" + shown(name) + "\" has " +
                   harness::encode::terminal(std::string(1, c)) + " at byte " + std::to_string(i) +
                   " (names are dot-separated parts of letters, digits, '_' and '-', not "
                   "starting with '-')";
        }
        component_start = false;
    }
    if (component_start) return "case name \"" + shown(name) + "\" ends with a dot";
    return std::nullopt;
}

ResultLines read_result_lines(const fs::path& file) {
    const std::string where = harness::encode::terminal(file.string());
    // Non-blocking, so that a FIFO cannot stall the open; fstat before any read.
    const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(where + ": cannot read (not a conformance run's output)");
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        throw std::runtime_error(where + ": not a regular file");
    }
    const auto size = static_cast<std::uint64_t>(st.st_size);
    if (size > kMaxResultsBytes) {
        ::close(fd);
        throw std::runtime_error(where + ": " + std::to_string(size) +
                                 " bytes, over the limit of " + std::to_string(kMaxResultsBytes) +
                                 " for results (docs/limits.md)");
    }
    std::string text(static_cast<std::size_t>(size), '\0');
    std::size_t got = 0;
    while (got < text.size()) {
        const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
        if (n < 0) {
            ::close(fd);
            throw std::runtime_error(where + ": read failed");
        }
        if (n == 0) break;  // shrank while read: what was there
        got += static_cast<std::size_t>(n);
    }
    ::close(fd);
    text.resize(got);
    ResultLines out;
    out.size = got;
    std::size_t start = 0;
    std::size_t number = 0;
    while (start < text.size()) {
        const auto nl = text.find('\n', start);
        const std::size_t end = nl == std::string::npos ? text.size() : nl;
        ++number;
        if (end - start > kMaxRecordBytes) {
            throw std::runtime_error(where + ":" + std::to_string(number) + ": a line of " +
                                     std::to_string(end - start) + " bytes, over the limit of " +
                                     std::to_string(kMaxRecordBytes) + " (docs/limits.md)");
        }
        if (nl == std::string::npos) {
            out.torn_bytes = text.size() - start;
            break;
        }
        if (out.lines.size() == kMaxRecords) {
            throw std::runtime_error(where + ":" + std::to_string(number) + ": more than " +
                                     std::to_string(kMaxRecords) +
                                     " records, the limit (docs/limits.md)");
        }
        out.lines.push_back({number, text.substr(start, end - start)});
        start = nl + 1;
    }
    return out;
}

fs::path case_file(const fs::path& output, std::string_view dir, std::string_view name,
                   std::string_view suffix) {
    if (const auto problem = case_name_problem(name)) throw std::runtime_error(*problem);
    return output_file(output, dir, std::string(name) + std::string(suffix));
}

void check_output_folders(const fs::path& output) {
    std::error_code ec;
    for (const char* d : {"cases", "images", "explain"}) {
        const auto st = fs::symlink_status(output / d, ec);
        if (!ec && fs::exists(st) && !fs::is_directory(st)) {
            throw std::runtime_error(harness::encode::terminal((output / d).string()) +
                                     ": not a directory (a symbolic link?); refusing to write "
                                     "through it");
        }
    }
}

fs::path output_file(const fs::path& output, std::string_view dir, std::string_view file) {
    const auto plain = [](std::string_view n) {
        return !n.empty() && n != "." && n != ".." && n.find('/') == std::string_view::npos &&
               n.find('\0') == std::string_view::npos;
    };
    if ((!dir.empty() && !plain(dir)) || !plain(file))
        throw std::runtime_error(
            "not a file name below the output: " +
            harness::encode::terminal(std::string(dir) + "/" + std::string(file)));
    const fs::path folder = dir.empty() ? output : output / std::string(dir);
    const fs::path path = folder / file;
    const auto refuse = [&](const fs::path& p, const char* what) {
        throw std::runtime_error(harness::encode::terminal(p.string()) + ": " + what +
                                 "; refusing to write through it");
    };
    std::error_code ec;
    if (!dir.empty()) {
        const auto s = fs::symlink_status(folder, ec);
        if (!ec && fs::exists(s) && !fs::is_directory(s)) refuse(folder, "not a directory");
    }
    const auto s = fs::symlink_status(path, ec);
    if (!ec && fs::exists(s) && !fs::is_regular_file(s)) refuse(path, "not a regular file");
    // Resolved, the folder must still be the output's (or the output itself).
    if (fs::exists(folder, ec)) {
        const fs::path real_output = fs::canonical(output, ec);
        const fs::path real_folder = fs::canonical(folder, ec);
        const fs::path expected = dir.empty() ? real_output : real_output / std::string(dir);
        if (ec || real_folder != expected) refuse(folder, "outside the output directory");
    }
    return path;
}

// ---- record checks ----------------------------------------------------------------------

namespace {

struct Checker {
    std::optional<std::string> problem;

    bool fail(const std::string& path, const std::string& what) {
        if (!problem) problem = path + ": " + what;
        return false;
    }
    bool string(const json& parent, const char* key, const std::string& path, bool required) {
        if (!parent.contains(key)) return required ? fail(path + key, "missing") : true;
        return parent[key].is_string() || fail(path + key, "not a string");
    }
    bool number(const json& parent, const char* key, const std::string& path) {
        if (!parent.contains(key)) return true;
        const json& v = parent[key];
        if (!v.is_number()) return fail(path + key, "not a number");
        const double d = v.get<double>();
        return std::isfinite(d) || fail(path + key, "not finite");
    }
    // A count: a whole number from 0 up.
    bool count(const json& parent, const char* key, const std::string& path) {
        if (!parent.contains(key)) return true;
        return parent[key].is_number_unsigned() || fail(path + key, "not a count (0, 1, 2 ...)");
    }
    // An integer an int holds (pixel coordinates, channels, samples, shard numbers).
    bool integer(const json& parent, const char* key, const std::string& path, bool required) {
        if (!parent.contains(key)) return required ? fail(path + key, "missing") : true;
        const json& v = parent[key];
        if (!v.is_number_integer()) return fail(path + key, "not an integer");
        if (v.is_number_unsigned()) {
            return v.get<std::uint64_t>() <=
                       static_cast<std::uint64_t>(std::numeric_limits<int>::max()) ||
                   fail(path + key, "out of range");
        }
        const auto i = v.get<std::int64_t>();
        return (i >= std::numeric_limits<int>::min() && i <= std::numeric_limits<int>::max()) ||
               fail(path + key, "out of range");
    }
    bool boolean(const json& parent, const char* key, const std::string& path) {
        if (!parent.contains(key)) return true;
        return parent[key].is_boolean() || fail(path + key, "not true or false");
    }
    bool status(const json& parent, const char* key, const std::string& path, bool required) {
        if (!string(parent, key, path, required) || !parent.contains(key)) return !problem;
        return harness::case_status_from_string(parent[key].get<std::string>()).has_value() ||
               fail(path + key, "not a case status");
    }
    // An object, when present.
    bool object(const json& parent, const char* key, const std::string& path) {
        if (!parent.contains(key)) return false;
        return parent[key].is_object() || fail(path + key, "not an object");
    }
    void channels(const json& m, const char* key, const std::string& path) {
        if (!m.contains(key)) return;
        const json& v = m[key];
        if (!v.is_array()) {
            number(m, key, path);
            return;
        }
        // A channel is a number, or "NaN", "Infinity" or "-Infinity" (case_result.cpp).
        for (std::size_t i = 0; i < v.size(); ++i) {
            const bool non_finite =
                v[i].is_string() && (v[i] == "NaN" || v[i] == "Infinity" || v[i] == "-Infinity");
            if (!v[i].is_number() && !non_finite)
                fail(path + key + "[" + std::to_string(i) + "]",
                     "not a number (nor \"NaN\", \"Infinity\", \"-Infinity\")");
        }
    }
    void largest(const json& c, const char* key, const std::string& path) {
        if (!object(c, key, path)) return;
        const json& m = c[key];
        const std::string p = path + key + ".";
        number(m, "amount", p);
        for (const char* k : {"x", "y", "channel", "sample"}) integer(m, k, p, false);
        channels(m, "reference", p);
        channels(m, "actual", p);
        string(m, "units", p, false);
    }
    void side(const json& r, const char* key) {
        if (!object(r, key, "")) return;
        const json& s = r[key];
        const std::string p = std::string(key) + ".";
        string(s, "backend", p, true);
        string(s, "status", p, false);
        string(s, "message", p, false);
        number(s, "seconds", p);
        if (s.contains("seconds") && s["seconds"].is_number() && s["seconds"].get<double>() < 0)
            fail(p + "seconds", "negative");
        if (object(s, "provenance", p)) {
            for (const auto& [k, v] : s["provenance"].items()) {
                if (!v.is_string()) fail(p + "provenance." + k, "not a string");
            }
        }
    }
    void comparison(const json& r) {
        if (!object(r, "comparison", "")) return;
        const json& c = r["comparison"];
        const std::string p = "comparison.";
        for (const char* k : {"mismatched_pixels", "missing", "extra", "color_only", "depth_only",
                              "other_primitive", "samples", "mismatched_samples",
                              "pixels_with_mismatched_samples"}) {
            count(c, k, p);
        }
        boolean(c, "size_mismatch", p);
        boolean(c, "sample_size_mismatch", p);
        string(c, "classified_by", p, false);
        string(c, "samples_classified_by", p, false);
        largest(c, "max_color", p);
        largest(c, "max_depth", p);
        largest(c, "max_sample_color", p);
        largest(c, "max_sample_depth", p);
        if (c.contains("per_sample")) {
            const json& per = c["per_sample"];
            if (!per.is_array()) {
                fail(p + "per_sample", "not an array");
                return;
            }
            for (std::size_t i = 0; i < per.size(); ++i) {
                const std::string q = p + "per_sample[" + std::to_string(i) + "]";
                if (!per[i].is_object()) {
                    fail(q, "not an object");
                    continue;
                }
                for (const char* k : {"sample", "mismatched", "missing", "extra", "other_primitive",
                                      "color_only", "depth_only"}) {
                    count(per[i], k, q + ".");
                }
            }
        }
    }
    void explanation(const json& r) {
        if (!object(r, "explanation", "")) return;
        const json& e = r["explanation"];
        for (const char* k : {"difference", "rule", "verdict"}) string(e, k, "explanation.", false);
        if (!e.contains("pixel") || !e["pixel"].is_array() || e["pixel"].size() != 2) {
            fail("explanation.pixel", "not two integers");
            return;
        }
        for (std::size_t i = 0; i < 2; ++i) {
            const json& v = e["pixel"][i];
            const bool ok = v.is_number_integer() &&
                            (v.is_number_unsigned() ? v.get<std::uint64_t>() <= 1u << 30
                                                    : v.get<std::int64_t>() >= -(1 << 30) &&
                                                          v.get<std::int64_t>() <= 1 << 30);
            if (!ok) fail("explanation.pixel[" + std::to_string(i) + "]", "not a pixel coordinate");
        }
    }
};

}  // namespace

std::optional<std::string> record_problem(const json& r) {
    if (!r.is_object()) return std::string("(the line): not a JSON object");
    Checker k;
    if (k.string(r, "case", "", true)) {
        if (const auto bad = case_name_problem(r["case"].get<std::string>())) k.fail("case", *bad);
    }
    k.status(r, "status", "", true);
    k.status(r, "raw_status", "", false);
    k.string(r, "scene", "", false);
    k.string(r, "message", "", false);
    k.string(r, "gl_verdict", "", false);
    if (k.object(r, "shard", "")) {
        k.integer(r["shard"], "index", "shard.", true);
        k.integer(r["shard"], "count", "shard.", true);
        k.string(r["shard"], "source", "shard.", false);
    }
    if (k.object(r, "expect", "")) {
        k.number(r["expect"], "color_tolerance", "expect.");
        k.number(r["expect"], "max_mismatched_pixels", "expect.");
    }
    if (k.object(r, "alone", "")) {
        k.status(r["alone"], "status", "alone.", true);
        k.count(r["alone"], "mismatched_pixels", "alone.");
    }
    k.side(r, "reference");
    k.side(r, "actual");
    k.comparison(r);
    k.explanation(r);
    return k.problem;
}

std::map<std::string, std::string> identity_of(const json& r) {
    std::map<std::string, std::string> id;
    for (const char* side : {"reference", "actual"}) {
        if (!r.contains(side) || !r[side].is_object()) continue;
        const json& s = r[side];
        if (s.contains("backend")) id[std::string(side) + " backend"] = dump_text(s["backend"]);
        if (!s.contains("provenance") || !s["provenance"].is_object()) continue;
        for (const char* k : {"commit", "profile", "profile_rules", "renderer", "driver",
                              "mesa_version", "gl_version", "fma"}) {
            if (s["provenance"].contains(k))
                id[std::string(side) + " " + k] = dump_text(s["provenance"][k]);
        }
    }
    return id;
}

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

std::string dump_text(const json& value, int indent) {
    return value.dump(indent, ' ', false, json::error_handler_t::replace);
}

}  // namespace conformance
