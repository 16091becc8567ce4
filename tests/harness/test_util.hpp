// Helpers shared by the harness, tool and conformance tests: temporary directories and running
// the CLI.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace testutil {

inline std::filesystem::path make_temp_dir(const std::string& tag) {
    std::string tmpl =
        (std::filesystem::temp_directory_path() / ("refraster-" + tag + "-XXXXXX")).string();
    const char* dir = ::mkdtemp(tmpl.data());
    if (dir == nullptr) throw std::runtime_error("mkdtemp failed");
    return dir;
}

// A temporary directory removed when the test ends.
class TempDir {
  public:
    explicit TempDir(const std::string& tag = "test") : path_(make_temp_dir(tag)) {}
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path write(const std::string& name, const std::string& text) const {
        const auto p = path_ / name;
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }

  private:
    std::filesystem::path path_;
};

inline std::string read_text(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

inline std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) {
        if (c == '\'') {
            q += "'\\''";
        } else {
            q += c;
        }
    }
    return q + "'";
}

struct CliResult {
    int exit_code = -1;
    std::string out;
    std::string err;
};

// The refraster binary the CLI tests run: build/bin/refraster, or the one
// REFRASTER_TEST_CLI names (an older build, to see a test fail there).
inline std::string refraster_bin() {
    if (const char* other = std::getenv("REFRASTER_TEST_CLI")) return other;
    return std::string(REFRASTER_BIN_DIR) + "/refraster";
}

// A command prefix that unsets every variable a CI engine or GoogleTest sets to shard a run,
// so that a conformance run started by a test is the whole run whatever the test's own
// environment holds.
inline const std::string kUnsetShardVariables =
    "env -u GTEST_SHARD_INDEX -u GTEST_TOTAL_SHARDS -u CI_NODE_INDEX -u CI_NODE_TOTAL "
    "-u JOB_COMPLETION_INDEX -u REFRASTER_SHARD_COUNT -u SLURM_ARRAY_TASK_ID "
    "-u SLURM_ARRAY_TASK_MIN -u SLURM_ARRAY_TASK_MAX -u SLURM_ARRAY_TASK_STEP "
    "-u SLURM_ARRAY_TASK_COUNT ";

// Runs the refraster binary with `args` after `prefix` (e.g. kUnsetShardVariables, or
// "timeout 60 " to bound a command that might block), capturing its exit code (128 + the
// signal when one ended it), stdout and stderr.
inline CliResult run_cli(const std::vector<std::string>& args, const std::string& prefix = "") {
    TempDir io("cli");
    std::string cmd = prefix + shell_quote(refraster_bin());
    for (const auto& a : args) cmd += " " + shell_quote(a);
    cmd += " > " + shell_quote((io.path() / "out").string()) + " 2> " +
           shell_quote((io.path() / "err").string()) + " < /dev/null";
    const int status = std::system(cmd.c_str());
    CliResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = read_text(io.path() / "out");
    r.err = read_text(io.path() / "err");
    return r;
}

// What a shell command writes to its standard output ("" when it cannot be started).
inline std::string command_output(const std::string& cmd) {
    std::string out;
    FILE* p = ::popen(cmd.c_str(), "r");
    if (p == nullptr) return out;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    ::pclose(p);
    return out;
}

inline std::size_t count_lines(const std::string& s) {
    std::size_t n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

// A page in a real browser: headless Chromium renders it (scripts included) in a window of
// `window` pixels and returns its DOM.
inline std::string chromium_dom(const std::filesystem::path& page,
                                const std::filesystem::path& profile_dir,
                                const std::string& window = "1280,900") {
    const std::string cmd =
        "timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
        "--disable-background-networking --disable-component-update --disable-sync "
        "--hide-scrollbars --window-size=" +
        window + " --user-data-dir=" + testutil::shell_quote(profile_dir.string()) +
        " --virtual-time-budget=2000 --dump-dom " +
        testutil::shell_quote("file://" + page.string()) + " 2>/dev/null";
    return testutil::command_output(cmd);
}

// The page laid out by Chromium in a 1,280 px wide window: a copy beside it with a script that,
// once loaded, lists every element whose box reaches past the window's right edge and every
// pair of text boxes (leaf elements with text; each of their line boxes) that overlap. Returns the
// probe's line: "scroll=W client=W outside=N overlaps=M" and the first few offenders.
inline std::string layout_probe(const std::filesystem::path& page,
                                const std::filesystem::path& chrome) {
    const auto copy = page.parent_path() / ("layout-probe-" + page.filename().string());
    std::string html = testutil::read_text(page);
    const std::string script = R"js(<script>
window.addEventListener('load', function () {
  var W = document.documentElement.clientWidth, out = [], texts = [];
  document.querySelectorAll('body *').forEach(function (e) {
    var r = e.getBoundingClientRect();
    if (r.width > 0 && r.right > W + 0.5)
      out.push(e.tagName + (e.id ? '#' + e.id : '') + '@' + Math.round(r.right));
    // A text box's line boxes, one a line (an inline element that wraps has a rectangle per
    // line, and its bounding box would overlap the text beside it on each).
    if (e.children.length === 0 && e.textContent.trim() !== '' && r.width > 0 &&
        getComputedStyle(e).visibility !== 'hidden')
      texts.push([e, Array.prototype.slice.call(e.getClientRects())]);
  });
  var overlaps = [];
  function hit(a, b) {
    return Math.min(a.right, b.right) - Math.max(a.left, b.left) > 1 &&
        Math.min(a.bottom, b.bottom) - Math.max(a.top, b.top) > 1;
  }
  for (var i = 0; i < texts.length; ++i) for (var j = i + 1; j < texts.length; ++j) {
    if (texts[i][0].contains(texts[j][0]) || texts[j][0].contains(texts[i][0])) continue;
    var any = texts[i][1].some(function (a) {
      return texts[j][1].some(function (b) { return hit(a, b); });
    });
    if (any)
      overlaps.push(texts[i][0].textContent.slice(0, 20) + '|' + texts[j][0].textContent.slice(0, 20));
  }
  var p = document.createElement('pre');
  p.id = 'layout-probe';
  p.textContent = 'scroll=' + document.documentElement.scrollWidth + ' client=' + W +
    ' outside=' + out.length + ' overlaps=' + overlaps.length + ' ' +
    out.slice(0, 6).join(' ') + ' ' + overlaps.slice(0, 4).join(' ; ');
  document.body.appendChild(p);
});
</script>)js";
    const auto at = html.rfind("</body>");
    html.insert(at == std::string::npos ? html.size() : at, script);
    std::ofstream(copy) << html;
    const std::string dom = chromium_dom(copy, chrome);
    const auto open = dom.find("<pre id=\"layout-probe\">");
    if (open == std::string::npos) return "no probe";
    const auto start = open + std::string("<pre id=\"layout-probe\">").size();
    return dom.substr(start, dom.find("</pre>", start) - start);
}

}  // namespace testutil
