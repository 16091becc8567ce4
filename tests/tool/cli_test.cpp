// `refraster render` end to end: usage errors, NotSupported, and a written image.
#include <gtest/gtest.h>
#include <sched.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "harness/bench.hpp"
#include "harness/image_io.hpp"
#include "layered_scene.hpp"
#include "test_util.hpp"

namespace {

TEST(Cli, UnknownSubcommandIsUsageError) {
    const auto r = testutil::run_cli({"frobnicate"});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
}

// Bad input met below the command (an unknown profile, an --egl-device that is not an index)
// reaches main as a refraster::Error of class BadInput: one line, "refraster: " and the
// message, exit code 2, whichever command met it, and nothing written.
TEST(Cli, BadInputErrorsAreOneLineWithExitTwo) {
    testutil::TempDir dir;
    const std::string scene = dir.write("s.json", R"({"format": "refraster-scene/1",
      "target": {"width": 2, "height": 2}, "draws": []})")
                                  .string();
    const std::string out = (dir.path() / "o.png").string();
    const std::vector<std::vector<std::string>> commands{
        {"render", scene, "-o", out, "--profile", "no-such-profile"},
        {"explain", scene, "--pixel", "0,0", "--no-backend", "--profile", "no-such-profile"},
        {"fingerprint", "--against", "ref", "-o", out, "--profile", "no-such-profile"},
        {"profile", "no-such-profile"},
        {"bench", "--no-gl", "--profile", "no-such-profile"},
        {"render", scene, "-o", out, "--backend", "egl", "--egl-device", "no-index"},
        {"render", scene, "-o", out, "--backend", "egl", "--driver", "no_such_driver"},
        {"render", scene, "-o", out, "--backend", "egl", "--driver", "zink;rm"},
        {"compare", scene, "--against", "osmesa", "--driver", "zink"}};
    for (const auto& args : commands) {
        const auto r = testutil::run_cli(args);
        EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << r.err;
        EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
        EXPECT_EQ(r.err.rfind("refraster: ", 0), 0u) << r.err;
        EXPECT_NE(r.err.find(args.back()), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(out)) << args[0];
    }
}

TEST(Cli, HelpOnSubcommand) {
    const auto r = testutil::run_cli({"render", "--help"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("--backend"), std::string::npos);
}

TEST(Cli, RefBackendRefusesPrimitivesWithExitFour) {
    testutil::TempDir dir;
    const auto scene = dir.write("s.json", R"({"format": "refraster-scene/1",
      "target": {"width": 4, "height": 4, "samples": 4},
      "draws": [{"primitive": "lines", "vertices": [{"position": [0, 0]}, {"position": [4, 0]}]}]})");
    const auto out = dir.path() / "o.png";
    // The exact profile draws filled triangles of single-sample targets only.
    const auto r = testutil::run_cli({"render", scene.string(), "--backend", "ref", "--profile",
                                      "gl-exact", "-o", out.string()});
    EXPECT_EQ(r.exit_code, 4) << r.err;
    EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("NotSupported"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(Cli, RequiredUnknownExtensionIsNotSupported) {
    testutil::TempDir dir;
    const auto scene =
        dir.write("s.json", R"({"format": "refraster-scene/1", "requires": ["x-future"],
      "target": {"width": 4, "height": 4}, "draws": []})");
    const auto r =
        testutil::run_cli({"render", scene.string(), "-o", (dir.path() / "o.png").string()});
    EXPECT_EQ(r.exit_code, 4) << r.err;
    EXPECT_NE(r.err.find("x-future"), std::string::npos);
}

// An rgba32f target is written as EXR through the codec module; without it, one line names
// where it was looked for, exit 2, and no file.
TEST(Cli, ExrNeedsTheCodecModuleAndSaysWhereItLooked) {
    testutil::TempDir dir;
    const auto scene = dir.write("s.json", R"({"format": "refraster-scene/1",
      "target": {"width": 2, "height": 2, "color": "rgba32f", "depth": "none"},
      "clear": {"color": [0.25, 0.5, 2, 1]}, "draws": []})");
    const auto out = dir.path() / "o.exr";
    const auto ok = testutil::run_cli({"render", scene.string(), "-o", out.string()});
    ASSERT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_EQ(harness::read_color_image(out).color32f[2], 2.0f);
    std::filesystem::remove(out);
    const auto r = testutil::run_cli({"render", scene.string(), "-o", out.string()},
                                     "env REFRASTER_CODEC_DIR=" + dir.path().string() + "/none ");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("REFRASTER_CODEC_DIR"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("libharness_oiio_codec.so"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(Cli, ClearOnlySceneRendersThroughRef) {
    testutil::TempDir dir;
    const auto scene = dir.write("s.json", R"({"format": "refraster-scene/1",
      "target": {"width": 3, "height": 2}, "clear": {"color": [0, 1, 0, 1]}, "draws": []})");
    const auto out = dir.path() / "o.png";
    const auto r = testutil::run_cli({"render", scene.string(), "-o", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto img = harness::read_color_image(out);
    ASSERT_EQ(img.color8.size(), 24u);
    for (std::size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(img.color8[4 * i + 1], 255);
        EXPECT_EQ(img.color8[4 * i + 0], 0);
    }
}

TEST(Cli, OutputExtensionMustMatchTarget) {
    testutil::TempDir dir;
    const auto scene = dir.write("s.json", R"({"format": "refraster-scene/1",
      "target": {"width": 3, "height": 2, "color": "rgba32f"}, "draws": []})");
    const auto r =
        testutil::run_cli({"render", scene.string(), "-o", (dir.path() / "o.png").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find(".exr"), std::string::npos);
}

TEST(Cli, SamplesOutputNeedsAMultisampledTarget) {
    testutil::TempDir dir;
    const auto scene = dir.write("s.json", R"({"format": "refraster-scene/1",
      "target": {"width": 3, "height": 2}, "draws": []})");
    const auto out = dir.path() / "o.png";
    const auto r = testutil::run_cli({"render", scene.string(), "-o", out.string(),
                                      "--samples-output", (dir.path() / "o").string()});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
    EXPECT_EQ(r.err, scene.string() +
                         ": --samples-output needs a multisampled target; target.samples is 1\n");
    EXPECT_FALSE(std::filesystem::exists(out));
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "o.s0.png"));
}

TEST(Cli, SamplesOutputIsAPrefixNotADirectory) {
    testutil::TempDir dir;
    const auto scene = dir.write("s.json", R"({"format": "refraster-scene/1",
      "target": {"width": 3, "height": 2, "samples": 4}, "draws": []})");
    const auto out = dir.path() / "o.png";
    const auto r = testutil::run_cli(
        {"render", scene.string(), "-o", out.string(), "--samples-output", dir.path().string()});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("takes a file name prefix (PREFIX.s0.png ...), not a directory"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(out));
}

// A 4x scene through the reference: either the reference refuses 4x (NotSupported, nothing
// written), or it writes the resolve and the four samples, whose resolve is the image.
TEST(Cli, SamplesOutputWritesEverySampleOrNothing) {
    testutil::TempDir dir;
    const auto scene = dir.write("s.json", R"({"format": "refraster-scene/1",
      "target": {"width": 4, "height": 4, "samples": 4}, "clear": {"color": [0, 0, 1, 1]},
      "draws": [{"primitive": "triangles", "vertices": [{"position": [0, 0]},
        {"position": [4, 0]}, {"position": [0, 4]}], "state": {"multisample": true}}]})");
    const auto out = dir.path() / "o.png";
    const auto prefix = dir.path() / "o";
    const auto r = testutil::run_cli(
        {"render", scene.string(), "-o", out.string(), "--samples-output", prefix.string()});
    const auto paths = harness::sample_image_paths(prefix, 4, refraster::ColorFormat::Rgba8);
    if (r.exit_code == 4) {
        EXPECT_NE(r.err.find("NotSupported"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(out));
        for (const auto& p : paths) EXPECT_FALSE(std::filesystem::exists(p)) << p;
        return;
    }
    ASSERT_EQ(r.exit_code, 0) << r.err;
    refraster::Framebuffer ms(4, 4, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 4);
    for (std::uint32_t s = 0; s < 4; ++s) {
        const auto plane = harness::read_color_image(paths[s]);
        ASSERT_EQ(plane.width, 4u);
        for (std::size_t i = 0; i < plane.pixel_count(); ++i) {
            for (std::size_t k = 0; k < 4; ++k) {
                ms.color8[(i * 4 + s) * 4 + k] = plane.color8[i * 4 + k];
            }
        }
    }
    EXPECT_EQ(refraster::resolve_samples(ms).color8, harness::read_color_image(out).color8);
}

TEST(Cli, HelpNamesTheSampleOutputs) {
    EXPECT_NE(testutil::run_cli({"render", "--help"}).out.find("--samples-output"),
              std::string::npos);
    EXPECT_NE(testutil::run_cli({"compare", "--help"}).out.find("NAME.samples.png"),
              std::string::npos);
}

// The README's library snippet is code of examples/compare_osmesa.cpp, which ctest builds and
// runs: every line of the snippet, whitespace aside, is in the example, in the same order
// (before, the snippet called make_gl_backend without a worker directory and aborted unless
// REFRASTER_WORKER_DIR was set).
TEST(Cli, ReadmeLibrarySnippetIsTheExamplesCode) {
    const auto squeeze = [](const std::string& t) {
        std::string out;
        for (char c : t)
            if (!std::isspace(static_cast<unsigned char>(c))) out += c;
        return out;
    };
    const std::string readme =
        testutil::read_text(std::filesystem::path(REFRASTER_SOURCE_DIR) / "README.md");
    const auto open = readme.find("```cpp\n");
    ASSERT_NE(open, std::string::npos);
    const auto close = readme.find("```", open + 7);
    std::istringstream snippet(readme.substr(open + 7, close - open - 7));
    const std::string example = squeeze(testutil::read_text(
        std::filesystem::path(REFRASTER_SOURCE_DIR) / "examples" / "compare_osmesa.cpp"));
    std::size_t at = 0, lines = 0;
    for (std::string line; std::getline(snippet, line);) {
        const std::string code = squeeze(line);
        if (code.empty()) continue;
        const auto found = example.find(code, at);
        ASSERT_NE(found, std::string::npos) << "not in the example (in this order): " << line;
        at = found + code.size();
        ++lines;
    }
    EXPECT_GE(lines, 5u);
}

// README's tour runs as written: each line of its block, from the source tree, with the
// binary of this build and out/tour/ in a temporary directory; a line whose comment says
// "exit 1" must exit 1, every other 0.
TEST(Cli, ReadmeTourRunsAsWritten) {
    const std::filesystem::path source = REFRASTER_SOURCE_DIR;
    const std::string readme = testutil::read_text(source / "README.md");
    const auto heading = readme.find("## A tour to copy and paste");
    ASSERT_NE(heading, std::string::npos);
    const auto open = readme.find("```sh\n", heading);
    const auto close = readme.find("```", open + 6);
    std::istringstream block(readme.substr(open + 6, close - open - 6));
    testutil::TempDir dir;
    const std::string bin = std::string(REFRASTER_BIN_DIR) + "/refraster";
    std::string prelude;  // variable assignments, kept for the lines after them
    std::size_t commands = 0;
    for (std::string line; std::getline(block, line);) {
        if (line.empty()) continue;
        // Each occurrence once, searching on after what replaced it (which may hold the text).
        const auto replace_all = [&line](const std::string& what, const std::string& with) {
            for (std::size_t at = line.find(what); at != std::string::npos;
                 at = line.find(what, at + with.size()))
                line.replace(at, what.size(), with);
        };
        replace_all("out/tour", (dir.path() / "tour").string());
        replace_all("build/bin/refraster", testutil::shell_quote(bin));
        if (line.find(bin) == std::string::npos) {
            prelude += line + "\n";
            continue;
        }
        const bool fails = line.find("# exit 1") != std::string::npos;
        if (const auto comment = line.find("  # "); comment != std::string::npos)
            line.erase(comment);
        const std::string out = testutil::command_output(
            "cd " + testutil::shell_quote(source.string()) + " && mkdir -p " +
            testutil::shell_quote((dir.path() / "tour").string()) + " && " + prelude + line +
            " >/dev/null 2>&1; echo \"rc=$?\"");
        EXPECT_EQ(out.substr(out.rfind("rc=") + 3, 1), fails ? "1" : "0") << line;
        ++commands;
    }
    EXPECT_GE(commands, 8u);
    for (const char* f : {"square.png", "pixel.svg", "run/index.html", "teach/frames/steps.gif",
                          "painter/index.html", "study/summary.md"})
        EXPECT_TRUE(std::filesystem::exists(dir.path() / "tour" / f)) << f;
}

// `bench --help` names every standard workload a default run measures, and their number.
TEST(Cli, BenchHelpNamesTheWorkloadsItRuns) {
    const auto r = testutil::run_cli({"bench", "--help"});
    EXPECT_EQ(r.exit_code, 0);
    std::string squeezed;  // CLI11 wraps long help lines
    for (char c : r.out)
        if (!std::isspace(static_cast<unsigned char>(c))) squeezed += c;
    const auto& names = harness::bench_workload_names();
    EXPECT_NE(squeezed.find("bydefaultthe" + std::to_string(names.size()) + "standardones"),
              std::string::npos)
        << r.out;
    for (const auto& n : names) EXPECT_NE(squeezed.find(n), std::string::npos) << n;
}

// Every command that writes a named output takes -o for it, as render, reduce and fingerprint
// always did.
TEST(Cli, EveryOutputTakesDashO) {
    for (const auto& cmd : std::vector<std::vector<std::string>>{{"render"},
                                                                 {"reduce"},
                                                                 {"fingerprint"},
                                                                 {"teach"},
                                                                 {"study"},
                                                                 {"conformance", "run"},
                                                                 {"conformance", "merge"},
                                                                 {"generate", "extreme"},
                                                                 {"generate", "many-triangles"}}) {
        auto args = cmd;
        args.push_back("--help");
        const auto r = testutil::run_cli(args);
        EXPECT_EQ(r.exit_code, 0) << cmd.back();
        EXPECT_NE(r.out.find("-o,--output"), std::string::npos) << cmd.back() << ":\n" << r.out;
    }
}

// `bench` without GL at a tiny scale: the new options reach the JSON and the table.
TEST(Cli, BenchOptionsReachTheJson) {
    testutil::TempDir dir;
    const auto json = dir.path() / "bench.json";
    const auto r =
        testutil::run_cli({"bench", "--no-gl", "--no-softpipe", "--scale", "0.0001", "--scenes",
                           "tiny-flat", "--rounds", "1", "--kernels", "scalar", "--threads", "1",
                           "--second-threads", "0", "--json", json.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("kernels scalar (asked: scalar); ref: 1 thread; ref 2T: off"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("| tiny-flat | 100 triangles |"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\ntargets: tiny-flat -/3.0 not measured"), std::string::npos) << r.out;
    const std::string j = testutil::read_text(json);
    for (const char* key : {"\"kernels\": \"scalar\"", "\"threads\": 1", "\"second_threads\": 0",
                            "\"softpipe\": false", "\"ref2_ms\": null", "\"targets\""}) {
        EXPECT_NE(j.find(key), std::string::npos) << key << "\n" << j;
    }
}

// The single-threaded renders run on one CPU, the lowest this process may use unless
// --pin-cpu names another or none; the table and the JSON say which, and a CPU the process
// may not use is bad input.
TEST(Cli, BenchPinsItsSingleThreadedRendersToOneCpu) {
    cpu_set_t set;
    CPU_ZERO(&set);
    ASSERT_EQ(::sched_getaffinity(0, sizeof set, &set), 0);
    int lowest = -1;
    for (int c = CPU_SETSIZE - 1; c >= 0; --c)
        if (CPU_ISSET(static_cast<std::size_t>(c), &set)) lowest = c;
    ASSERT_GE(lowest, 0);
    testutil::TempDir dir;
    const auto json = dir.path() / "bench.json";
    const std::vector<std::string> quick = {
        "bench",     "--no-gl",  "--scale", "0.0001",           "--scenes",
        "tiny-flat", "--rounds", "1",       "--second-threads", "0"};
    auto args = quick;
    args.insert(args.end(), {"--json", json.string()});
    const auto pinned = testutil::run_cli(args);
    ASSERT_EQ(pinned.exit_code, 0) << pinned.err;
    EXPECT_NE(pinned.out.find("; one thread on CPU " + std::to_string(lowest) + ";"),
              std::string::npos)
        << pinned.out;
    EXPECT_NE(testutil::read_text(json).find("\"pinned_cpu\": " + std::to_string(lowest)),
              std::string::npos);

    args = quick;
    args.insert(args.end(), {"--pin-cpu", "none", "--json", json.string()});
    const auto free = testutil::run_cli(args);
    ASSERT_EQ(free.exit_code, 0) << free.err;
    EXPECT_NE(free.out.find("; not pinned;"), std::string::npos) << free.out;
    EXPECT_NE(testutil::read_text(json).find("\"pinned_cpu\": null"), std::string::npos);

    if (!CPU_ISSET(1023, &set)) {
        args = quick;
        args.insert(args.end(), {"--pin-cpu", "1023"});
        const auto bad = testutil::run_cli(args);
        EXPECT_EQ(bad.exit_code, 2) << bad.err;
        EXPECT_NE(bad.err.find("CPU 1023 is not one this process may run on"), std::string::npos)
            << bad.err;
    }
    args = quick;
    args.insert(args.end(), {"--pin-cpu", "fastest"});
    EXPECT_EQ(testutil::run_cli(args).exit_code, 2);
}

TEST(Cli, BenchRefusesUnknownKernelsAndScenes) {
    const auto k = testutil::run_cli({"bench", "--no-gl", "--kernels", "sse"});
    EXPECT_EQ(k.exit_code, 2) << k.err;
    const auto s = testutil::run_cli({"bench", "--no-gl", "--scenes", "huge-flat"});
    EXPECT_EQ(s.exit_code, 2) << s.err;
    EXPECT_NE(s.err.find("tiny-flat-4m"), std::string::npos) << s.err;
    EXPECT_NE(testutil::run_cli({"bench", "--help"}).out.find("--scaling"), std::string::npos);
}

}  // namespace

TEST(Cli, ThreadsChangeNoByteOfARender) {
    testutil::TempDir dir;
    const auto scene = dir.path() / "many.json";
    ASSERT_EQ(testutil::run_cli({"generate", "many-triangles", "--triangles", "4000", "--form",
                                 "values", "--output", scene.string()})
                  .exit_code,
              0);
    std::vector<refraster::Framebuffer> images;
    for (const char* threads : {"1", "3"}) {
        const auto out = dir.path() / (std::string("t") + threads + ".png");
        const auto r =
            testutil::run_cli({"render", scene.string(), "--threads", threads, "-o", out.string()});
        ASSERT_EQ(r.exit_code, 0) << r.err;
        images.push_back(harness::read_color_image(out));
    }
    ASSERT_FALSE(images[0].color8.empty());
    EXPECT_TRUE(images[0].color8 == images[1].color8);
    // Something was drawn: not every pixel is the first one's colour.
    bool varied = false;
    for (std::size_t i = 4; i < images[0].color8.size() && !varied; ++i)
        varied = images[0].color8[i] != images[0].color8[i % 4];
    EXPECT_TRUE(varied);
    EXPECT_NE(testutil::run_cli({"compare", "--help"}).out.find("--threads"), std::string::npos);
    EXPECT_NE(testutil::run_cli({"conformance", "run", "--help"}).out.find("--threads"),
              std::string::npos);
    const auto bad = testutil::run_cli(
        {"render", scene.string(), "--threads", "-1", "-o", (dir.path() / "x.png").string()});
    EXPECT_EQ(bad.exit_code, 2) << bad.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "x.png"));
}

namespace {

// A 2x2 texture (red, green / blue, white, rows bottom to top) magnified over an 8x8 target
// with bilinear filtering and repeat: pixel (3, 2) samples at (3.5/8, 2.5/8); the numbers below
// follow from the rules of docs/precision.md, "Textures".
const char* kTexturedScene = R"({"format": "refraster-scene/1", "requires": ["textures"],
  "target": {"width": 8, "height": 8},
  "textures": {"t": {"width": 2, "height": 2, "data": "/wAA/wD/AP8AAP///////w=="}},
  "draws": [{"primitive": "triangles", "state": {"texture": {"name": "t", "env": "replace"}},
    "vertices": [{"position": [0, 0], "texcoord": [0, 0]}, {"position": [8, 0], "texcoord": [1, 0]},
                 {"position": [0, 8], "texcoord": [0, 1]}, {"position": [8, 0], "texcoord": [1, 0]},
                 {"position": [8, 8], "texcoord": [1, 1]}, {"position": [0, 8], "texcoord": [0, 1]}]}]})";

// Explain writes down its arithmetic: the corners' order after setup's swap, the area's sign
// convention against GL's winding, and the edge function's formula, which the printed values
// obey (checked on every edge of the JSON trace).
// Two reference profiles side by side: --against ref with its own profile, or with a rule of
// the reference's changed; each side named by its profile. A GL backend has no profile.
TEST(Cli, CompareTwoProfilesSideBySide) {
    const std::string scene = std::string(REFRASTER_SOURCE_DIR) +
                              "/conformance/scenes/triangles/coverage/square_through_centres.json";
    const auto same = testutil::run_cli({"compare", scene, "--against", "ref"});
    EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
    testutil::TempDir dir;
    const auto mask = dir.path() / "mask.png";
    const auto two = testutil::run_cli({"compare", scene, "--against", "ref", "--against-profile",
                                        "softpipe-22.3", "--diff", mask.string()});
    EXPECT_EQ(two.exit_code, 1) << two.out << two.err;  // the tie rules differ
    // Both sides' images, named by side (both are "ref").
    for (const char* f : {"mask.png", "mask.reference.png", "mask.against.png"})
        EXPECT_TRUE(std::filesystem::exists(dir.path() / f)) << f;
    EXPECT_NE(two.out.find("(ref llvmpipe-22.3 vs ref softpipe-22.3)"), std::string::npos)
        << two.out;
    const auto rule = testutil::run_cli(
        {"compare", scene, "--against", "ref", "--against-profile-set", "tie_rule=right-top"});
    EXPECT_EQ(rule.exit_code, 1) << rule.out << rule.err;
    EXPECT_NE(rule.out.find("vs ref llvmpipe-22.3 tie_rule=right-top)"), std::string::npos)
        << rule.out;
    const auto gl = testutil::run_cli(
        {"compare", scene, "--against", "osmesa", "--against-profile", "softpipe-22.3"});
    EXPECT_EQ(gl.exit_code, 2);
    EXPECT_NE(gl.err.find("a GL backend has no profile"), std::string::npos) << gl.err;
}

TEST(Cli, ExplainStatesTheWindingOrderAndEdgeFormula) {
    const std::string scene =
        std::string(REFRASTER_SOURCE_DIR) +
        "/conformance/scenes/triangles/coverage/shared_edge_slope_half_ccw.json";
    const auto t = testutil::run_cli({"explain", scene, "--pixel", "12,15", "--no-backend"});
    EXPECT_EQ(t.exit_code, 0) << t.err;
    EXPECT_NE(t.out.find("negative, counter-clockwise in GL's window space, y up): front-facing"),
              std::string::npos)
        << t.out;
    EXPECT_NE(t.out.find("corners in setup's order: window vertices 1, 0, 2"), std::string::npos)
        << t.out;
    EXPECT_NE(t.out.find("E = c - a x + b y"), std::string::npos) << t.out;
    const auto j =
        testutil::run_cli({"explain", scene, "--pixel", "12,15", "--no-backend", "--json"});
    const auto trace = nlohmann::json::parse(j.out);
    int edges = 0;
    for (const auto& p : trace["primitives"]) {
        for (const auto& s : p["setups"]) {
            const std::int64_t unit = std::int64_t{1} << s["subpixel_bits"].get<int>();
            const std::int64_t x = 12 * unit, y = 15 * unit;  // the pixel centre, centre at 0
            for (const auto& e : s["edges"]) {
                const auto a = e["a"].get<std::int64_t>(), b = e["b"].get<std::int64_t>();
                EXPECT_EQ(e["value"].get<std::int64_t>(),
                          e["c"].get<std::int64_t>() - a * x + b * y);
                ++edges;
            }
        }
    }
    EXPECT_EQ(edges, 6);
}

TEST(Cli, ExplainShowsTheSamplersDecisionsAndTheTexelGrid) {
    testutil::TempDir dir;
    const auto scene = dir.write("tex.json", kTexturedScene);
    const auto svg = dir.path() / "e.svg";
    const auto r =
        testutil::run_cli({"explain", scene.string(), "--pixel", "3,2", "--svg", svg.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // u = 3.5 / 8, S = RNE(u * 512) - 128 = 96: texels 0 and 1, weight 96/256 along s;
    // v = 2.5 / 8, S = 32: texels 0 and 1, weight 32/256 along t.
    EXPECT_NE(r.out.find("texture (8-bit path): s 0.4375 t 0.3125"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("bilinear in level 0"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("texels x 0, 1 y 0, 1, weights 96/256 along s, 32/256 along t"),
              std::string::npos)
        << r.out;
    const std::string text = testutil::read_text(svg);
    EXPECT_NE(text.find("texels of level 0 (2x2), bilinear, 8-bit path"), std::string::npos);
    // The four texels of the 2x2 level, each a rectangle with its bytes in its title.
    EXPECT_NE(text.find("texel (1, 1): 255,255,255,255"), std::string::npos);
    EXPECT_NE(text.find("texel (0, 0): 255,0,0,255"), std::string::npos);
}

TEST(Cli, ExplainSvgShowsBothGeometriesAxesGridAndLegend) {
    testutil::TempDir dir;
    const auto scene = dir.write("tex.json", kTexturedScene);
    const auto svg = dir.path() / "corner.svg";
    // Pixel (0, 0): the 9x9 neighbourhood reaches four pixels beyond the target's left and
    // bottom sides.
    const auto r =
        testutil::run_cli({"explain", scene.string(), "--pixel", "0,0", "--svg", svg.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string text = testutil::read_text(svg);
    const auto count = [&](const std::string& what) {
        std::size_t n = 0;
        for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
        return n;
    };
    EXPECT_EQ(count("<g class=\"panel\""), 2u);
    EXPECT_NE(text.find("id=\"unsnapped\""), std::string::npos);
    EXPECT_NE(text.find("id=\"snapped\""), std::string::npos);
    // 81 cells a panel; outside the 8x8 target: 81 - 25 = 56 of them, hatched.
    EXPECT_EQ(count("class=\"cell outside\""), 2u * 56u);
    EXPECT_EQ(count("class=\"cell\""), 2u * 25u);
    EXPECT_NE(text.find("pixel (-4, -4): outside the target"), std::string::npos);
    // Axes: columns -4..4 below each panel, rows -4..4 beside it.
    EXPECT_EQ(count("class=\"axis-x\""), 18u);
    EXPECT_EQ(count("class=\"axis-y\""), 18u);
    EXPECT_NE(text.find(">-4</text>"), std::string::npos);
    // The unsnapped outlines dashed, the snapped ones with edge arrows and inside ticks,
    // every primitive clipped to its panel.
    EXPECT_EQ(count("class=\"unsnapped\""), 2u);  // the two triangles that reach (0, 0)
    EXPECT_EQ(count("class=\"snapped\""), 2u);
    EXPECT_GT(count("class=\"edge-direction\""), 0u);
    EXPECT_EQ(count("class=\"edge-direction\""), count("class=\"inside-side\""));
    EXPECT_EQ(count("clip-path=\"url(#clip-"), 2u);
    EXPECT_EQ(count("class=\"subpixel-grid\""), 2u);
    EXPECT_NE(text.find("id=\"legend\""), std::string::npos);
    EXPECT_NE(text.find("outside the target</text>"), std::string::npos);
    EXPECT_NE(text.find("the sub-pixel grid"), std::string::npos);
}

// Every subcommand that loads scene files takes --texture-root: without it a scene's texture
// file outside its folder is refused (exit 2 where the command reports bad input), with it the
// scene loads.
TEST(Cli, EveryCommandThatLoadsScenesTakesTheTextureRoot) {
    testutil::TempDir dir;
    std::filesystem::create_directories(dir.path() / "scenes");
    std::filesystem::create_directories(dir.path() / "tex");
    refraster::Framebuffer fb(1, 1, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None);
    fb.color8 = {10, 20, 30, 255};
    harness::write_color_image(fb, dir.path() / "tex" / "t.png");
    const std::string scene = dir.write("scenes/t.json", R"({"format": "refraster-scene/1",
      "name": "t", "requires": ["textures"], "target": {"width": 4, "height": 4},
      "textures": {"t": {"file": "../tex/t.png"}},
      "draws": [{"primitive": "triangles", "state": {"texture": {"name": "t"}},
                 "vertices": [{"position": [0, 0]}, {"position": [4, 0]}, {"position": [0, 4]}]}]})")
                                  .string();
    const std::string root = (dir.path() / "tex").string();
    const std::string out = (dir.path() / "out").string();
    const std::string message = "cannot be used as a texture";
    const std::vector<std::vector<std::string>> commands{
        {"check", scene},
        {"render", scene, "-o", out + ".png"},
        {"compare", scene, "--against", "ref"},
        {"explain", scene, "--pixel", "1,1", "--no-backend"},
        {"teach", scene, "--algorithm", "half-space", "--against", "ref", "--output", out},
        {"reduce", scene, "--pixel", "1,1", "-o", out + ".json"},
        {"conformance", "hashes", "--scenes", (dir.path() / "scenes").string()},
        {"conformance", "run", "--against", "ref", "--scenes", (dir.path() / "scenes").string(),
         "--output", out + "-run"}};
    for (const auto& args : commands) {
        const std::string name = args[0] + (args[0] == "conformance" ? " " + args[1] : "");
        const auto without = testutil::run_cli(args);
        EXPECT_NE(without.exit_code, 0) << name;
        if (args[0] != "conformance") {  // the runner records it in the case's result
            EXPECT_EQ(without.exit_code, 2) << name << ": " << without.err;
            EXPECT_EQ(testutil::count_lines(without.err), 1u) << name << ": " << without.err;
            EXPECT_NE(without.err.find(message), std::string::npos) << name << ": " << without.err;
        }
        auto widened = args;
        widened.insert(widened.end(), {"--texture-root", root});
        const auto with = testutil::run_cli(widened);
        EXPECT_EQ((with.out + with.err).find(message), std::string::npos)
            << name << ": " << with.err;
        if (args[0] != "reduce") {
            EXPECT_EQ(with.exit_code, 0) << name << ": " << with.err;
        }
        std::filesystem::remove_all(out + "-run");
    }
    // The root must be a folder.
    const auto r = testutil::run_cli({"check", scene, "--texture-root", scene});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--texture-root"), std::string::npos) << r.err;
}

}  // namespace

namespace {

// --timeout bounds the reference as it bounds a GL worker: a scene that would take the
// reference many seconds (13 s on two threads of the development machine) ends after half a
// second as a Timeout, in the GL workers' words ("... gave no answer within T s for SCENE"),
// exit code 3 (a backend failure), nothing written.
TEST(Cli, TimeoutStopsTheReference) {
    testutil::TempDir dir;
    const auto scene = dir.write("heavy.json", testutil::layered_scene(2048, 400)).string();
    const auto out = dir.path() / "o.png";
    const std::vector<std::vector<std::string>> commands{
        {"render", scene, "--backend", "ref", "--threads", "2", "--timeout", "0.5", "-o",
         out.string()},
        {"compare", scene, "--reference", "ref", "--against", "ref", "--threads", "2", "--timeout",
         "0.5", "--json", (dir.path() / "r.json").string()}};
    for (const auto& args : commands) {
        const auto r = testutil::run_cli(args);
        EXPECT_EQ(r.exit_code, 3) << args[0] << ": " << r.err;
        EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
        EXPECT_NE(r.err.find("Timeout"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("gave no answer within 0.500000 s for " + scene + " (stopped)"),
                  std::string::npos)
            << r.err;
        EXPECT_FALSE(std::filesystem::exists(out)) << args[0];
    }
    // The record names the reference's own status.
    const auto rec = testutil::read_text(dir.path() / "r.json");
    EXPECT_NE(rec.find(R"("status":"Timeout")"), std::string::npos) << rec;
}

// explain renders the reference itself (the plain render, its alternatives, the trace); each
// render is bounded by --timeout as render's is: the same one-line Timeout message, exit 3,
// no SVG written.
TEST(Cli, TimeoutStopsTheReferenceInExplain) {
    testutil::TempDir dir;
    const auto scene = dir.write("heavy.json", testutil::layered_scene(2048, 400)).string();
    const auto svg = dir.path() / "p.svg";
    const auto r = testutil::run_cli({"explain", scene, "--pixel", "5,5", "--no-backend",
                                      "--timeout", "0.5", "--svg", svg.string()});
    EXPECT_EQ(r.exit_code, 3) << r.err << r.out;
    EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("gave no answer within 0.500000 s for " + scene + " (stopped)"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(svg));
}

}  // namespace
