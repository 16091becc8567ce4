#include "conformance/reports.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/case_result.hpp"
#include "harness/files.hpp"

namespace conformance {

namespace {

using json = nlohmann::json;
using ojson = nlohmann::ordered_json;

std::string esc(const std::string& s) {
    std::string o;
    for (char c : s) {
        switch (c) {
            case '&':
                o += "&amp;";
                break;
            case '<':
                o += "&lt;";
                break;
            case '>':
                o += "&gt;";
                break;
            case '"':
                o += "&quot;";
                break;
            case '\'':
                o += "&#39;";
                break;
            default:
                o += c;
        }
    }
    return o;
}

std::string fixed(double v, int digits) {
    std::ostringstream o;
    o.setf(std::ios::fixed);
    o.precision(digits);
    o << v;
    return o.str();
}

// A report is either whole or absent.
void write_file(const std::filesystem::path& p, const std::string& text) {
    harness::write_file_atomically(p, text);
}

double seconds(const json& r, const char* who) {
    return r.contains(who) ? r[who].value("seconds", 0.0) : 0.0;
}

std::uint64_t mismatched(const json& r) {
    return r.contains("comparison") ? r["comparison"].value("mismatched_pixels", std::uint64_t{0})
                                    : 0;
}

// A 4x case's record holds per-sample fields in its comparison; a single-sample one does not.
bool has_samples(const json& r) {
    return r.contains("comparison") && r["comparison"].contains("mismatched_samples");
}

std::uint64_t mismatched_samples(const json& r) {
    return has_samples(r) ? r["comparison"].value("mismatched_samples", std::uint64_t{0}) : 0;
}

// "3 at (1, 2) sample 0" for a largest difference that names its pixel (and sample).
std::string difference_at(const json& m) {
    std::string t = std::to_string(m.value("amount", std::uint64_t{0})) + " at (" +
                    std::to_string(m.value("x", 0)) + ", " + std::to_string(m.value("y", 0)) + ")";
    if (m.contains("sample")) t += " sample " + std::to_string(m.value("sample", 0));
    return t;
}

// One line of a 4x case's sample numbers: "5 of 64 samples mismatched (by sample 0: 1, ...)".
std::string samples_line(const json& r) {
    const auto& c = r["comparison"];
    std::string t = std::to_string(mismatched_samples(r)) + " mismatched samples in " +
                    std::to_string(c.value("pixels_with_mismatched_samples", std::uint64_t{0})) +
                    " pixels";
    if (c.contains("per_sample") && c["per_sample"].is_array()) {
        std::string by;
        for (const auto& p : c["per_sample"]) {
            by += (by.empty() ? "" : ", ") + std::to_string(p.value("sample", 0)) + ": " +
                  std::to_string(p.value("mismatched", std::uint64_t{0}));
        }
        t += " (by sample " + by + ")";
    }
    if (c.contains("max_sample_color")) {
        t += "; max sample colour error " + difference_at(c["max_sample_color"]);
    }
    if (c.contains("max_sample_depth")) {
        t += "; max sample depth error " + difference_at(c["max_sample_depth"]);
    }
    return t;
}

std::string area_of(const std::string& name) {
    const auto a = name.find('.');
    if (a == std::string::npos) return name;
    const auto b = name.find('.', a + 1);
    return b == std::string::npos ? name.substr(0, a) : name.substr(0, b);
}

// deqp-runner's word for a status (its RunnerStatus): NotSupported is Skip, and an internal
// error of the harness, which deqp-runner has no word for, is a Fail.
std::string deqp_status(const std::string& status) {
    if (status == "NotSupported") return "Skip";
    if (status == "InternalError") return "Fail";
    return status;
}

// The command that explains a case's pixel exactly as the run compared it: the same backend
// and driver, and the same profile (its file and overrides).
std::string explain_command(const json& r, int x, int y) {
    const auto quote = [](const std::string& s) {
        if (!s.empty() &&
            s.find_first_not_of(
                "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.,/=+:") ==
                std::string::npos) {
            return s;
        }
        std::string q = "'";
        for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
        return q + "'";
    };
    std::string cmd = "refraster explain " + quote(r.value("scene", "")) + " --pixel " +
                      std::to_string(x) + "," + std::to_string(y);
    const json none = json::object();
    const json& act = r.contains("actual") && r["actual"].contains("provenance")
                          ? r["actual"]["provenance"]
                          : none;
    const json& ref = r.contains("reference") && r["reference"].contains("provenance")
                          ? r["reference"]["provenance"]
                          : none;
    if (act.contains("backend")) cmd += " --against " + quote(act.value("backend", ""));
    if (act.contains("driver")) cmd += " --driver " + quote(act.value("driver", ""));
    const std::string source = ref.value("profile_source", "built-in");
    if (source != "built-in") {
        cmd += " --profile " + quote(source);
    } else if (ref.contains("profile")) {
        const std::string name = ref.value("profile", "");
        cmd += " --profile " + quote(name.substr(0, name.find('+')));
    }
    std::stringstream overrides(ref.value("profile_overrides", ""));
    for (std::string o; std::getline(overrides, o, ';');) {
        if (!o.empty()) cmd += " --profile-set " + quote(o);
    }
    return cmd;
}

bool failed(const std::string& status) {
    const auto st = harness::case_status_from_string(status);
    return !st || harness::counts_as_failure(*st);
}

const char* status_color(const std::string& s) {
    if (s == "Pass") return "#2e7d32";
    if (s == "ExpectedFail" || s == "Flake") return "#8d6e63";
    if (s == "NotSupported") return "#757575";
    return "#c62828";
}

const char* kStyle = R"(<style>
body{font-family:system-ui,sans-serif;margin:1.5em;color:#222}
table{border-collapse:collapse;font-size:14px}td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}
th{background:#f3f3f3}.num{text-align:right;font-variant-numeric:tabular-nums}
.st{font-weight:600}.imgs{display:flex;gap:16px;flex-wrap:wrap}.imgs figure{margin:0}
.imgs img{image-rendering:pixelated;image-rendering:crisp-edges;border:1px solid #999;background:#444}
code{background:#f3f3f3;padding:1px 4px}
</style>)";

// The chart: every case as a dot, run time (reference + backend) on a log x axis, mismatched
// pixels on a log(1 + n) y axis, coloured by status.
std::string chart(const std::vector<json>& results) {
    const double W = 640, H = 260, L = 60, B = 40, T = 10, R = 10;
    double tmin = 1e9, tmax = 0, emax = 0;
    for (const auto& r : results) {
        const double t = std::max(1e-6, seconds(r, "reference") + seconds(r, "actual"));
        tmin = std::min(tmin, t);
        tmax = std::max(tmax, t);
        emax = std::max(emax, std::log10(1.0 + static_cast<double>(mismatched(r))));
    }
    if (tmax <= tmin) tmax = tmin * 10;
    if (emax <= 0) emax = 1;
    const double lx0 = std::floor(std::log10(tmin)), lx1 = std::ceil(std::log10(tmax));
    std::ostringstream s;
    s << "<svg id=\"error-chart\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W
      << "\" height=\"" << H
      << "\" role=\"img\" aria-label=\"mismatched pixels against run time\">";
    s << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << W - L - R << "\" height=\""
      << H - T - B << "\" fill=\"#fafafa\" stroke=\"#999\"/>";
    for (double lx = lx0; lx <= lx1; lx += 1) {
        const double x = L + (lx - lx0) / std::max(1.0, lx1 - lx0) * (W - L - R);
        s << "<line x1=\"" << x << "\" y1=\"" << H - B << "\" x2=\"" << x << "\" y2=\"" << H - B + 4
          << "\" stroke=\"#999\"/><text x=\"" << x << "\" y=\"" << H - B + 16
          << "\" font-size=\"10\" text-anchor=\"middle\">1e" << static_cast<int>(lx) << " s</text>";
    }
    s << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 4
      << "\" font-size=\"11\" text-anchor=\"middle\">reference + backend render time</text>";
    s << "<text x=\"12\" y=\"" << (T + H - B) / 2
      << "\" font-size=\"11\" transform=\"rotate(-90 12 " << (T + H - B) / 2
      << ")\" text-anchor=\"middle\">mismatched pixels (log)</text>";
    for (int k = 0; k <= static_cast<int>(std::ceil(emax)); ++k) {
        const double y = H - B - k / std::ceil(emax) * (H - T - B);
        s << "<text x=\"" << L - 4 << "\" y=\"" << y + 3
          << "\" font-size=\"10\" text-anchor=\"end\">" << (k == 0 ? "0" : "1e" + std::to_string(k))
          << "</text>";
    }
    for (const auto& r : results) {
        const double t = std::max(1e-6, seconds(r, "reference") + seconds(r, "actual"));
        const double x = L + (std::log10(t) - lx0) / std::max(1.0, lx1 - lx0) * (W - L - R);
        const double e = std::log10(1.0 + static_cast<double>(mismatched(r)));
        const double y = H - B - e / std::ceil(emax) * (H - T - B);
        const std::string st = r.value("status", "");
        s << "<circle cx=\"" << fixed(x, 1) << "\" cy=\"" << fixed(y, 1) << "\" r=\"3\" fill=\""
          << status_color(st) << "\" fill-opacity=\"0.7\"><title>" << esc(r.value("case", ""))
          << ": " << esc(st) << ", " << mismatched(r) << " px, " << fixed(t * 1000, 2)
          << " ms</title></circle>";
    }
    s << "</svg>";
    return s.str();
}

std::string case_page(const json& r, const std::filesystem::path& images) {
    const std::string name = r.value("case", "");
    const std::string st = r.value("status", "");
    std::ostringstream h;
    h << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>" << esc(name) << "</title>"
      << kStyle
      << "</head><body><p><a href=\"../index.html\">&larr; all cases</a></p><h1 id=\"case-name\">"
      << esc(name)
      << "</h1><p>Status: <span id=\"case-status\" class=\"st\" style=\"color:" << status_color(st)
      << "\">" << esc(st) << "</span>";
    if (r.contains("raw_status"))
        h << " (result " << esc(r["raw_status"].get<std::string>()) << ")";
    h << "</p><p>Scene: <code>" << esc(r.value("scene", "")) << "</code></p>";
    if (r.contains("message"))
        h << "<p id=\"case-message\">" << esc(r["message"].get<std::string>()) << "</p>";

    // Images, side by side, pixelated and zoomable.
    h << "<p><label>Zoom <input id=\"zoom\" type=\"range\" min=\"1\" max=\"32\" "
         "value=\"8\"></label> "
         "<span id=\"zoom-value\">8</span>x</p><div class=\"imgs\">";
    const auto figure = [&](const std::string& file, const std::string& caption) {
        if (!std::filesystem::exists(images / file)) return;
        h << "<figure><img class=\"zoomable\" src=\"../images/" << esc(file) << "\" alt=\""
          << esc(caption) << "\"><figcaption>" << esc(caption) << "</figcaption></figure>";
    };
    const std::string ref =
        r.contains("reference") ? r["reference"].value("backend", "ref") : "ref";
    const std::string act = r.contains("actual") ? r["actual"].value("backend", "") : "";
    for (const char* ext : {".png", ".exr"}) {
        figure(name + "." + ref + ext, "reference (" + ref + ")");
        figure(name + "." + act + ext, act);
    }
    figure(name + ".mask.png",
           "error mask: magenta missing, red extra, orange another primitive, yellow colour only, "
           "blue depth only");
    // A 4x case's sample mask is 2W x 2H: shown at the size of the others, a sample a quarter
    // of a pixel.
    if (std::filesystem::exists(images / (name + ".samples.png"))) {
        const std::string caption =
            "sample mask: each pixel's four samples in their places (top: 2 3, bottom: 0 1), "
            "coloured as the error mask";
        h << "<figure id=\"sample-mask\"><img class=\"zoomable\" data-scale=\"0.5\" "
             "src=\"../images/"
          << esc(name + ".samples.png") << "\" alt=\"" << esc(caption) << "\"><figcaption>"
          << esc(caption) << "</figcaption></figure>";
    }
    h << "</div>";

    if (r.contains("comparison")) {
        const auto& c = r["comparison"];
        h << "<h2>Numbers</h2><table id=\"case-numbers\">";
        for (const char* k : {"mismatched_pixels", "missing", "extra", "other_primitive",
                              "color_only", "depth_only"}) {
            h << "<tr><th>" << k << "</th><td class=\"num\">" << c.value(k, 0) << "</td></tr>";
        }
        if (c.contains("max_color")) {
            const auto& m = c["max_color"];
            h << "<tr><th>max colour error</th><td class=\"num\">" << m.value("amount", 0)
              << " at (" << m.value("x", 0) << ", " << m.value("y", 0) << ") channel "
              << "RGBA"[m.value("channel", 0) & 3] << ": " << esc(m["reference"].dump()) << " vs "
              << esc(m["actual"].dump()) << "</td></tr>";
        }
        if (c.contains("max_depth")) {
            const auto& m = c["max_depth"];
            h << "<tr><th>max depth error</th><td class=\"num\">" << m.value("amount", 0) << " at ("
              << m.value("x", 0) << ", " << m.value("y", 0) << "): " << m.value("reference", 0)
              << " vs " << m.value("actual", 0) << "</td></tr>";
        }
        h << "<tr><th>reference time</th><td class=\"num\">"
          << fixed(seconds(r, "reference") * 1000, 3)
          << " ms</td></tr><tr><th>backend time</th><td class=\"num\">"
          << fixed(seconds(r, "actual") * 1000, 3) << " ms</td></tr>";
        if (has_samples(r)) {
            h << "</table><h3>Samples</h3><table id=\"sample-numbers\">";
            for (const char* k :
                 {"samples", "mismatched_samples", "pixels_with_mismatched_samples"}) {
                h << "<tr><th>" << k << "</th><td class=\"num\">" << c.value(k, 0) << "</td></tr>";
            }
            if (c.contains("per_sample") && c["per_sample"].is_array()) {
                h << "<tr><th>by sample</th><td><table id=\"per-sample\"><tr><th>sample</th>";
                const char* keys[] = {"mismatched",      "missing",    "extra",
                                      "other_primitive", "color_only", "depth_only"};
                for (const char* k : keys) h << "<th>" << k << "</th>";
                h << "</tr>";
                for (const auto& p : c["per_sample"]) {
                    h << "<tr><td class=\"num\">" << p.value("sample", 0) << "</td>";
                    for (const char* k : keys) {
                        h << "<td class=\"num\">" << p.value(k, 0) << "</td>";
                    }
                    h << "</tr>";
                }
                h << "</table></td></tr>";
            }
            if (c.contains("max_sample_color")) {
                const auto& m = c["max_sample_color"];
                h << "<tr><th>max sample colour error</th><td class=\"num\">" << difference_at(m)
                  << " channel "
                  << "RGBA"[m.value("channel", 0) & 3] << ": " << esc(m["reference"].dump())
                  << " vs " << esc(m["actual"].dump()) << "</td></tr>";
            }
            if (c.contains("max_sample_depth")) {
                const auto& m = c["max_sample_depth"];
                h << "<tr><th>max sample depth error</th><td class=\"num\">" << difference_at(m)
                  << ": " << m.value("reference", 0) << " vs " << m.value("actual", 0)
                  << "</td></tr>";
            }
            h << "<tr><th>samples classified by</th><td>"
              << esc(c.value("samples_classified_by", "")) << "</td></tr>";
        }
        h << "</table>";
        h << "<h2>Explanation</h2><p id=\"case-explanation\">";
        if (c.value("mismatched_pixels", 0) == 0 && mismatched_samples(r) == 0) {
            h << (has_samples(r) ? "Every pixel and every sample agrees." : "Every pixel agrees.");
        } else if (r.contains("explanation")) {
            const auto& e = r["explanation"];
            h << "<b>" << esc(e.value("difference", "")) << ", " << esc(e.value("rule", ""))
              << "</b>: " << esc(e.value("verdict", ""))
              << ". Every decision at that pixel: <code id=\"explain-command\">"
              << esc(explain_command(r, e["pixel"][0].get<int>(), e["pixel"][1].get<int>()))
              << "</code>.";
        } else if (c.contains("max_color")) {
            const auto& m = c["max_color"];
            h << "The largest difference is at pixel (" << m.value("x", 0) << ", "
              << m.value("y", 0)
              << "). Trace every decision there with <code id=\"explain-command\">"
              << esc(explain_command(r, m.value("x", 0), m.value("y", 0))) << "</code>.";
        } else if (c.contains("max_sample_color") || c.contains("max_sample_depth")) {
            const auto& m =
                c.contains("max_sample_color") ? c["max_sample_color"] : c["max_sample_depth"];
            h << "The resolved pixels agree; the largest sample difference is at pixel ("
              << m.value("x", 0) << ", " << m.value("y", 0) << "), sample " << m.value("sample", 0)
              << ". Trace every decision there with <code id=\"explain-command\">"
              << esc(explain_command(r, m.value("x", 0), m.value("y", 0))) << "</code>.";
        }
        h << "</p>";
    }
    const auto provenance = [&](const char* who, const char* title) {
        if (!r.contains(who) || !r[who].contains("provenance")) return;
        h << "<h2>" << title << "</h2><table>";
        for (const auto& [k, v] : r[who]["provenance"].items()) {
            h << "<tr><th>" << esc(k) << "</th><td>"
              << esc(v.is_string() ? v.get<std::string>() : v.dump()) << "</td></tr>";
        }
        h << "</table>";
    };
    provenance("reference", "Reference provenance");
    provenance("actual", "Backend provenance");
    h << "<script>(function(){var "
         "z=document.getElementById('zoom'),v=document.getElementById('zoom-value');"
         "function apply(){var "
         "s=+z.value;v.textContent=s;document.querySelectorAll('img.zoomable').forEach("
         "function(i){if(i.naturalWidth){i.style.width=(i.naturalWidth*s*(+i.dataset.scale||1))+"
         "'px';}});}"
         "z.addEventListener('input',apply);document.querySelectorAll('img.zoomable').forEach("
         "function(i){"
         "i.addEventListener('load',apply);});apply();})();</script>";
    h << "</body></html>\n";
    return h.str();
}

}  // namespace

void write_reports(const std::filesystem::path& output, std::size_t selected_cases) {
    std::vector<json> results;
    {
        std::ifstream in(output / "results.jsonl");
        for (std::string line; std::getline(in, line);) {
            if (!line.empty()) results.push_back(json::parse(line));
        }
    }
    std::sort(results.begin(), results.end(), [](const json& a, const json& b) {
        return a.value("case", "") < b.value("case", "");
    });

    // deqp-runner's CSVs.
    std::ostringstream csv, failures;
    for (const auto& r : results) {
        const std::string line = r.value("case", "") + "," + deqp_status(r.value("status", "")) +
                                 "," + fixed(seconds(r, "reference") + seconds(r, "actual"), 6) +
                                 "\n";
        csv << line;
        if (failed(r.value("status", ""))) {
            failures << r.value("case", "") << "," << deqp_status(r.value("status", "")) << "\n";
        }
    }
    write_file(output / "results.csv", csv.str());
    write_file(output / "failures.csv", failures.str());

    // The samples of 4x cases, which deqp-runner's three columns have no room for.
    std::ostringstream samples;
    samples << "name,status,mismatched_pixels,mismatched_samples,pixels_with_mismatched_samples,"
               "sample0,sample1,sample2,sample3,max_sample_color,max_sample_color_x,"
               "max_sample_color_y,max_sample_color_sample,max_sample_depth,max_sample_depth_x,"
               "max_sample_depth_y,max_sample_depth_sample\n";
    for (const auto& r : results) {
        if (!has_samples(r)) continue;
        const auto& c = r["comparison"];
        samples << r.value("case", "") << "," << r.value("status", "") << "," << mismatched(r)
                << "," << mismatched_samples(r) << ","
                << c.value("pixels_with_mismatched_samples", std::uint64_t{0});
        for (std::size_t k = 0; k < 4; ++k) {
            samples << ",";
            if (c.contains("per_sample") && c["per_sample"].is_array() &&
                k < c["per_sample"].size()) {
                samples << c["per_sample"][k].value("mismatched", std::uint64_t{0});
            }
        }
        for (const char* key : {"max_sample_color", "max_sample_depth"}) {
            if (c.contains(key)) {
                const auto& m = c[key];
                samples << "," << m.value("amount", std::uint64_t{0}) << "," << m.value("x", 0)
                        << "," << m.value("y", 0) << "," << m.value("sample", 0);
            } else {
                samples << ",,,,";
            }
        }
        samples << "\n";
    }
    write_file(output / "samples.csv", samples.str());

    // Counts, overall and per area.
    std::map<std::string, std::size_t> counts;
    std::map<std::string, std::map<std::string, std::size_t>> areas;
    for (const auto& r : results) {
        ++counts[r.value("status", "")];
        ++areas[area_of(r.value("case", ""))][r.value("status", "")];
    }

    ojson doc;
    doc["summary"] = {
        {"selected", selected_cases}, {"finished", results.size()}, {"statuses", counts}};
    doc["cases"] = results;
    write_file(output / "results.json", doc.dump(1) + "\n");

    // JUnit.
    std::size_t nfail = 0, nskip = 0;
    double total = 0;
    for (const auto& r : results) {
        nfail += failed(r.value("status", ""));
        nskip += r.value("status", "") == "NotSupported";
        total += seconds(r, "reference") + seconds(r, "actual");
    }
    std::ostringstream x;
    x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites><testsuite name=\"refraster "
         "conformance\" tests=\""
      << results.size() << "\" failures=\"" << nfail << "\" skipped=\"" << nskip << "\" time=\""
      << fixed(total, 6) << "\">\n";
    for (const auto& r : results) {
        const std::string name = r.value("case", "");
        const auto dot = name.rfind('.');
        x << "  <testcase classname=\""
          << esc(dot == std::string::npos ? name : name.substr(0, dot)) << "\" name=\""
          << esc(dot == std::string::npos ? name : name.substr(dot + 1)) << "\" time=\""
          << fixed(seconds(r, "reference") + seconds(r, "actual"), 6) << "\">";
        const std::string st = r.value("status", "");
        if (st == "NotSupported") {
            x << "<skipped message=\"" << esc(r.value("message", "")) << "\"/>";
        } else if (failed(st)) {
            x << "<failure type=\"" << esc(st) << "\" message=\"" << esc(r.value("message", st))
              << "\"/>";
        }
        if (has_samples(r)) {
            x << "<system-out>"
              << esc(std::to_string(mismatched(r)) + " mismatched pixels; " + samples_line(r))
              << "</system-out>";
        }
        x << "</testcase>\n";
    }
    x << "</testsuite></testsuites>\n";
    write_file(output / "junit.xml", x.str());

    // HTML.
    std::filesystem::create_directories(output / "cases");
    std::ostringstream h;
    h << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>refraster conformance</title>"
      << kStyle << "</head><body><h1>refraster conformance run</h1>";
    if (!results.empty() && results.front().contains("actual")) {
        const auto& pv = results.front()["actual"].value("provenance", json::object());
        h << "<p>Against <b>" << esc(results.front()["actual"].value("backend", ""))
          << "</b>: " << esc(pv.value("renderer", "")) << ", " << esc(pv.value("gl_version", ""))
          << ", Mesa package " << esc(pv.value("mesa_version", "")) << "; CPU "
          << esc(pv.value("cpu_flags", "")) << "; commit " << esc(pv.value("commit", ""))
          << ".</p>";
    }
    if (!results.empty() && results.front().contains("reference") &&
        results.front()["reference"].contains("provenance")) {
        const auto& pv = results.front()["reference"]["provenance"];
        h << "<p id=\"reference-profile\">Reference profile <b>" << esc(pv.value("profile", ""))
          << "</b> (" << esc(pv.value("profile_source", "built-in"));
        if (pv.contains("profile_overrides"))
            h << ", --profile-set " << esc(pv.value("profile_overrides", ""));
        h << "): <code>" << esc(pv.value("profile_rules", "")) << "</code>.</p>";
    }
    h << "<table id=\"summary\"><tr><th>status</th><th>cases</th></tr>";
    for (const auto& [st, n] : counts) {
        h << "<tr><td class=\"st\" style=\"color:" << status_color(st) << "\">" << esc(st)
          << "</td><td class=\"num\">" << n << "</td></tr>";
    }
    h << "<tr><th>finished</th><td class=\"num\">" << results.size() << " of " << selected_cases
      << "</td></tr></table>";
    h << "<h2>By area</h2><table "
         "id=\"areas\"><tr><th>area</th><th>passed</th><th>failed</th><th>skipped</th></tr>";
    for (const auto& [area, st] : areas) {
        std::size_t p = 0, f = 0, k = 0;
        for (const auto& [s, n] : st) {
            if (s == "NotSupported") {
                k += n;
            } else if (failed(s)) {
                f += n;
            } else {
                p += n;
            }
        }
        h << "<tr><td>" << esc(area) << "</td><td class=\"num\">" << p << "</td><td class=\"num\">"
          << f << "</td><td class=\"num\">" << k << "</td></tr>";
    }
    h << "</table><h2>Error against run time</h2>" << chart(results);
    h << "<h2>Cases</h2><table id=\"cases\"><tr><th>case</th><th>status</th><th>mismatched "
         "px</th><th>mismatched samples</th><th>max colour "
         "error</th><th>reference ms</th><th>backend ms</th></tr>";
    for (const auto& r : results) {
        const std::string name = r.value("case", "");
        const std::string st = r.value("status", "");
        std::string maxc;
        if (r.contains("comparison") && r["comparison"].contains("max_color")) {
            maxc = std::to_string(r["comparison"]["max_color"].value("amount", 0));
        }
        h << "<tr><td><a href=\"cases/" << esc(name) << ".html\">" << esc(name)
          << "</a></td><td class=\"st\" style=\"color:" << status_color(st) << "\">" << esc(st)
          << "</td><td class=\"num\">" << mismatched(r) << "</td><td class=\"num\">"
          << (has_samples(r) ? std::to_string(mismatched_samples(r)) : std::string())
          << "</td><td class=\"num\">" << maxc << "</td><td class=\"num\">"
          << fixed(seconds(r, "reference") * 1000, 3) << "</td><td class=\"num\">"
          << fixed(seconds(r, "actual") * 1000, 3) << "</td></tr>";
        write_file(output / "cases" / (name + ".html"), case_page(r, output / "images"));
    }
    h << "</table></body></html>\n";
    write_file(output / "index.html", h.str());
}

}  // namespace conformance
