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

}  // namespace testutil
