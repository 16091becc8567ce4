// `refraster study` end to end in --quick mode: each study writes its table, figure and summary,
// and bad requests are refused with the bad-input exit code.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "test_util.hpp"

namespace {

std::size_t count_lines(const std::string& s) {
    return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

TEST(StudyCli, EachStudyWritesItsOutputs) {
    testutil::TempDir dir;
    const std::vector<std::pair<std::string, std::string>> studies{
        {"precision", "study,family,seed,variant,"},
        {"antialiasing", "study,family,seed,samples,pattern,filter,"},
        {"stability", "study,sweep,seed,parameter,variant,metric,value"}};
    for (const auto& [name, header] : studies) {
        SCOPED_TRACE(name);
        const auto out = dir.path() / name;
        const auto r = testutil::run_cli(
            {"study", name, "--quick", "--quiet", "--seed", "7", "--output", out.string()});
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const std::string csv = testutil::read_text(out / "study.csv");
        EXPECT_EQ(csv.rfind(header, 0), 0u) << csv.substr(0, 200);
        EXPECT_GT(count_lines(csv), 5u);
        EXPECT_NE(csv.find(",7,"), std::string::npos);  // the seed on every row
        const std::string svg = testutil::read_text(out / "study.svg");
        EXPECT_NE(svg.find("<svg"), std::string::npos);
        EXPECT_NE(svg.find("</svg>"), std::string::npos);
        EXPECT_EQ(svg.find("nan"), std::string::npos);
        if (name != "stability") {
            EXPECT_NE(svg.find("Pareto front"), std::string::npos);
        }
        const std::string md = testutil::read_text(out / "summary.md");
        EXPECT_NE(md.find("refraster study " + name), std::string::npos);
        EXPECT_NE(md.find("--seed 7 --quick"), std::string::npos);
        EXPECT_FALSE(r.out.empty());
        // summary.md opens with the decision table and the conclusions; the provenance and
        // every number follow.
        const auto decisions = md.find("## Decisions\n\n");
        const auto conclusions = md.find("## Conclusions\n\n- ");
        const auto provenance = md.find("## Provenance");
        ASSERT_NE(decisions, std::string::npos) << md;
        ASSERT_NE(conclusions, std::string::npos) << md;
        EXPECT_LT(decisions, conclusions);
        EXPECT_LT(conclusions, provenance);
        // The figure fits a page: its width attribute is at most 1000 px.
        const auto w = svg.find(" width=\"");
        ASSERT_NE(w, std::string::npos);
        EXPECT_LE(std::stod(svg.substr(w + 8)), 1000.0) << svg.substr(w, 40);
        // Laid out by Chromium: nothing past a 1,280 px window, no two text boxes overlapping.
        const auto page = out / "figure.html";
        std::ofstream(page) << "<!DOCTYPE html><html><body style=\"margin:8px\">"
                            << svg.substr(svg.find("<svg")) << "</body></html>\n";
        const std::string probe = testutil::layout_probe(page, dir.path() / "chrome");
        ASSERT_NE(probe, "no probe") << "(is the chromium package installed?)";
        EXPECT_NE(probe.find("outside=0 "), std::string::npos) << probe;
        EXPECT_NE(probe.find("overlaps=0 "), std::string::npos) << probe;
    }
}

TEST(StudyCli, RefusesBadRequests) {
    testutil::TempDir dir;
    const auto file = dir.write("not-a-dir", "x");
    auto r = testutil::run_cli({"study", "precision", "--quick", "--output", file.string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("not a directory"), std::string::npos) << r.err;
    EXPECT_EQ(testutil::read_text(file), "x");
    r = testutil::run_cli({"study", "speed", "--output", (dir.path() / "o").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "o"));
}

}  // namespace
