#include "conformance/reports.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "conformance/deqp_runner.hpp"
#include "conformance/records.hpp"
#include "harness/case_result.hpp"
#include "harness/compare.hpp"
#include "harness/encode.hpp"
#include "harness/files.hpp"
#include "harness/markup.hpp"
#include "record_check.hpp"

namespace conformance {

namespace {

using json = nlohmann::json;
using ojson = nlohmann::ordered_json;
namespace markup = harness::markup;

std::string fixed(double v, int digits) {
    std::ostringstream o;
    o.setf(std::ios::fixed);
    o.precision(digits);
    o << v;
    return o.str();
}

namespace encode = harness::encode;

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
    std::string t = std::to_string(m.value("amount", std::uint64_t{0})) +
                    (m.value("units", "") == "ULPs" ? " ULPs" : "") + " at (" +
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

// deqp-runner's word for a record's status (deqp_runner.hpp).
std::string deqp_status(const json& r) {
    return deqp_runner_status(r.value("status", ""), r.value("raw_status", ""));
}

// The command that explains a case's pixel exactly as the run compared it: the same backend
// and driver, and the same profile (its file and overrides).
std::string explain_command(const json& r, int x, int y) {
    const auto quote = [](const std::string& s) { return encode::shell_word(s); };
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
    if (s == "ExpectedFail" || s == "Flake" || s == "KnownFlake") return "#8d6e63";
    if (s == "NotSupported") return "#757575";
    return "#c62828";
}

const char* kStyle = R"(<style>
body{font-family:system-ui,sans-serif;margin:1.5em;color:#222}
table{border-collapse:collapse;font-size:14px}td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}
th{background:#f3f3f3}.num{text-align:right;font-variant-numeric:tabular-nums}
.st{font-weight:600}.imgs{display:flex;gap:16px;flex-wrap:wrap}.imgs figure{margin:0}
.imgs img{image-rendering:pixelated;image-rendering:crisp-edges;border:1px solid #999;background:#444}
code{background:#f3f3f3;padding:1px 4px;overflow-wrap:anywhere}
#cases{font-size:13px}#cases th{font-size:12px}#cases td:first-child{overflow-wrap:anywhere;max-width:18em}
th[aria-sort=ascending]::after{content:" \25B2"}th[aria-sort=descending]::after{content:" \25BC"}
td.verdict{max-width:24em;font-size:13px;overflow-wrap:anywhere}#case-filters input{width:22em}
.frame{position:relative;display:inline-block;line-height:0}
.cursor{position:absolute;display:none;outline:2px solid #00e5ff;pointer-events:none}
.swatch{display:inline-block;width:1.2em;height:1.2em;border:1px solid #999;vertical-align:middle}
#pixel-readout{font-variant-numeric:tabular-nums}
table.provenance td{overflow-wrap:anywhere}
</style>)";

// Sorting and filtering of the index's case table: a click on a header sorts by that column
// (again: the other way), numbers as numbers and empty cells last; the filter keeps the rows
// whose text holds every word typed, and the status menu those of one status.
const char* kTableScript = R"(</table><script>
(function () {
  var table = document.getElementById('cases');
  var body = table.tBodies[0];
  var rows = Array.prototype.slice.call(body.rows);
  var text = document.getElementById('case-filter');
  var status = document.getElementById('status-filter');
  var count = document.getElementById('case-count');
  function filter() {
    var words = text.value.toLowerCase().split(/\s+/).filter(Boolean);
    var shown = 0;
    rows.forEach(function (r) {
      var t = r.textContent.toLowerCase();
      var ok = words.every(function (w) { return t.indexOf(w) >= 0; }) &&
               (!status.value || r.getAttribute('data-status') === status.value);
      r.style.display = ok ? '' : 'none';
      shown += ok ? 1 : 0;
    });
    count.textContent = shown + ' of ' + rows.length + ' cases shown';
  }
  var order = {};
  Array.prototype.forEach.call(table.tHead.rows[0].cells, function (th) {
    th.style.cursor = 'pointer';
    th.title = 'sort';
    th.addEventListener('click', function () {
      var col = +th.getAttribute('data-col');
      var num = th.getAttribute('data-type') === 'num';
      var dir = order[col] = -(order[col] || -1);
      rows.sort(function (a, b) {
        var x = a.cells[col].textContent, y = b.cells[col].textContent;
        if (x === '' || y === '') return (x === '') - (y === '');
        return dir * (num ? parseFloat(x) - parseFloat(y) : x.localeCompare(y));
      });
      rows.forEach(function (r) { body.appendChild(r); });
      Array.prototype.forEach.call(table.tHead.rows[0].cells, function (c) {
        c.removeAttribute('aria-sort');
      });
      th.setAttribute('aria-sort', dir > 0 ? 'ascending' : 'descending');
    });
  });
  text.addEventListener('input', filter);
  status.addEventListener('change', filter);
  // Links to a view of the table: index.html#status=Fail&filter=coverage&sort=-3 (the column
  // by its number from 0, descending with a minus).
  var params = {};
  location.hash.replace(/^#/, '').split('&').forEach(function (kv) {
    var i = kv.indexOf('=');
    if (i > 0) params[kv.slice(0, i)] = decodeURIComponent(kv.slice(i + 1));
  });
  if (params.filter) text.value = params.filter;
  if (params.status) status.value = params.status;
  if (params.sort) {
    var col = Math.abs(+params.sort), th = table.tHead.rows[0].cells[col];
    if (th) {
      th.click();
      if (params.sort.charAt(0) === '-') th.click();
    }
  }
  filter();
})();
</script>)";

// A pixel's channel values as people read them: "0, 0, 0, 255" for an rgba8 target's bytes
// (whole numbers, however the record stores them), the float values otherwise.
// " ULPs" after a float target's amount (the record's "units"), nothing for integer levels.
std::string units(const json& m) {
    return m.value("units", "") == "ULPs" ? " ULPs" : "";
}

// A stored depth value as a number: z32f's bits as the float they hold.
std::string depth_value(const json& m, const char* side) {
    const auto v = m.value(side, std::uint32_t{0});
    if (m.value("units", "") != "ULPs") return std::to_string(v);
    return harness::float_text(std::bit_cast<float>(v));
}

std::string channel_values(const json& values) {
    if (!values.is_array()) return markup::escape(dump_text(values));
    std::ostringstream o;
    bool first = true;
    for (const auto& v : values) {
        o << (first ? "" : ", ");
        first = false;
        if (v.is_number()) {
            const double d = v.get<double>();
            if (std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 1e15) {
                o << static_cast<long long>(d);
            } else {
                o << dump_text(v);
            }
        } else {
            o << markup::escape(dump_text(v));
        }
    }
    return "(" + o.str() + ")";
}

// A run time in seconds as people read it: "250 µs", "1.5 ms", "10 s".
std::string time_label(double t) {
    std::ostringstream o;
    const auto trimmed = [](double v) {
        std::ostringstream n;
        n << std::setprecision(3) << v;
        return n.str();
    };
    if (t == 0) return "0";
    if (t < 1e-3) {
        o << trimmed(t * 1e6) << " \xC2\xB5s";
    } else if (t < 1) {
        o << trimmed(t * 1e3) << " ms";
    } else {
        o << trimmed(t) << " s";
    }
    return o.str();
}

// A pixel count: 7, 1k, 25k, 1M ...
std::string count_label(double n) {
    std::ostringstream o;
    o << std::setprecision(3);
    if (n >= 1e6) {
        o << n / 1e6 << "M";
    } else if (n >= 1e3) {
        o << n / 1e3 << "k";
    } else {
        o << n;
    }
    return o.str();
}

// One axis of the chart: logarithmic where its data spans a decade or more (run times; pixel
// counts, as log(1 + n) so that 0 stays on the axis), linear otherwise, with ticks at decades
// (and minor ticks at 2..9 times them) or at a 1-2-5 step.
struct ChartAxis {
    bool log = false;
    bool counts = false;  // log(1 + n) rather than log(n)
    double lo = 0, hi = 1;
    std::vector<double> major, minor;

    double position(double v) const {  // 0 at lo, 1 at hi
        const double f = log ? (counts ? std::log10(1.0 + v) : std::log10(v)) : v;
        return (f - lo) / (hi - lo);
    }

    static ChartAxis times(double tmin, double tmax) {
        ChartAxis a;
        a.log = tmax >= 10 * tmin;
        if (a.log) {
            a.lo = std::floor(std::log10(tmin));
            a.hi = std::ceil(std::log10(tmax));
            if (a.hi <= a.lo) a.hi = a.lo + 1;
            a.add_decades(static_cast<int>(a.lo), static_cast<int>(a.hi));
        } else {
            a.linear_ticks(tmin, tmax, 0.0);
        }
        return a;
    }

    static ChartAxis pixel_counts(double nmax) {
        ChartAxis a;
        a.counts = true;
        a.log = nmax >= 10;
        if (a.log) {
            a.lo = 0;
            a.hi = std::ceil(std::log10(1.0 + nmax));
            a.add_decades(0, static_cast<int>(a.hi));
            // The axis plots 1 + n, so its first decade, log10(1) = 0, is where n = 0 sits.
            a.major.front() = 0;
        } else {
            a.linear_ticks(0.0, std::max(1.0, nmax), 0.0);
        }
        return a;
    }

  private:
    void add_decades(int first, int last) {
        const markup::DecadeTicks ticks = markup::decade_ticks(first, last);
        for (const markup::DecadeTick& t : ticks.major) major.push_back(t.value);
        for (const markup::DecadeTick& t : ticks.minor) minor.push_back(t.value);
    }

    // Ticks at the 1-2-5 step that gives about five of them, the range widened to whole steps
    // (never below `floor_at`).
    void linear_ticks(double from, double to, double floor_at) {
        const double span = std::max(to - from, to * 1e-3 + 1e-12);
        const double raw = span / 5;
        const double step = markup::tick_step(raw);
        lo = std::max(floor_at, std::floor(from / step) * step);
        hi = std::ceil(to / step) * step;
        if (hi <= lo) hi = lo + step;
        // Added up rather than markup::linear_ticks: the running sum prints differently at
        // some ends (0.9999999999999999 s reads "1e+03 ms", 1.0 reads "1 s"), and the report
        // keeps the labels it has always written.
        for (double v = lo; v <= hi + step / 2; v += step) major.push_back(v);
    }
};

// The chart: every case as a dot, run time (reference + backend) across, mismatched pixels
// up, coloured by status, with a legend of the statuses present.
std::string chart(const std::vector<json>& results) {
    const double W = 720, H = 300, L = 64, B = 44, T = 12, R = 150;
    double tmin = 1e9, tmax = 0, nmax = 0;
    std::map<std::string, std::size_t> statuses;
    for (const auto& r : results) {
        const double t = std::max(1e-6, seconds(r, "reference") + seconds(r, "actual"));
        tmin = std::min(tmin, t);
        tmax = std::max(tmax, t);
        nmax = std::max(nmax, static_cast<double>(mismatched(r)));
        ++statuses[r.value("status", "")];
    }
    if (results.empty()) tmin = tmax = 1e-3;
    const ChartAxis ax = ChartAxis::times(tmin, tmax);
    const ChartAxis ay = ChartAxis::pixel_counts(nmax);
    const double pw = W - L - R, ph = H - T - B;
    const auto x_of = [&](double t) { return L + ax.position(t) * pw; };
    const auto y_of = [&](double n) { return H - B - ay.position(n) * ph; };
    std::ostringstream s;
    s << markup::svg_open({{"width", fixed(W, 0)},
                           {"height", fixed(H, 0)},
                           {"role", "img"},
                           {"aria-label", "mismatched pixels against run time"},
                           {"font-family", "system-ui,sans-serif"},
                           {"font-size", "11"},
                           {"data-x-scale", ax.log ? "log" : "linear"},
                           {"data-y-scale", ay.log ? "log" : "linear"}},
                          "error-chart");
    s << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << pw << "\" height=\"" << ph
      << "\" fill=\"#fafafa\" stroke=\"#999\"/>";
    for (const double v : ax.major) {
        const double x = x_of(v);
        s << "<line class=\"grid\" x1=\"" << fixed(x, 1) << "\" y1=\"" << T << "\" x2=\""
          << fixed(x, 1) << "\" y2=\"" << H - B << "\" stroke=\"#e3e3e3\"/>";
        s << "<line x1=\"" << fixed(x, 1) << "\" y1=\"" << H - B << "\" x2=\"" << fixed(x, 1)
          << "\" y2=\"" << H - B + 5 << "\" stroke=\"#666\"/><text class=\"tick-x\" x=\""
          << fixed(x, 1) << "\" y=\"" << H - B + 17 << "\" text-anchor=\"middle\">" << time_label(v)
          << "</text>";
    }
    for (const double v : ax.minor) {
        s << "<line x1=\"" << fixed(x_of(v), 1) << "\" y1=\"" << H - B << "\" x2=\""
          << fixed(x_of(v), 1) << "\" y2=\"" << H - B + 3 << "\" stroke=\"#999\"/>";
    }
    s << "<text x=\"" << L + pw / 2 << "\" y=\"" << H - 6
      << "\" text-anchor=\"middle\">render time, reference + backend"
      << (ax.log ? " (log scale)" : "") << "</text>";
    for (const double v : ay.major) {
        const double y = y_of(v);
        if (v > 0) {
            s << "<line class=\"grid\" x1=\"" << L << "\" y1=\"" << fixed(y, 1) << "\" x2=\""
              << L + pw << "\" y2=\"" << fixed(y, 1) << "\" stroke=\"#e3e3e3\"/>";
        }
        s << "<line x1=\"" << L - 5 << "\" y1=\"" << fixed(y, 1) << "\" x2=\"" << L << "\" y2=\""
          << fixed(y, 1) << "\" stroke=\"#666\"/><text class=\"tick-y\" x=\"" << L - 8 << "\" y=\""
          << fixed(y + 4, 1) << "\" text-anchor=\"end\">" << count_label(v) << "</text>";
    }
    for (const double v : ay.minor) {
        s << "<line x1=\"" << L - 3 << "\" y1=\"" << fixed(y_of(v), 1) << "\" x2=\"" << L
          << "\" y2=\"" << fixed(y_of(v), 1) << "\" stroke=\"#999\"/>";
    }
    s << "<text x=\"14\" y=\"" << T + ph / 2 << "\" transform=\"rotate(-90 14 " << T + ph / 2
      << ")\" text-anchor=\"middle\">mismatched pixels"
      << (ay.log ? " (log scale, 0 at the bottom)" : "") << "</text>";
    // Each dot links to its case's page. A case that timed out has no pixels to count: it is a
    // cross on the plot's top edge at the time it was given, not a dot at 0.
    bool timeouts = false;
    for (const auto& r : results) {
        const double t = std::max(1e-6, seconds(r, "reference") + seconds(r, "actual"));
        const std::string st = r.value("status", "");
        const std::string name = r.value("case", "");
        const std::string x = fixed(x_of(t), 1);
        s << "<a href=\"cases/" << markup::escape(name) << ".html\">";
        if (st == "Timeout") {
            timeouts = true;
            const double y = T + 5;
            s << "<path class=\"timeout\" d=\"M" << fixed(x_of(t) - 4, 1) << " " << fixed(y - 4, 1)
              << "l8 8m0 -8l-8 8\" stroke=\"" << status_color(st) << "\" stroke-width=\"2\"><title>"
              << markup::escape(name) << ": Timeout, no pixels compared, stopped after "
              << fixed(t * 1000, 2) << " ms</title></path>";
        } else {
            s << "<circle cx=\"" << x << "\" cy=\""
              << fixed(y_of(static_cast<double>(mismatched(r))), 1) << "\" r=\"3.5\" fill=\""
              << status_color(st) << "\" fill-opacity=\"0.7\"><title>" << markup::escape(name)
              << ": " << markup::escape(st) << ", " << mismatched(r) << " px, "
              << fixed(t * 1000, 2) << " ms</title></circle>";
        }
        s << "</a>";
    }
    // The legend: one entry a status present, with its count.
    s << "<g id=\"chart-legend\">";
    double ly = T + 8;
    for (const auto& [st, n] : statuses) {
        s << "<circle cx=\"" << W - R + 18 << "\" cy=\"" << ly << "\" r=\"4\" fill=\""
          << status_color(st) << "\"/><text x=\"" << W - R + 28 << "\" y=\"" << ly + 4 << "\">"
          << markup::escape(st) << " (" << n << ")</text>";
        ly += 18;
    }
    if (timeouts) {
        s << "<text x=\"" << W - R + 10 << "\" y=\"" << ly + 4
          << "\">&#xd7; on top: timed out</text>";
    }
    s << "</g>" << markup::svg_close();
    return s.str();
}

std::string case_page(const json& r, const FileExists& exists) {
    const std::string name = r.value("case", "");
    const std::string st = r.value("status", "");
    std::ostringstream h;
    h << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>" << markup::escape(name)
      << "</title>" << kStyle
      << "</head><body><p><a href=\"../index.html\">&larr; all cases</a></p><h1 id=\"case-name\">"
      << markup::escape(name)
      << "</h1><p>Status: <span id=\"case-status\" class=\"st\" style=\"color:" << status_color(st)
      << "\">" << markup::escape(st) << "</span>";
    if (r.contains("raw_status"))
        h << " (result " << markup::escape(r["raw_status"].get<std::string>()) << ")";
    h << "</p><p>Scene: <code>" << markup::escape(r.value("scene", "")) << "</code></p>";
    if (r.contains("message"))
        h << "<p id=\"case-message\">" << markup::escape(r["message"].get<std::string>()) << "</p>";

    // Images, side by side, pixelated and zoomable.
    h << "<p><label>Zoom <input id=\"zoom\" type=\"range\" min=\"1\" max=\"64\" "
         "value=\"8\"></label> "
         "<span id=\"zoom-value\">8</span>x &nbsp; <span id=\"pixel-readout\">move the "
         "pointer over an image: its pixel (x, y), y up from the bottom row as GL counts "
         "it</span></p><div class=\"imgs\">";
    const auto figure = [&](const std::string& file, const std::string& caption) {
        if (!exists("images/" + file)) return;
        h << "<figure><div class=\"frame\"><img class=\"zoomable pixels\" src=\"../images/"
          << markup::escape(file) << "\" alt=\"" << markup::escape(caption)
          << "\"><div class=\"cursor\"></div></div><figcaption>" << markup::escape(caption)
          << "</figcaption></figure>";
    };
    const std::string ref =
        r.contains("reference") ? r["reference"].value("backend", "ref") : "ref";
    const std::string act = r.contains("actual") ? r["actual"].value("backend", "") : "";
    for (const char* ext : {".png", ".exr"}) {
        figure(name + "." + ref + ext, "reference (" + ref + ")");
        figure(name + "." + act + ext, act);
    }
    figure(name + ".mask.png", "error mask (legend below)");
    // A 4x case's sample mask is 2W x 2H: shown at the size of the others, a sample a quarter
    // of a pixel.
    if (exists("images/" + name + ".samples.png")) {
        const std::string caption =
            "sample mask: each pixel's four samples in their places (top: 2 3, bottom: 0 1), "
            "coloured as the error mask";
        h << "<figure id=\"sample-mask\"><img class=\"zoomable\" data-scale=\"0.5\" "
             "src=\"../images/"
          << markup::escape(name + ".samples.png") << "\" alt=\"" << markup::escape(caption)
          << "\"><figcaption>" << markup::escape(caption) << "</figcaption></figure>";
    }
    h << "</div>";
    // The command that explains the pixel under the pointer, right under the images it is read
    // from (filled in by the script below).
    h << "<p id=\"pixel-command\"></p>";
    if (exists("images/" + name + ".mask.png") || exists("images/" + name + ".samples.png")) {
        // Every class a mask pixel can have (harness::mask_color), with its colour.
        h << "<table id=\"mask-legend\"><tr><th colspan=\"2\">mask colours</th></tr>";
        const std::pair<harness::PixelClass, const char*> classes[] = {
            {harness::PixelClass::Equal, "equal: within the tolerance, depth equal"},
            {harness::PixelClass::Missing, "missing: drawn by the reference only"},
            {harness::PixelClass::Extra, "extra: drawn by the backend only"},
            {harness::PixelClass::Coverage, "another primitive owns the pixel"},
            {harness::PixelClass::ColorOnly, "colour only: both drew it, colours differ"},
            {harness::PixelClass::DepthOnly, "depth only: colours agree, depth differs"}};
        for (const auto& [k, what] : classes) {
            const auto c = harness::mask_color(k);
            h << "<tr><td><span class=\"swatch\" style=\"background:rgb(" << int{c[0]} << ","
              << int{c[1]} << "," << int{c[2]} << ")\"></span></td><td>" << what << "</td></tr>";
        }
        h << "</table>";
    }
    if (exists("explain/" + name + ".svg")) {
        h << "<p id=\"explain-view\">The explain view of the pixel of largest difference: <a "
             "href=\"../explain/"
          << markup::escape(name) << ".svg\">picture</a>, <a href=\"../explain/"
          << markup::escape(name) << ".txt\">every decision as text</a>.</p>";
    }

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
              << units(m) << " at (" << m.value("x", 0) << ", " << m.value("y", 0) << ") channel "
              << "RGBA"[m.value("channel", 0) & 3] << ": reference "
              << channel_values(m["reference"]) << ", backend " << channel_values(m["actual"])
              << "</td></tr>";
        }
        if (c.contains("max_depth")) {
            const auto& m = c["max_depth"];
            h << "<tr><th>max depth error</th><td class=\"num\">" << m.value("amount", 0)
              << units(m) << " at (" << m.value("x", 0) << ", " << m.value("y", 0)
              << "): reference " << depth_value(m, "reference") << ", backend "
              << depth_value(m, "actual") << "</td></tr>";
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
                  << "RGBA"[m.value("channel", 0) & 3] << ": reference "
                  << channel_values(m["reference"]) << ", backend " << channel_values(m["actual"])
                  << "</td></tr>";
            }
            if (c.contains("max_sample_depth")) {
                const auto& m = c["max_sample_depth"];
                h << "<tr><th>max sample depth error</th><td class=\"num\">" << difference_at(m)
                  << ": reference " << depth_value(m, "reference") << ", backend "
                  << depth_value(m, "actual") << "</td></tr>";
            }
            h << "<tr><th>samples classified by</th><td>"
              << markup::escape(c.value("samples_classified_by", "")) << "</td></tr>";
        }
        h << "</table>";
        h << "<h2>Explanation</h2><p id=\"case-explanation\">";
        if (c.value("mismatched_pixels", 0) == 0 && mismatched_samples(r) == 0) {
            h << (has_samples(r) ? "Every pixel and every sample agrees." : "Every pixel agrees.");
        } else if (r.contains("explanation")) {
            const auto& e = r["explanation"];
            h << "<b>" << markup::escape(e.value("difference", "")) << ", "
              << markup::escape(e.value("rule", ""))
              << "</b>: " << markup::escape(e.value("verdict", ""))
              << ". Every decision at that pixel: <code id=\"explain-command\">"
              << markup::escape(
                     explain_command(r, e["pixel"][0].get<int>(), e["pixel"][1].get<int>()))
              << "</code>.";
        } else if (c.contains("max_color")) {
            const auto& m = c["max_color"];
            h << "The largest difference is at pixel (" << m.value("x", 0) << ", "
              << m.value("y", 0)
              << "). Trace every decision there with <code id=\"explain-command\">"
              << markup::escape(explain_command(r, m.value("x", 0), m.value("y", 0))) << "</code>.";
        } else if (c.contains("max_sample_color") || c.contains("max_sample_depth")) {
            const auto& m =
                c.contains("max_sample_color") ? c["max_sample_color"] : c["max_sample_depth"];
            h << "The resolved pixels agree; the largest sample difference is at pixel ("
              << m.value("x", 0) << ", " << m.value("y", 0) << "), sample " << m.value("sample", 0)
              << ". Trace every decision there with <code id=\"explain-command\">"
              << markup::escape(explain_command(r, m.value("x", 0), m.value("y", 0))) << "</code>.";
        }
        h << "</p>";
    }
    const auto provenance = [&](const char* who, const char* title) {
        if (!r.contains(who) || !r[who].contains("provenance")) return;
        h << "<h2>" << title << "</h2><table class=\"provenance\">";
        for (const auto& [k, v] : r[who]["provenance"].items()) {
            h << "<tr><th>" << markup::escape(k) << "</th><td>"
              << markup::escape(v.is_string() ? v.get<std::string>() : dump_text(v))
              << "</td></tr>";
        }
        h << "</table>";
    };
    provenance("reference", "Reference provenance");
    provenance("actual", "Backend provenance");
    // Both sides' values under the pointer, when the run wrote them (images/NAME.values.js: a
    // failed case of up to 256 x 256 pixels).
    if (exists("images/" + name + ".values.js")) {
        h << "<script>var caseValues = null; function refrasterCaseValues(v) { caseValues = v; "
             "}</script><script src=\"../images/"
          << markup::escape(name) << ".values.js\"></script>";
    } else {
        h << "<script>var caseValues = null;</script>";
    }
    // Zoom, and the pixel under the pointer: its coordinates (GL's, y up), the same pixel
    // outlined in every image, and the command that explains it.
    std::string template_command;
    if (r.contains("comparison")) template_command = explain_command(r, 77770, 88880);
    h << "<script>(function () {\n"
         "var z = document.getElementById('zoom'), v = document.getElementById('zoom-value');\n"
         "var readout = document.getElementById('pixel-readout');\n"
         "var command = document.getElementById('pixel-command');\n"
         "var template = "
      << encode::json_in_script(template_command)
      << ";\n"
         "var imgs = Array.prototype.slice.call(document.querySelectorAll('img.zoomable'));\n"
         "function apply() {\n"
         "  var s = +z.value; v.textContent = s;\n"
         "  imgs.forEach(function (i) { if (i.naturalWidth) {\n"
         "    i.style.width = (i.naturalWidth * s * (+i.dataset.scale || 1)) + 'px'; } });\n"
         "}\n"
         "// Both sides' values at (x, y) from caseValues (base64 colour and depth, row 0 at the\n"
         "// bottom): bytes for rgba8, floats for rgba32f, integers for z16/z24, floats for z32f.\n"
         "var decoded = {};\n"
         "function plane(side, what) {\n"
         "  var key = side + what; if (decoded[key] !== undefined) return decoded[key];\n"
         "  var text = caseValues && caseValues[side] && caseValues[side][what];\n"
         "  if (!text) return (decoded[key] = null);\n"
         "  var raw = atob(text), b = new Uint8Array(raw.length);\n"
         "  for (var i = 0; i < raw.length; ++i) b[i] = raw.charCodeAt(i);\n"
         "  var floats = what === 'color' ? caseValues.color_format === 'rgba32f'\n"
         "                                : caseValues.depth_format === 'z32f';\n"
         "  return (decoded[key] = what === 'color' && !floats ? b :\n"
         "      floats ? new Float32Array(b.buffer) : new Uint32Array(b.buffer));\n"
         "}\n"
         "function values(x, y) {\n"
         "  if (!caseValues || x >= caseValues.width || y >= caseValues.height) return '';\n"
         "  var i = y * caseValues.width + x, s = '';\n"
         "  ['reference', 'backend'].forEach(function (side) {\n"
         "    var c = plane(side, 'color'), d = plane(side, 'depth');\n"
         "    if (!c) return;\n"
         "    s += (s ? '; ' : ': ') + side + ' ' + Array.prototype.slice.call(c, 4 * i, 4 * i + "
         "4)\n"
         "        .join(', ') + (d ? ', depth ' + d[i] : '');\n"
         "  });\n"
         "  return s;\n"
         "}\n"
         "function show(x, y) {\n"
         "  imgs.forEach(function (i) {\n"
         "    var c = i.parentNode.querySelector('.cursor'); if (!c || !i.naturalWidth) return;\n"
         "    if (x < 0) { c.style.display = 'none'; return; }\n"
         "    var k = i.clientWidth / i.naturalWidth, h = i.naturalHeight;\n"
         "    c.style.display = 'block'; c.style.left = (x * k) + 'px';\n"
         "    c.style.top = ((h - 1 - y) * k) + 'px';\n"
         "    c.style.width = k + 'px'; c.style.height = k + 'px';\n"
         "  });\n"
         "  if (x < 0) return;\n"
         "  readout.textContent = 'pixel (' + x + ', ' + y + ')' + values(x, y);\n"
         "  if (template) command.innerHTML = 'Explain it: <code>' + template\n"
         "      .replace('77770,88880', x + ',' + y).replace(/&/g, '&amp;').replace(/</g, '&lt;')\n"
         "      + '</code>';\n"
         "}\n"
         "imgs.forEach(function (i) {\n"
         "  i.addEventListener('load', apply);\n"
         "  if (!i.classList.contains('pixels')) return;\n"
         "  i.addEventListener('mousemove', function (e) {\n"
         "    var r = i.getBoundingClientRect();\n"
         "    var x = Math.floor((e.clientX - r.left) / r.width * i.naturalWidth);\n"
         "    var row = Math.floor((e.clientY - r.top) / r.height * i.naturalHeight);\n"
         "    show(Math.min(x, i.naturalWidth - 1), i.naturalHeight - 1 -\n"
         "         Math.min(row, i.naturalHeight - 1));\n"
         "  });\n"
         "  i.addEventListener('mouseleave', function () { show(-1, -1); });\n"
         "});\n"
         "z.addEventListener('input', apply); apply();\n"
         "// A link to a pixel: case.html#pixel=X,Y outlines it once the images are in.\n"
         "var m = /^#pixel=(\\d+),(\\d+)$/.exec(location.hash);\n"
         "if (m) window.addEventListener('load', function () { apply(); show(+m[1], +m[2]); });\n"
         "})();</script>";
    h << "</body></html>\n";
    return h.str();
}

}  // namespace

namespace {

// The run's baseline, skips and flakes files (run.json's "inputs"), each as given, linked to
// the copy the run kept (when it is there and has one of the names the run gives copies), with
// what it holds. Nothing when the run predates the record.
std::string run_inputs_html(const json& inputs, const FileExists& exists) {
    if (!inputs.is_object()) return "";
    static const std::regex copy_name(R"(inputs/(baseline\.csv|(skips|flakes)-[0-9]+\.txt))");
    const auto text = [](const json& j, const char* key) {
        return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>()
                                                                      : std::string();
    };
    // "1 pattern", "2 patterns", "? patterns" when the record lacks the count.
    const auto count = [](const json& j, const char* key, const std::string& noun) {
        if (!(j.is_object() && j.contains(key) && j[key].is_number_unsigned()))
            return "? " + noun + "s";
        const std::uint64_t n = j[key].get<std::uint64_t>();
        return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
    };
    const auto file = [&](const json& j) {
        const std::string copy = text(j, "copy");
        std::string s = "<code>" + markup::escape(text(j, "file")) + "</code>";
        if (std::regex_match(copy, copy_name) && exists(copy))
            s += " (<a href=\"" + markup::escape(copy) + "\">the run's copy</a>";
        else
            s += " (no copy";
        return s + ", FNV-1a " + markup::escape(text(j, "fnv1a64")) + ")";
    };
    std::vector<std::string> items;
    if (inputs.contains("baseline") && inputs["baseline"].is_object()) {
        const json& b = inputs["baseline"];
        items.push_back("baseline " + file(b) + ": " + count(b, "cases", "case") + " listed");
    }
    for (const char* kind : {"skips", "flakes"}) {
        if (!inputs.contains(kind) || !inputs[kind].is_array()) continue;
        for (const json& f : inputs[kind]) {
            std::string item =
                std::string(kind) + " " + file(f) + ": " + count(f, "patterns", "pattern");
            if (std::string(kind) == "skips")
                item += ", " + count(f, "skipped_cases", "case") + " left out";
            items.push_back(item);
        }
    }
    std::string h = "<p id=\"run-inputs\">";
    if (items.empty()) return h + "No baseline, skips or flakes file.</p>";
    h += "Inputs: ";
    for (std::size_t i = 0; i < items.size(); ++i) h += (i ? "; " : "") + items[i];
    return h + ".</p>";
}

}  // namespace

std::vector<ReportFile> build_reports(const std::vector<std::string>& lines,
                                      const std::string& source, std::size_t selected_cases,
                                      const FileExists& exists, const std::string& run_setup,
                                      const std::string& run_source) {
    std::vector<ReportFile> files;
    json inputs;
    if (!run_setup.empty()) {
        json setup;
        try {
            setup = json::parse(run_setup);
        } catch (const json::exception&) {
            throw std::runtime_error(run_source + ": not a run's setup (not JSON)");
        }
        if (setup.is_object() && setup.contains("inputs") && setup["inputs"].is_object())
            inputs = setup["inputs"];
    }
    std::vector<json> results;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (lines[i].empty()) continue;
        const std::string where = source + ":" + std::to_string(i + 1);
        json r;
        try {
            r = json::parse(lines[i]);
        } catch (const json::exception&) {
            throw std::runtime_error(where + ": not a JSON record");
        }
        if (const auto problem = record_problem(r))
            throw std::runtime_error(where + ": " + *problem);
        results.push_back(std::move(r));
    }
    std::sort(results.begin(), results.end(), [](const json& a, const json& b) {
        return a.value("case", "") < b.value("case", "");
    });

    // deqp-runner's CSVs, as its RunnerResults::write_results and write_failures write them:
    // sorted by name (bytewise, as Rust sorts a String), no header, the duration an f32
    // printed with Rust's `{}`, and failures.csv every case that is not a success.
    std::ostringstream csv, failures;
    for (const auto& r : results) {
        const std::string word = deqp_status(r);
        const auto duration = static_cast<float>(seconds(r, "reference") + seconds(r, "actual"));
        const std::string name = encode::csv_field(r.value("case", ""));
        csv << name << "," << word << "," << deqp_runner_duration(duration) << "\n";
        if (!deqp_runner_is_success(word)) failures << name << "," << word << "\n";
    }
    files.push_back({"results.csv", csv.str()});
    files.push_back({"failures.csv", failures.str()});

    // The samples of 4x cases, which deqp-runner's three columns have no room for.
    std::ostringstream samples;
    samples << "name,status,mismatched_pixels,mismatched_samples,pixels_with_mismatched_samples,"
               "sample0,sample1,sample2,sample3,max_sample_color,max_sample_color_x,"
               "max_sample_color_y,max_sample_color_sample,max_sample_depth,max_sample_depth_x,"
               "max_sample_depth_y,max_sample_depth_sample\n";
    for (const auto& r : results) {
        if (!has_samples(r)) continue;
        const auto& c = r["comparison"];
        samples << encode::csv_field(r.value("case", "")) << ","
                << encode::csv_field(r.value("status", "")) << "," << mismatched(r) << ","
                << mismatched_samples(r) << ","
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
    files.push_back({"samples.csv", samples.str()});

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
    if (!inputs.is_null()) doc["inputs"] = inputs;
    doc["cases"] = results;
    files.push_back(
        {"results.json", doc.dump(1, ' ', false, json::error_handler_t::replace) + "\n"});

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
          << encode::xml_attribute(dot == std::string::npos ? name : name.substr(0, dot))
          << "\" name=\""
          << encode::xml_attribute(dot == std::string::npos ? name : name.substr(dot + 1))
          << "\" time=\"" << fixed(seconds(r, "reference") + seconds(r, "actual"), 6) << "\">";
        const std::string st = r.value("status", "");
        if (st == "NotSupported") {
            x << "<skipped message=\"" << encode::xml_attribute(r.value("message", "")) << "\"/>";
        } else if (failed(st)) {
            const std::string word = reported_status(st, r.value("raw_status", ""));
            x << "<failure type=\"" << encode::xml_attribute(word) << "\" message=\""
              << encode::xml_attribute(r.value("message", word)) << "\"/>";
        }
        // What a CI page shows beside the test: the verdict, the numbers, where to look.
        std::string out = st + ": " + std::to_string(mismatched(r)) + " mismatched pixels";
        if (r.contains("comparison")) {
            const auto& c = r["comparison"];
            out += " (missing " + std::to_string(c.value("missing", std::uint64_t{0})) +
                   ", extra " + std::to_string(c.value("extra", std::uint64_t{0})) +
                   ", colour only " + std::to_string(c.value("color_only", std::uint64_t{0})) +
                   ", depth only " + std::to_string(c.value("depth_only", std::uint64_t{0})) +
                   ", other primitive " +
                   std::to_string(c.value("other_primitive", std::uint64_t{0})) + ")";
        }
        if (has_samples(r)) out += "; " + samples_line(r);
        if (r.contains("explanation")) {
            const auto& e = r["explanation"];
            out += "\nverdict: " + e.value("difference", "") + ": " + e.value("rule", "");
        } else if (!r.contains("comparison") && !r.value("message", "").empty()) {
            out += "\n" + r.value("message", "");  // why nothing was compared
        }
        out += "\ncase page: cases/" + name + ".html";
        x << "<system-out>" << encode::xml_text(out) << "</system-out>";
        x << "</testcase>\n";
    }
    x << "</testsuite></testsuites>\n";
    files.push_back({"junit.xml", x.str()});

    // HTML.
    std::ostringstream h;
    h << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>refraster conformance</title>"
      << kStyle << "</head><body><h1>refraster conformance run</h1>";
    if (!results.empty() && results.front().contains("actual")) {
        const auto& pv = results.front()["actual"].value("provenance", json::object());
        h << "<p>Against <b>" << markup::escape(results.front()["actual"].value("backend", ""))
          << "</b>: " << markup::escape(pv.value("renderer", "")) << ", "
          << markup::escape(pv.value("gl_version", "")) << ", Mesa package "
          << markup::escape(pv.value("mesa_version", "")) << "; CPU "
          << markup::escape(pv.value("cpu_flags", "")) << "; commit "
          << markup::escape(pv.value("commit", "")) << ".</p>";
    }
    if (!results.empty() && results.front().contains("reference") &&
        results.front()["reference"].contains("provenance")) {
        const auto& pv = results.front()["reference"]["provenance"];
        h << "<p id=\"reference-profile\">Reference profile <b>"
          << markup::escape(pv.value("profile", "")) << "</b> ("
          << markup::escape(pv.value("profile_source", "built-in"));
        if (pv.contains("profile_overrides"))
            h << ", --profile-set " << markup::escape(pv.value("profile_overrides", ""));
        h << "): <code>" << markup::escape(pv.value("profile_rules", "")) << "</code>.</p>";
    }
    h << run_inputs_html(inputs, exists);
    h << "<table id=\"summary\"><tr><th>status</th><th>cases</th></tr>";
    for (const auto& [st, n] : counts) {
        h << "<tr><td class=\"st\" style=\"color:" << status_color(st) << "\">"
          << markup::escape(st) << "</td><td class=\"num\">" << n << "</td></tr>";
    }
    h << "<tr><th>finished</th><td class=\"num\">" << results.size() << " of " << selected_cases
      << "</td></tr></table>";
    // Why the failures failed, at a glance: the failed cases grouped by what explain names (the
    // class of difference and its rule), else by their status and message's kind; the largest
    // group first, each with its first cases linked. Then the worst cases by mismatched pixels.
    {
        std::map<std::string, std::vector<std::string>> why;
        std::vector<std::pair<std::uint64_t, std::string>> worst;
        for (const auto& r : results) {
            const std::string st = r.value("status", "");
            if (!failed(st)) continue;
            const std::string name = r.value("case", "");
            std::string reason = st;
            if (r.contains("explanation") && r["explanation"].is_object()) {
                const auto& e = r["explanation"];
                reason = e.value("difference", "") + ": " + e.value("rule", "");
            }
            why[reason].push_back(name);
            worst.emplace_back(mismatched(r), name);
        }
        if (!why.empty()) {
            std::vector<std::pair<std::string, std::vector<std::string>>> groups(why.begin(),
                                                                                 why.end());
            std::stable_sort(groups.begin(), groups.end(), [](const auto& a, const auto& b) {
                return a.second.size() > b.second.size();
            });
            h << "<h2>Why cases failed</h2><table id=\"failures-by-verdict\"><tr><th>verdict "
                 "(difference: rule, or status)</th><th>cases</th><th>first cases</th></tr>";
            for (const auto& [reason, names] : groups) {
                h << "<tr><td>" << markup::escape(reason) << "</td><td class=\"num\">"
                  << names.size() << "</td><td>";
                for (std::size_t i = 0; i < names.size() && i < 3; ++i) {
                    h << (i ? ", " : "") << "<a href=\"cases/" << markup::escape(names[i])
                      << ".html\">" << markup::escape(names[i]) << "</a>";
                }
                if (names.size() > 3) h << ", &hellip;";
                h << "</td></tr>";
            }
            h << "</table>";
            std::stable_sort(worst.begin(), worst.end(),
                             [](const auto& a, const auto& b) { return a.first > b.first; });
            h << "<h2>Worst cases</h2><ol id=\"worst-cases\">";
            for (std::size_t i = 0; i < worst.size() && i < 5; ++i) {
                h << "<li><a href=\"cases/" << markup::escape(worst[i].second) << ".html\">"
                  << markup::escape(worst[i].second) << "</a>: " << worst[i].first
                  << " mismatched pixels</li>";
            }
            h << "</ol>";
        }
    }
    // Counted as the console's summary line counts them (RunSummary): a case the baseline
    // expects to fail, or one that failed and then passed alone, is neither passed nor failed.
    h << "<h2>By area</h2><table "
         "id=\"areas\"><tr><th>area</th><th>passed</th><th>failed</th><th>skipped</th><th>failed "
         "as expected</th><th>flaky</th></tr>";
    for (const auto& [area, st] : areas) {
        std::size_t p = 0, f = 0, k = 0, e = 0, fl = 0;
        for (const auto& [s, n] : st) {
            if (s == "NotSupported") {
                k += n;
            } else if (failed(s)) {
                f += n;
            } else if (s == "ExpectedFail") {
                e += n;
            } else if (s == "Flake" || s == "KnownFlake") {
                fl += n;
            } else {
                p += n;
            }
        }
        h << "<tr><td>" << markup::escape(area) << "</td>";
        for (const std::size_t v : {p, f, k, e, fl}) h << "<td class=\"num\">" << v << "</td>";
        h << "</tr>";
    }
    h << "</table><h2>Error against run time</h2>" << chart(results);
    // This chart is per case; how the reference's own precision choices (sub-pixel bits, float
    // or exact setup, fused planes, depth formats, samples per pixel) trade error against run
    // time, against exact answers, is what `refraster study` measures.
    // Named, not linked: the report is read from any output folder, or from a CI artifact, where
    // no relative path reaches the source tree.
    h << "<p class=\"note\">Each dot is one case of this run. For error against run time of "
         "the rules themselves, against exact answers, see <code>docs/precision-study.md</code> "
         "in the source tree (<code>refraster study precision|antialiasing|stability</code>).</p>";
    // The cases: verdict and pixel classes, sortable by any column (click its header) and
    // filterable by text and status; the script keeps working without a server (file://).
    h << "<h2>Cases</h2><p id=\"case-filters\"><label>filter <input id=\"case-filter\" "
         "type=\"search\" placeholder=\"case name, status or verdict\"></label> <label>status "
         "<select id=\"status-filter\"><option value=\"\">any</option>";
    for (const auto& [st, n] : counts) {
        h << "<option>" << markup::escape(st) << "</option>";
    }
    h << "</select></label> <span id=\"case-count\"></span></p>";
    h << "<table id=\"cases\" class=\"sortable\"><thead><tr>";
    const char* headers[] = {"case",
                             "status",
                             "verdict",
                             "mismatched px",
                             "missing",
                             "extra",
                             "colour only",
                             "depth only",
                             "other primitive",
                             "mismatched samples",
                             "max colour error",
                             "reference ms",
                             "backend ms"};
    for (std::size_t i = 0; i < std::size(headers); ++i) {
        h << "<th data-col=\"" << i << "\"" << (i >= 3 ? " data-type=\"num\"" : "") << ">"
          << headers[i] << "</th>";
    }
    h << "</tr></thead><tbody>";
    // Failures first, each group by name: what a reader opens the report for is on top; a
    // click on a header sorts otherwise.
    std::vector<const json*> rows;
    for (const auto& r : results) rows.push_back(&r);
    std::stable_partition(rows.begin(), rows.end(),
                          [](const json* r) { return failed(r->value("status", "")); });
    for (const json* row : rows) {
        const json& r = *row;
        const std::string name = r.value("case", "");
        const std::string st = r.value("status", "");
        const json c = r.value("comparison", json::object());
        const auto count = [&](const char* k) -> std::string {
            return r.contains("comparison") ? std::to_string(c.value(k, std::uint64_t{0})) : "";
        };
        std::string maxc;
        if (c.contains("max_color")) maxc = std::to_string(c["max_color"].value("amount", 0));
        std::string verdict;
        if (r.contains("explanation")) {
            const auto& e = r["explanation"];
            verdict = e.value("difference", "") + ": " + e.value("rule", "");
        } else if (failed(st)) {
            verdict = r.value("message", "");
        }
        h << "<tr data-status=\"" << markup::escape(st) << "\"><td><a href=\"cases/"
          << markup::escape(name) << ".html\">" << markup::escape(name)
          << "</a></td><td class=\"st\" style=\"color:" << status_color(st) << "\">"
          << markup::escape(st) << "</td><td class=\"verdict\">" << markup::escape(verdict)
          << "</td><td class=\"num\">" << count("mismatched_pixels") << "</td><td class=\"num\">"
          << count("missing") << "</td><td class=\"num\">" << count("extra")
          << "</td><td class=\"num\">" << count("color_only") << "</td><td class=\"num\">"
          << count("depth_only") << "</td><td class=\"num\">" << count("other_primitive")
          << "</td><td class=\"num\">"
          << (has_samples(r) ? std::to_string(mismatched_samples(r)) : std::string())
          << "</td><td class=\"num\">" << maxc << "</td><td class=\"num\">"
          << fixed(seconds(r, "reference") * 1000, 3) << "</td><td class=\"num\">"
          << fixed(seconds(r, "actual") * 1000, 3) << "</td></tr>";
        files.push_back({"cases/" + name + ".html", case_page(r, exists)});
    }
    h << "</tbody>";
    h << kTableScript;
    h << "</body></html>\n";
    files.push_back({"index.html", h.str()});
    return files;
}

void write_report_files(const std::filesystem::path& output, const std::vector<ReportFile>& files) {
    // Every path checked before the first is written.
    std::vector<std::filesystem::path> paths;
    for (const ReportFile& f : files) {
        const auto slash = f.path.find('/');
        paths.push_back(slash == std::string::npos ? output_file(output, "", f.path)
                                                   : output_file(output, f.path.substr(0, slash),
                                                                 f.path.substr(slash + 1)));
    }
    for (std::size_t i = 0; i < files.size(); ++i) {
        std::filesystem::create_directories(paths[i].parent_path());
        harness::write_file_atomically(paths[i], files[i].text);
    }
}

void write_reports(const std::filesystem::path& output, std::size_t selected_cases) {
    const std::filesystem::path jsonl = output / "results.jsonl";
    std::vector<std::string> lines;
    for (auto& l : read_result_lines(jsonl).lines) lines.push_back(std::move(l.text));
    const auto exists = [&](const std::string& relative) {
        std::error_code ec;
        return std::filesystem::is_regular_file(
            std::filesystem::symlink_status(output / relative, ec));
    };
    std::string setup;
    const std::filesystem::path run = output / "run.json";
    if (exists("run.json")) {
        for (auto& l : read_result_lines(run).lines) setup += l.text + "\n";
    }
    write_report_files(
        output, build_reports(lines, encode::terminal(jsonl.string()), selected_cases, exists,
                              setup, encode::terminal(run.string())));
}

}  // namespace conformance
