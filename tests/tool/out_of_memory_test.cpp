// Running out of memory, wherever it happens, ends the tool with the one line
// `refraster: out of memory` and exit code 3 (README.md, "Exit codes"), never an abort. The tool
// runs under an address-space limit (the shell's `ulimit -v`, RLIMIT_AS) of 768 MiB, far above
// what it needs to start and load a small scene, on a scene whose target alone needs 1 GiB in
// one allocation: the allocation fails whatever the machine, and the process can never use
// more memory than the limit.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace {

constexpr unsigned long kLimitKiB = 768ul * 1024;

testutil::CliResult run_cli_limited(const std::vector<std::string>& args) {
    testutil::TempDir io("oom");
    std::string cli = testutil::shell_quote(std::string(REFRASTER_BIN_DIR) + "/refraster");
    for (const auto& a : args) cli += " " + testutil::shell_quote(a);
    const std::string script = "ulimit -v " + std::to_string(kLimitKiB) + " && exec " + cli;
    const std::string cmd = "sh -c " + testutil::shell_quote(script) + " > " +
                            testutil::shell_quote((io.path() / "out").string()) + " 2> " +
                            testutil::shell_quote((io.path() / "err").string()) + " < /dev/null";
    const int status = std::system(cmd.c_str());
    testutil::CliResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = testutil::read_text(io.path() / "out");
    r.err = testutil::read_text(io.path() / "err");
    return r;
}

// 8192 x 8192 rgba32f: 1 GiB of colour, within the format's target limit.
constexpr const char* kHugeTarget = R"({"format": "refraster-scene/1",
  "target": {"width": 8192, "height": 8192, "color": "rgba32f"},
  "draws": [{"primitive": "triangles", "vertices": [
    {"position": [0, 0]}, {"position": [4, 0]}, {"position": [0, 4]}]}]})";

TEST(OutOfMemory, EndsWithOneLineAndExitCode3) {
    testutil::TempDir dir;
    const auto scene = dir.write("huge.json", kHugeTarget);
    // The limit leaves room for the tool itself: a small scene renders under it.
    const auto small = dir.write("small.json", R"({"format": "refraster-scene/1",
      "target": {"width": 16, "height": 16},
      "draws": [{"primitive": "triangles", "vertices": [
        {"position": [0, 0]}, {"position": [4, 0]}, {"position": [0, 4]}]}]})");
    auto r = run_cli_limited({"render", small.string(), "-o", (dir.path() / "s.png").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;

    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"render", scene.string(), "-o",
                                   (dir.path() / "out.exr").string()},
          std::vector<std::string>{"render", scene.string(), "--threads", "2", "-o",
                                   (dir.path() / "out.exr").string()},
          std::vector<std::string>{"compare", scene.string(), "--against", "ref"}}) {
        SCOPED_TRACE(args[0] + " " + args[2]);
        r = run_cli_limited(args);
        EXPECT_EQ(r.exit_code, 3) << r.err;
        EXPECT_EQ(r.err, "refraster: out of memory\n");
        EXPECT_FALSE(std::filesystem::exists(dir.path() / "out.exr"));
    }
}

}  // namespace
