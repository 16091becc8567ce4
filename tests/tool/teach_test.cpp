// `refraster teach` end to end: every algorithm on the teaching scenes of examples/teach/, the
// reasons it names for pixels whose cause is known by construction, and its refusals.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "harness/image_io.hpp"
#include "test_util.hpp"

namespace {

using json = nlohmann::json;
const std::filesystem::path kSource = REFRASTER_SOURCE_DIR;

struct Taught {
    testutil::CliResult cli;
    json data;
};

Taught teach(const std::filesystem::path& scene, const std::string& algorithm,
             const std::filesystem::path& out) {
    Taught t;
    t.cli = testutil::run_cli(
        {"teach", scene.string(), "--algorithm", algorithm, "--output", out.string()});
    if (t.cli.exit_code == 0) t.data = json::parse(testutil::read_text(out / "teach.json"));
    return t;
}

// "Reproduce this page" gives every option that chose the page's GL image and pictures (before,
// --against, --driver, --profile-set and --zoom were dropped).
TEST(Teach, ReproduceCommandKeepsEveryOption) {
    testutil::TempDir dir;
    const auto out = dir.path() / "t";
    const auto r = testutil::run_cli({"teach", (kSource / "examples/teach/lines_fan.json").string(),
                                      "--algorithm", "bresenham", "--profile-set",
                                      "tie_rule=right-top", "--profile-set", "line_rule=bresenham",
                                      "--zoom", "4", "--output", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto page = testutil::read_text(out / "index.html");
    EXPECT_NE(page.find("--algorithm bresenham --profile-set tie_rule=right-top --profile-set "
                        "line_rule=bresenham --zoom 4 --output"),
              std::string::npos)
        << page.substr(page.find("Reproduce this page"), 400);
}

// The frames of a GIF: one graphic control extension (21 F9 04) before each image.
std::size_t gif_frames(const std::string& bytes) {
    std::size_t n = 0;
    for (auto at = bytes.find("\x21\xF9\x04"); at != std::string::npos;
         at = bytes.find("\x21\xF9\x04", at + 3))
        ++n;
    return n;
}

// Lecture frames: the chosen steps as SVG and PNG (the picture at the page's zoom, each step's
// pixels outlined) and as an animated GIF of as many frames; bad ranges refused before anything
// is written.
TEST(Teach, FramesDrawTheChosenStepsForALecture) {
    testutil::TempDir dir;
    const auto scene = (kSource / "examples/teach/lines_fan.json").string();
    const auto out = dir.path() / "t";
    const auto r =
        testutil::run_cli({"teach", scene, "--algorithm", "bresenham", "--frames", "--frame-steps",
                           "2-4", "--zoom", "4", "--output", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json data = json::parse(testutil::read_text(out / "teach.json"));
    EXPECT_FALSE(std::filesystem::exists(out / "frames" / "step-0001.svg"));
    EXPECT_FALSE(std::filesystem::exists(out / "frames" / "step-0005.png"));
    for (int k = 2; k <= 4; ++k) {
        const std::string name = "step-000" + std::to_string(k);
        const std::string svg = testutil::read_text(out / "frames" / (name + ".svg"));
        // The step's number and title under the picture.
        EXPECT_NE(
            svg.find("Step " + std::to_string(k) + " of " + std::to_string(data["steps"].size())),
            std::string::npos);
        const auto png = harness::read_color_image(out / "frames" / (name + ".png"));
        EXPECT_EQ(png.width, 4u * data["width"].get<std::uint32_t>());
        EXPECT_EQ(png.height, 4u * data["height"].get<std::uint32_t>());
        // The step's first pixel: outlined in yellow at its border, lit white at its centre.
        const auto& p = data["steps"][static_cast<std::size_t>(k - 1)]["pixels"][0];
        const std::uint32_t x = 4 * p[0].get<std::uint32_t>(), y = 4 * p[1].get<std::uint32_t>();
        const std::size_t border = 4 * png.index(x, y), centre = 4 * png.index(x + 2, y + 2);
        EXPECT_EQ(png.color8[border], 0xff) << name;
        EXPECT_EQ(png.color8[border + 1], 0xd6) << name;
        EXPECT_EQ(png.color8[border + 2], 0x00) << name;
        // Lit: white, or the input line's green drawn over it (the path follows the line).
        EXPECT_GE(std::max({png.color8[centre], png.color8[centre + 1], png.color8[centre + 2]}),
                  200)
            << name;
    }
    const std::string gif = testutil::read_text(out / "frames" / "steps.gif");
    EXPECT_EQ(gif.rfind("GIF89a", 0), 0u);
    EXPECT_EQ(gif_frames(gif), 3u);

    for (const auto& [range, what] :
         std::vector<std::pair<std::string, std::string>>{{"4-2", "not a range"},
                                                          {"0-3", "not a range"},
                                                          {"2-x", "not a range"},
                                                          {"1-100000", "past the run's"}}) {
        const auto bad = dir.path() / ("bad" + range);
        const auto b = testutil::run_cli({"teach", scene, "--algorithm", "bresenham", "--frames",
                                          "--frame-steps", range, "--output", bad.string()});
        EXPECT_EQ(b.exit_code, 2) << range;
        EXPECT_NE(b.err.find("--frame-steps: "), std::string::npos) << b.err;
        EXPECT_NE(b.err.find(what), std::string::npos) << b.err;
        EXPECT_FALSE(std::filesystem::exists(bad)) << range;  // nothing written
    }
    const auto alone =
        testutil::run_cli({"teach", scene, "--algorithm", "bresenham", "--frame-steps", "1-2",
                           "--output", (dir.path() / "alone").string()});
    EXPECT_EQ(alone.exit_code, 2);
    EXPECT_NE(alone.err.find("only with --frames"), std::string::npos) << alone.err;
}

const json* difference_at(const json& data, int x, int y) {
    for (const auto& d : data["differences"]) {
        if (d["x"] == x && d["y"] == y) return &d;
    }
    return nullptr;
}

// Every algorithm runs on a scene it can take and writes the page, the data and three images
// of the target's size times the zoom; every difference has a reason and every run has steps.
TEST(Teach, EveryAlgorithmWritesItsPage) {
    const std::vector<std::pair<std::string, std::string>> runs{
        {"dda", "lines_fan"},
        {"bresenham", "lines_fan"},
        {"midpoint", "lines_fan"},
        {"wu", "lines_fan"},
        {"circle", "points_circles"},
        {"circle", "circle_loops"},
        {"scanline-evenodd", "star_evenodd"},
        {"scanline-nonzero", "star_evenodd"},
        {"flood4", "arrow_polygon"},
        {"flood8", "arrow_polygon"},
        {"ear-clipping", "arrow_polygon"},
        {"trapezoids", "arrow_polygon"},
        {"painter", "pinwheel_depth"},
        {"homogeneous", "behind_eye"},
        {"half-space", "shared_edges"}};
    testutil::TempDir dir;
    for (const auto& [algorithm, scene] : runs) {
        SCOPED_TRACE(algorithm + " on " + scene);
        const auto out = dir.path() / (algorithm + "-" + scene);
        const auto t = teach(kSource / "examples/teach" / (scene + ".json"), algorithm, out);
        ASSERT_EQ(t.cli.exit_code, 0) << t.cli.err;
        EXPECT_EQ(t.data["algorithm"], algorithm);
        EXPECT_GT(t.data["steps"].size(), 0u);
        const int w = t.data["width"];
        const int h = t.data["height"];
        EXPECT_EQ(t.data["algorithm_rgba"].size(), static_cast<std::size_t>(4 * w * h));
        for (const auto& d : t.data["differences"])
            EXPECT_FALSE(d["reason"].get<std::string>().empty());
        const auto page = testutil::read_text(out / "index.html");
        EXPECT_NE(page.find("id=\"teach-data\""), std::string::npos);
        // The algorithm's pseudo-code, shown on the page, and every step on one of its lines.
        const auto& code = t.data["pseudo_code"];
        ASSERT_GE(code.size(), 2u);
        EXPECT_NE(page.find("<ol id=\"pseudo-code\"><li><code>"), std::string::npos);
        std::set<int> lines;
        for (const auto& st : t.data["steps"]) {
            ASSERT_TRUE(st.contains("line")) << st["title"];
            const int line = st["line"];
            EXPECT_GE(line, 1) << st["title"];
            EXPECT_LE(line, static_cast<int>(code.size())) << st["title"];
            lines.insert(line);
        }
        EXPECT_GE(lines.size(), 2u);  // the steps walk the code, not one line of it
        for (const char* png : {"algorithm.png", "gl.png", "differences.png"}) {
            const auto img = harness::read_color_image(out / png);
            EXPECT_EQ(img.width, static_cast<std::uint32_t>(8 * w)) << png;
            EXPECT_EQ(img.height, static_cast<std::uint32_t>(8 * h)) << png;
        }
    }
}

// Two algorithms side by side (--beside): the second's image where GL's is, the differences
// where the two part, each with both runs' reasons against GL; an algorithm beside itself
// differs nowhere.
TEST(Teach, TwoAlgorithmsSideBySide) {
    testutil::TempDir dir;
    const auto scene = (kSource / "examples/teach/lines_fan.json").string();
    const auto out = dir.path() / "b";
    const auto r = testutil::run_cli(
        {"teach", scene, "--algorithm", "bresenham", "--beside", "dda", "--output", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json data = json::parse(testutil::read_text(out / "teach.json"));
    EXPECT_EQ(data["beside"], "the DDA line");
    const auto alone = teach(kSource / "examples/teach/lines_fan.json", "dda", dir.path() / "d");
    ASSERT_EQ(alone.cli.exit_code, 0);
    EXPECT_EQ(data["gl_rgba"], alone.data["algorithm_rgba"]);  // the DDA's image in the middle
    ASSERT_GT(data["differences"].size(), 0u);
    for (const auto& d : data["differences"]) {
        const std::string reason = d["reason"];
        EXPECT_EQ(reason.rfind("Bresenham's line algorithm: ", 0), 0u) << reason;
        EXPECT_NE(reason.find("; the DDA line: "), std::string::npos) << reason;
    }
    const std::string page = testutil::read_text(out / "index.html");
    EXPECT_NE(page.find("beside the DDA line"), std::string::npos);
    EXPECT_NE(page.find("--algorithm bresenham --beside dda"), std::string::npos);
    const auto same = testutil::run_cli({"teach", scene, "--algorithm", "dda", "--beside", "dda",
                                         "--output", (dir.path() / "s").string()});
    ASSERT_EQ(same.exit_code, 0) << same.err;
    EXPECT_EQ(
        json::parse(testutil::read_text(dir.path() / "s" / "teach.json"))["differences"].size(),
        0u);
}

// Teaching pages as Chromium lays them out in a 1,280 px window: nothing past the right edge,
// no two text boxes overlapping, for pages with long step titles, pseudo-code, parts and a
// second algorithm; and a lecture frame's SVG the same at its own size.
TEST(Teach, ChromiumLayoutFitsA1280PixelWindow) {
    testutil::TempDir dir;
    const std::vector<std::vector<std::string>> runs = {{"lines_fan", "bresenham"},
                                                        {"arrow_polygon", "scanline-evenodd"},
                                                        {"bars_cycle", "painter"},
                                                        {"shared_edges", "half-space"},
                                                        {"lines_fan", "wu", "--beside", "dda"}};
    for (const auto& run : runs) {
        SCOPED_TRACE(run[1]);
        const auto out = dir.path() / (run[0] + "-" + run[1]);
        std::vector<std::string> args = {
            "teach",       (kSource / "examples/teach" / (run[0] + ".json")).string(),
            "--algorithm", run[1],
            "--frames",    "--frame-steps",
            "1-2",         "--output",
            out.string()};
        args.insert(args.end(), run.begin() + 2, run.end());
        const auto r = testutil::run_cli(args);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const std::string probe = testutil::layout_probe(out / "index.html", dir.path() / "chrome");
        ASSERT_NE(probe, "no probe") << "(is the chromium package installed?)";
        EXPECT_NE(probe.find("client=1280"), std::string::npos) << probe;
        EXPECT_NE(probe.find("outside=0 "), std::string::npos) << probe;
        EXPECT_NE(probe.find("overlaps=0 "), std::string::npos) << probe;
        const auto frame = out / "frames" / "frame.html";
        std::ofstream(frame) << "<!DOCTYPE html><html><body style=\"margin:8px\">"
                             << testutil::read_text(out / "frames" / "step-0002.svg")
                             << "</body></html>\n";
        const std::string fprobe = testutil::layout_probe(frame, dir.path() / "chrome");
        EXPECT_NE(fprobe.find("outside=0 "), std::string::npos) << fprobe;
        EXPECT_NE(fprobe.find("overlaps=0 "), std::string::npos) << fprobe;
    }
}

// A circle drawn as GL draws one, a line loop of chords: the midpoint circle takes the loop's
// circle, and every pixel where they part is explained by the chords (never by a square point:
// before, the circle could only be compared with GL's square points, whose insides were most of
// the differences).
TEST(Teach, TheCircleIsComparedWithGlsLoopOfChords) {
    testutil::TempDir dir;
    const auto t = teach(kSource / "examples/teach/circle_loops.json", "circle", dir.path() / "c");
    ASSERT_EQ(t.cli.exit_code, 0) << t.cli.err;
    const auto& diffs = t.data["differences"];
    ASSERT_GT(diffs.size(), 0u);
    // Outline against outline: few pixels part, a small share of the pixels either side lights.
    std::size_t lit = 0;  // the circle's pixels: red above 0
    const auto& rgba = t.data["algorithm_rgba"];
    for (std::size_t i = 0; i < rgba.size(); i += 4) lit += rgba[i].get<int>() > 0 ? 1u : 0u;
    EXPECT_LT(diffs.size() * 4, lit);  // fewer than a quarter of the circle's pixels
    for (const auto& d : diffs) {
        const std::string reason = d["reason"];
        EXPECT_NE(reason.find("straight chords"), std::string::npos) << reason;
        EXPECT_EQ(reason.find("square"), std::string::npos) << reason;
    }
    EXPECT_NE(t.data["notes"].dump().find("line loop"), std::string::npos);
}

// Known causes. A line ending on the centre of pixel (22, 16): Bresenham lights that pixel and
// GL's half-open end does not. The arrow's fan reaches outside it: every pixel GL lights and the
// scanline fill does not is a fan pixel. The even-odd star's middle is lit by non-zero only.
// The pinwheel's cycle is named by the painter.
TEST(Teach, NamesTheKnownCauses) {
    testutil::TempDir dir;
    const auto lines =
        teach(kSource / "examples/teach/lines_fan.json", "bresenham", dir.path() / "b");
    ASSERT_EQ(lines.cli.exit_code, 0) << lines.cli.err;
    const json* end = difference_at(lines.data, 22, 16);
    ASSERT_NE(end, nullptr);
    EXPECT_EQ((*end)["gl"], false);
    EXPECT_NE((*end)["reason"].get<std::string>().find("last pixel"), std::string::npos)
        << (*end)["reason"];

    const auto arrow =
        teach(kSource / "examples/teach/arrow_polygon.json", "scanline-evenodd", dir.path() / "s");
    ASSERT_EQ(arrow.cli.exit_code, 0) << arrow.cli.err;
    ASSERT_GT(arrow.data["differences"].size(), 20u);
    for (const auto& d : arrow.data["differences"]) {
        EXPECT_EQ(d["gl"], true);
        EXPECT_NE(d["reason"].get<std::string>().find("fan"), std::string::npos) << d["reason"];
    }

    const auto star =
        teach(kSource / "examples/teach/star_evenodd.json", "scanline-nonzero", dir.path() / "n");
    ASSERT_EQ(star.cli.exit_code, 0) << star.cli.err;
    const json* middle = difference_at(star.data, 16, 14);
    ASSERT_NE(middle, nullptr);
    EXPECT_EQ((*middle)["gl"], false);
    EXPECT_NE((*middle)["reason"].get<std::string>().find("the rules differ: winding number"),
              std::string::npos)
        << (*middle)["reason"];

    // GL's own rule written out agrees with GL on unclipped triangles, and its steps name the
    // centres on edges and the edge that owns each.
    const auto half =
        teach(kSource / "examples/teach/shared_edges.json", "half-space", dir.path() / "h");
    ASSERT_EQ(half.cli.exit_code, 0) << half.cli.err;
    EXPECT_EQ(half.data["differences"].size(), 0u);
    int owned = 0, not_owned = 0;
    for (const auto& st : half.data["steps"]) {
        const auto title = st["title"].get<std::string>();
        owned += title.find("which owns it") != std::string::npos;
        not_owned += title.find("which does not own it") != std::string::npos;
    }
    EXPECT_GT(owned, 10);
    EXPECT_GT(not_owned, 10);
    // Each edge function is written as an expression with its units, signs merged: never
    // "c 1 - -2816 x + -2816 y".
    int functions = 0, biased = 0;
    for (const auto& st : half.data["steps"]) {
        for (const auto& kv : st["state"]) {
            const auto key = kv[0].get<std::string>();
            const auto value = kv[1].get<std::string>();
            // A pixel's value shows the tie bias apart, never a bare "1" on an owned edge.
            if (key.size() == 7 && key.substr(2) == " here") {
                biased += value.find(" + 1 (tie bias) = ") != std::string::npos;
                continue;
            }
            if (key.size() != 2 || key[0] != 'E') continue;
            EXPECT_EQ(value.find("- -"), std::string::npos) << value;
            EXPECT_EQ(value.find("+ -"), std::string::npos) << value;
            EXPECT_NE(value.find("in 1/256 px"), std::string::npos) << value;
            ++functions;
        }
    }
    EXPECT_GE(functions, 3);
    EXPECT_GT(biased, 10);  // centres on owned edges: "0 + 1 (tie bias) = 1", not a bare 1

    const auto painter =
        teach(kSource / "examples/teach/pinwheel_depth.json", "painter", dir.path() / "p");
    ASSERT_EQ(painter.cli.exit_code, 0) << painter.cli.err;
    bool cycle = false;
    for (const auto& d : painter.data["differences"])
        cycle =
            cycle || d["reason"].get<std::string>().find("painter's order") != std::string::npos;
    EXPECT_TRUE(cycle);
}

// GL's rules from OSMesa llvmpipe (--against gl) rather than the reference: the same pixels,
// so the same differences, and the page names the driver.
TEST(Teach, AgainstGlUsesTheGlBackend) {
    if (!std::filesystem::exists(std::filesystem::path(REFRASTER_BIN_DIR) /
                                 "refraster-worker-osmesa"))
        GTEST_SKIP() << "built without the OSMesa worker";
    testutil::TempDir dir;
    const auto scene = kSource / "examples/teach/star_evenodd.json";
    const auto ref = teach(scene, "scanline-nonzero", dir.path() / "ref");
    ASSERT_EQ(ref.cli.exit_code, 0) << ref.cli.err;
    const auto r = testutil::run_cli({"teach", scene.string(), "--algorithm", "scanline-nonzero",
                                      "--against", "gl", "--output", (dir.path() / "gl").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto gl = json::parse(testutil::read_text(dir.path() / "gl" / "teach.json"));
    EXPECT_NE(gl["gl_source"].get<std::string>().find("osmesa"), std::string::npos)
        << gl["gl_source"];
    EXPECT_EQ(gl["gl_rgba"], ref.data["gl_rgba"]);
    EXPECT_EQ(gl["differences"], ref.data["differences"]);
    EXPECT_GT(gl["differences"].size(), 20u);
}

// A scene without what the algorithm draws, an unknown algorithm and a 4x target are usage
// errors (exit 2, one line naming the scene), and nothing is written.
TEST(Teach, RefusesWhatItCannotTeach) {
    testutil::TempDir dir;
    const auto out = dir.path() / "none";
    auto r = testutil::run_cli({"teach", (kSource / "examples/teach/points_circles.json").string(),
                                "--algorithm", "bresenham", "--output", out.string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("points_circles.json: the scene has no line draws"), std::string::npos)
        << r.err;
    EXPECT_EQ(testutil::count_lines(r.err), 1u);
    EXPECT_FALSE(std::filesystem::exists(out / "index.html"));
    r = testutil::run_cli({"teach", (kSource / "examples/teach/lines_fan.json").string(),
                           "--algorithm", "no-such", "--output", out.string()});
    EXPECT_EQ(r.exit_code, 2);
    const auto msaa = dir.write("m.json", R"({"format": "refraster-scene/1",
      "target": {"width": 4, "height": 4, "samples": 4},
      "draws": [{"primitive": "lines", "vertices": [{"position": [0, 0]}, {"position": [4, 1]}]}]})");
    r = testutil::run_cli({"teach", msaa.string(), "--algorithm", "dda", "--output", out.string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("single-sample"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out / "index.html"));
}

// A scene with one draw of `primitive` through `points` on a `w` x `h` target.
std::string one_draw(int w, int h, const std::string& primitive,
                     const std::vector<std::pair<double, double>>& points) {
    json draw{{"primitive", primitive}, {"vertices", json::array()}};
    for (const auto& [x, y] : points) draw["vertices"].push_back({{"position", {x, y}}});
    json scene{{"format", "refraster-scene/1"},
               {"target", {{"width", w}, {"height", h}}},
               {"draws", json::array({draw})}};
    if (primitive == "polygon") scene["requires"] = {"polygons"};
    return scene.dump();
}

// A comb of `teeth` teeth across a `w` x `h` target (2 * teeth + 2 vertices).
std::vector<std::pair<double, double>> comb(int teeth, int w, int h) {
    const double step = (w - 2.0) / (2.0 * teeth);
    std::vector<std::pair<double, double>> c = {{1, 1}, {1 + 2 * teeth * step, 1}};
    for (int i = teeth; i > 0; --i) {
        c.push_back({1 + 2 * i * step, h - 1.0});
        c.push_back({1 + (2 * i - 1) * step, 2});
    }
    return c;
}

// Over a bound of docs/limits.md ("Teaching pages"): one line naming the scene and the JSON path
// (or the option) and the limit, exit 2, before any work, and nothing written.
TEST(Teach, RefusesInputsOverItsBounds) {
    testutil::TempDir dir;
    const auto out = dir.path() / "page";
    const std::vector<std::pair<double, double>> tri = {{0, 0}, {8, 0}, {0, 8}};
    struct Case {
        std::string file, text, algorithm, expected;
        std::vector<std::string> extra;
    };
    const std::vector<Case> cases{
        {"wide.json",
         one_draw(257, 256, "triangles", tri),
         "half-space",
         "wide.json: target: teach draws at most 65536 pixels",
         {}},
        {"sliver.json",
         one_draw(16384, 64, "triangles", tri),
         "flood4",
         "sliver.json: target: teach draws at most 65536 pixels",
         {}},
        {"comb.json",
         one_draw(256, 256, "polygon", comb(512, 256, 256)),
         "ear-clipping",
         "comb.json: draws[0]: \"ear-clipping\" takes at most 1024 vertices",
         {}},
        {"comb2.json",
         one_draw(256, 256, "polygon", comb(2049, 256, 256)),
         "scanline-evenodd",
         "comb2.json: draws[0]: \"scanline-evenodd\" takes at most 4096 vertices",
         {}},
        {"zoom.json",
         one_draw(256, 256, "triangles", tri),
         "half-space",
         "--zoom: 17 makes images of 4352 x 4352 = 18939904 pixels, over the limit of 16777216",
         {"--zoom", "17"}},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.file);
        const auto scene = dir.write(c.file, c.text);
        std::vector<std::string> args{"teach",     scene.string(), "--algorithm",
                                      c.algorithm, "--output",     out.string()};
        args.insert(args.end(), c.extra.begin(), c.extra.end());
        const auto r = testutil::run_cli(args);
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
        EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
    // At the bounds, each runs.
    const auto comb_at =
        dir.write("comb_at.json", one_draw(256, 256, "polygon", comb(511, 256, 256)));
    const auto t = teach(comb_at, "ear-clipping", dir.path() / "at");
    ASSERT_EQ(t.cli.exit_code, 0) << t.cli.err;
    EXPECT_EQ(t.data["width"], 256);
}

// A sliver across the widest target teach takes: the flood fill's seed search tests the
// sliver's box once (there is no pixel inside it, so no seed and no fill) and the run ends.
TEST(Teach, AFloodFillOnASliverEnds) {
    testutil::TempDir dir;
    const auto scene = dir.write(
        "sliver.json",
        one_draw(16384, 4, "triangles", {{0.0, 0.0}, {16384.0, 4.0}, {16384.0, 4.00001}}));
    const auto t = teach(scene, "flood4", dir.path() / "flood");
    ASSERT_EQ(t.cli.exit_code, 0) << t.cli.err;
    for (const auto& note : t.data["notes"])
        EXPECT_EQ(note.get<std::string>().find("seed ("), std::string::npos) << note;
}

// A run with more steps than a page records keeps the first 10,000 and counts the rest in a last
// step and a note; the images and differences are the whole run's.
TEST(Teach, RecordsTheFirstStepsAndCountsTheRest) {
    testutil::TempDir dir;
    // Two triangles over a 256 x 256 target: a half-space step a pixel of each box (131,072+).
    const auto scene = dir.write(
        "full.json", one_draw(256, 256, "triangles",
                              {{0, 0}, {256, 0}, {0, 256}, {256, 0}, {256, 256}, {0, 256}}));
    const auto t = teach(scene, "half-space", dir.path() / "steps");
    ASSERT_EQ(t.cli.exit_code, 0) << t.cli.err;
    ASSERT_EQ(t.data["steps"].size(), 10'001u);
    const std::size_t omitted = t.data["omitted_steps"];
    EXPECT_GT(omitted, 256u * 256u);
    EXPECT_EQ(t.data["steps"].back()["title"],
              std::to_string(omitted) + " more steps not recorded");
    EXPECT_NE(t.cli.out.find("(" + std::to_string(omitted) + " more not recorded)"),
              std::string::npos)
        << t.cli.out;
    // The image is the whole run's: every pixel lit.
    const auto& rgba = t.data["algorithm_rgba"];
    for (std::size_t i = 0; i < rgba.size(); i += 4) ASSERT_EQ(rgba[i], 255) << i / 4;
}

// A recorded step is bounded whatever the input: the scanline fill of a 4,096-vertex comb lists
// the active edges of each row, cut to 240 characters, and draws them, within the run's 65,536
// overlay segments (the rows past them are counted, not recorded).
TEST(Teach, BoundsEachStepsValuesAndTheOverlay) {
    testutil::TempDir dir;
    const auto scene = dir.write("comb.json", one_draw(256, 256, "polygon", comb(2047, 256, 256)));
    const auto out = dir.path() / "scanline";
    const auto t = teach(scene, "scanline-evenodd", out);
    ASSERT_EQ(t.cli.exit_code, 0) << t.cli.err;
    bool cut = false;
    std::size_t segments = 0;
    for (const auto& step : t.data["steps"]) {
        ASSERT_LE(step["state"].size(), 24u);
        for (const auto& kv : step["state"]) {
            const std::string value = kv[1];
            EXPECT_LE(value.size(), 240u + 40u) << value.substr(0, 80);
            cut = cut || value.find(" more characters)") != std::string::npos;
        }
        segments += step["overlay"].size();
    }
    EXPECT_TRUE(cut);
    EXPECT_LE(segments, 65'536u + 4'096u);  // the last step recorded may pass the bound
    EXPECT_GT(t.data["omitted_steps"].get<std::size_t>(), 0u);
}

}  // namespace
