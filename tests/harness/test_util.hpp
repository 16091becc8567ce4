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

// Runs build/bin/refraster with `args`, capturing its exit code, stdout and stderr.
inline CliResult run_cli(const std::vector<std::string>& args) {
    TempDir io("cli");
    std::string cmd = shell_quote(std::string(REFRASTER_BIN_DIR) + "/refraster");
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
