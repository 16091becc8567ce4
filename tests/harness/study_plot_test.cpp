// Tests of the study's figures and tables (study/plot.hpp): the Pareto front of points made by
// hand (ties, dominated points, non-finite points), CSV quoting and numbers read back exactly,
// and the SVG: well-formed, self-contained, every name and label in it escaped, no non-finite
// number, the "0" row of a logarithmic axis, the front's legend entry, empty panels.
//
// Deliberately does not: compare pixels or a whole document; the layout may change, what is
// tested here may not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <regex>
#include <string>
#include <vector>

#include "harness/markup.hpp"
#include "refraster/assert.hpp"
#include "study/plot.hpp"
#include "study/study_common.hpp"
#include "test_util.hpp"

namespace {

using harness::study::CsvTable;
using harness::study::PlotPanel;
using harness::study::PlotPoint;
using harness::study::PlotSeries;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Whether `xml` is one element with properly nested tags, quoted attributes, and no stray
// '<' or '&' in its text: enough of well-formedness to catch what a writer of SVG gets wrong.
// Returns "" when it is, otherwise what is wrong.
std::string xml_problem(const std::string& xml) {
    std::vector<std::string> open;
    bool root_seen = false;
    std::size_t i = 0;
    auto entity_ok = [&](std::size_t at) {
        static const std::regex entity("&(amp|lt|gt|quot|apos|#[0-9]+|#x[0-9a-fA-F]+);");
        const std::size_t end = xml.find(';', at);
        if (end == std::string::npos) return false;
        return std::regex_match(xml.substr(at, end - at + 1), entity);
    };
    while (i < xml.size()) {
        const char c = xml[i];
        if (c == '&') {
            if (!entity_ok(i)) return "a bare '&' at " + std::to_string(i);
            ++i;
            continue;
        }
        if (c != '<') {
            if (open.empty() && !std::isspace(static_cast<unsigned char>(c))) {
                return "text outside the root element at " + std::to_string(i);
            }
            ++i;
            continue;
        }
        if (xml.compare(i, 5, "<?xml") == 0) {
            if (i != 0) return "an XML declaration not at the start";
            const std::size_t end = xml.find("?>", i);
            if (end == std::string::npos) return "an unclosed declaration";
            i = end + 2;
            continue;
        }
        if (xml.compare(i, 4, "<!--") == 0) {
            const std::size_t end = xml.find("-->", i);
            if (end == std::string::npos) return "an unclosed comment";
            i = end + 3;
            continue;
        }
        // A tag: scan to its '>' outside quotes.
        std::size_t j = i + 1;
        char quote = 0;
        for (; j < xml.size(); ++j) {
            const char d = xml[j];
            if (quote != 0) {
                if (d == quote) quote = 0;
                if (d == '<') return "a '<' in an attribute at " + std::to_string(j);
                if (d == '&' && !entity_ok(j)) return "a bare '&' in an attribute";
            } else if (d == '"' || d == '\'') {
                quote = d;
            } else if (d == '>') {
                break;
            } else if (d == '<') {
                return "a '<' inside a tag at " + std::to_string(j);
            }
        }
        if (j >= xml.size()) return "an unclosed tag at " + std::to_string(i);
        const std::string tag = xml.substr(i + 1, j - i - 1);
        const bool closing = !tag.empty() && tag[0] == '/';
        const bool self_closing = !tag.empty() && tag.back() == '/';
        std::string name;
        for (std::size_t k = closing ? 1 : 0; k < tag.size(); ++k) {
            const char d = tag[k];
            if (std::isspace(static_cast<unsigned char>(d)) || d == '/') break;
            name += d;
        }
        if (name.empty()) return "a tag without a name at " + std::to_string(i);
        // Every attribute is name="value" (or with single quotes).
        static const std::regex attrs(
            R"(^/?[A-Za-z_:][-A-Za-z0-9_:.]*)"
            R"((\s+[A-Za-z_:][-A-Za-z0-9_:.]*\s*=\s*("[^"]*"|'[^']*'))*\s*/?$)");
        if (!std::regex_match(tag, attrs)) return "a malformed tag: <" + tag + ">";
        if (closing) {
            if (open.empty() || open.back() != name) return "</" + name + "> closes nothing open";
            open.pop_back();
        } else if (!self_closing) {
            if (open.empty() && root_seen) return "a second root element <" + name + ">";
            root_seen = true;
            open.push_back(name);
        } else if (open.empty()) {
            return "a self-closed root element";
        }
        i = j + 1;
    }
    if (!open.empty()) return "<" + open.back() + "> is never closed";
    if (!root_seen) return "no root element";
    return "";
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

// Each number inside a tag (a coordinate, a size) has at most two decimals.
bool numbers_compact(const std::string& svg) {
    static const std::regex long_decimal("[0-9]\\.[0-9]{3,}");
    static const std::regex tag("<[^>]*>");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), tag); it != std::sregex_iterator();
         ++it) {
        if (std::regex_search(it->str(), long_decimal)) return false;
    }
    return true;
}

// Variants with names and labels that need escaping; one with an exact answer (error 0).
PlotPanel scatter_panel() {
    PlotPanel p;
    p.title = "coverage: error & time";
    p.x_label = "run time per triangle (ns)";
    p.y_label = "mean |error| <pixels>";
    p.log_y = true;
    p.pareto = true;
    PlotSeries snap{"snap <8> & co", {}, false};
    snap.points = {{12.0, 3e-3, "snap-8"}, {14.0, 2e-4, "snap-12"}, {19.0, 1e-5, "snap-16"}};
    PlotSeries fl{"float \"32\"", {}, false};
    fl.points = {{9.0, 0.02, "f32 'fast'"}, {25.0, 4e-4, "f32 slow"}, {kInf, 1e-3, "gone"}};
    PlotSeries exact{"exact", {}, false};
    exact.points = {{60.0, 0.0, "exact"}, {kNaN, 1e-3, "lost"}};
    p.series = {snap, fl, exact};
    return p;
}

// Error against a sweep parameter on log-log axes, with points that cannot be drawn.
PlotPanel curve_panel() {
    PlotPanel p;
    p.title = "area to 0";
    p.x_label = "triangle area";
    p.y_label = "relative error";
    p.log_x = true;
    p.log_y = true;
    PlotSeries a{"llvmpipe", {}, true};
    PlotSeries b{"softpipe", {}, true};
    for (int k = 0; k < 8; ++k) {
        const double area = std::pow(10.0, -k);
        a.points.push_back({area, 1e-7 * std::pow(3.0, k), ""});
        b.points.push_back({area, k == 3 ? kInf : 2e-7 * std::pow(2.5, k), ""});
    }
    b.points.push_back({kNaN, 1.0, ""});
    p.series = {a, b};
    p.x_marks = {{1e-4, "z24 step"}};
    return p;
}

std::string xmllint_problem(const std::string& svg) {
    if (!std::filesystem::exists("/usr/bin/xmllint")) return "";
    const testutil::TempDir dir("plot");
    const auto file = dir.write("figure.svg", svg);
    const std::string cmd =
        "/usr/bin/xmllint --noout " + testutil::shell_quote(file.string()) + " 2>&1";
    const std::string out = testutil::command_output(cmd);
    return out;
}

TEST(StudyPlot, ParetoFrontKeepsTiesAndDropsDominatedAndNonFinitePoints) {
    const std::vector<PlotPoint> points = {
        {1.0, 5.0, "a"},   // 0: fastest finite
        {2.0, 3.0, "b"},   // 1
        {2.0, 3.0, "b'"},  // 2: equal to 1, so both on the front
        {3.0, 3.0, "c"},   // 3: as good as 1 in y, slower
        {4.0, 1.0, "d"},   // 4
        {5.0, 5.0, "e"},   // 5: dominated by everything before it
        {kNaN, 0.0, "n"},  // 6: never on the front, and dominates nothing
        {0.5, kInf, "i"},  // 7: would lead the front if infinities counted
        {4.0, 1.0, "d'"},  // 8: equal to 4
        {6.0, 0.5, "f"},   // 9: slowest, most accurate
        {1.0, 6.0, "g"},   // 10: as fast as 0, worse
    };
    const std::vector<std::size_t> expected = {0, 1, 2, 4, 8, 9};
    EXPECT_EQ(harness::study::pareto_front(points), expected);
}

TEST(StudyPlot, ParetoFrontOfFewPoints) {
    EXPECT_TRUE(harness::study::pareto_front({}).empty());
    EXPECT_EQ(harness::study::pareto_front({{3.0, 4.0, ""}}), std::vector<std::size_t>{0});
    EXPECT_TRUE(harness::study::pareto_front({{kNaN, 1.0, ""}, {1.0, kNaN, ""}}).empty());
    // Ordered by x whatever the input order; -0 and 0 are the same point.
    const std::vector<std::size_t> expected = {2, 1, 0};
    EXPECT_EQ(harness::study::pareto_front({{3.0, 0.0, ""}, {0.0, 1.0, ""}, {-1.0, 2.0, ""}}),
              expected);
    EXPECT_EQ(harness::study::pareto_front({{0.0, 1.0, ""}, {-0.0, 1.0, ""}}).size(), 2u);
}

// A point with the range of its timing rounds (median x, fastest and slowest round).
PlotPoint timed(double error, std::vector<double> rounds, std::string label) {
    const harness::study::Timing t = harness::study::timing_of(std::move(rounds));
    return {t.median, error, std::move(label), t.low, t.high};
}

// Synthetic timings with noise: five variants of one kernel, truly equally fast, whose noisy
// medians happen to fall in the order of their errors. A front on the medians alone would
// hold all five (each faster and worse than the next); a time counts only beyond the spread, so
// the most accurate one beats the rest. A variant faster beyond the spread, or more accurate,
// stays on the front; two of equal error whose ranges overlap both do.
TEST(StudyPlot, ParetoFrontCountsATimeOnlyBeyondItsSpread) {
    const std::vector<double> noise = {0.7, 0.85, 1.0, 1.15, 1.3};
    const auto rounds = [&](double median) {
        std::vector<double> r;
        for (const double n : noise) r.push_back(median * n);
        return r;
    };
    std::vector<PlotPoint> points = {
        timed(6.0, rounds(900.0), "snap-4"),    // 0
        timed(5.0, rounds(950.0), "snap-6"),    // 1
        timed(4.0, rounds(1000.0), "snap-8"),   // 2
        timed(3.0, rounds(1050.0), "snap-10"),  // 3
        timed(1.0, rounds(1100.0), "snap-16"),  // 4: the most accurate of the five
    };
    // On the medians alone every one of them would be on the front.
    std::vector<PlotPoint> medians = points;
    for (PlotPoint& p : medians) p.x_low = p.x_high = kNaN;
    EXPECT_EQ(harness::study::pareto_front(medians).size(), 5u);
    EXPECT_EQ(harness::study::pareto_front(points), std::vector<std::size_t>{4});

    points.push_back(timed(7.0, {480.0, 500.0, 510.0, 515.0, 520.0}, "fast"));        // 5
    points.push_back(timed(0.0, {4900.0, 5000.0, 5010.0, 5050.0, 5100.0}, "exact"));  // 6
    points.push_back(timed(1.0, rounds(1150.0), "snap-16 again"));                    // 7
    points.push_back(timed(1.0, {1300.0, 1310.0, 1320.0, 1330.0, 1340.0}, "slow"));   // 8
    // 8 is as accurate as 4 and 7 and slower than 4 beyond the spread.
    const std::vector<std::size_t> expected = {5, 4, 7, 6};
    EXPECT_EQ(harness::study::pareto_front(points), expected);
}

// The colours that the markers of `svg` are drawn in, in order: a marker is filled with its
// series' colour and outlined in white.
std::vector<std::string> marker_colours(const std::string& svg) {
    static const std::regex marker("fill=\"(#[0-9a-f]{6})\" stroke=\"#ffffff\"");
    std::vector<std::string> out;
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), marker);
         it != std::sregex_iterator(); ++it)
        out.push_back((*it)[1].str());
    return out;
}

// One series name, one colour: "b" is the second series of the first panel and the only one
// of the second, and keeps its colour; with a shared legend the names are listed once.
TEST(StudyPlot, ASeriesKeepsItsColourInEveryPanel) {
    PlotPanel one{"one", "x", "y", false, false, {}, false, {}};
    one.series.push_back({"a", {{1.0, 1.0, ""}}, false});
    one.series.push_back({"b", {{2.0, 2.0, ""}}, false});
    PlotPanel two{"two", "x", "y", false, false, {}, false, {}};
    two.series.push_back({"b", {{3.0, 3.0, ""}}, false});
    for (const auto legend : {harness::study::Legend::PerPanel, harness::study::Legend::Shared}) {
        const std::string svg = harness::study::svg_figure("colours", {one, two}, 2, legend);
        const std::string first = svg.substr(0, svg.find(">two<"));
        const std::string second = svg.substr(svg.find(">two<"));
        const auto c1 = marker_colours(first);
        const auto c2 = marker_colours(second);
        ASSERT_GE(c1.size(), 2u);
        ASSERT_GE(c2.size(), 1u);
        EXPECT_NE(c1[c1.size() - 2], c1.back());  // a and b differ
        EXPECT_EQ(c2.front(), c1.back());         // b is b everywhere
        if (legend == harness::study::Legend::Shared) {
            EXPECT_EQ(std::count(c1.begin(), c1.end(), c1.back()) +
                          std::count(c2.begin(), c2.end(), c1.back()),
                      3);  // the legend's sample of b, and b's two points
        }
    }
}

// However many panels and however long their legends, a figure is at most a page wide: its
// panels stack into fewer columns.
TEST(StudyPlot, AFigureFitsAPage) {
    std::vector<PlotPanel> panels;
    for (int i = 0; i < 4; ++i) {
        PlotPanel p{"panel " + std::to_string(i), "x", "y", false, false, {}, false, {}};
        for (int s = 0; s < 3; ++s)
            p.series.push_back({"a rather long series name number " + std::to_string(s),
                                {{1.0 + s, 2.0, ""}},
                                false});
        panels.push_back(std::move(p));
    }
    for (const auto legend : {harness::study::Legend::PerPanel, harness::study::Legend::Shared}) {
        const std::string svg = harness::study::svg_figure("wide", panels, 3, legend);
        const auto w = svg.find(" width=\"");
        ASSERT_NE(w, std::string::npos);
        EXPECT_LE(std::stod(svg.substr(w + 8)), harness::study::kMaxFigureWidth);
        EXPECT_EQ(xml_problem(svg), "");
    }
}

TEST(StudyPlot, CsvQuotesCellsWithCommasQuotesAndLineBreaks) {
    CsvTable t({"variant", "error, max", "note"});
    EXPECT_EQ(t.text(), "variant,\"error, max\",note\n");
    t.add_row({"snap-8", "0.5", "say \"hi\""});
    t.add_row({"two\nlines", "cr\rhere", ""});
    t.add_row({"\"", ",", "plain;text 'quoted'"});
    EXPECT_EQ(t.rows(), 3u);
    EXPECT_EQ(t.text(),
              "variant,\"error, max\",note\n"
              "snap-8,0.5,\"say \"\"hi\"\"\"\n"
              "\"two\nlines\",\"cr\rhere\",\n"
              "\"\"\"\",\",\",plain;text 'quoted'\n");
}

TEST(StudyPlotDeathTest, ARowOfTheWrongLengthIsAsserted) {
    if (!refraster::kAssertions) GTEST_SKIP() << "assertions are off in this build";
    CsvTable t({"a", "b"});
    EXPECT_DEATH(t.add_row({"1"}), "one cell per column");
    EXPECT_DEATH(t.add_row({"1", "2", "3"}), "one cell per column");
}

TEST(StudyPlot, CsvNumbersReadBackExactly) {
    for (double v : {0.1, 1e-300, 12345.0, -3.0, std::ldexp(1.0, 60), 1.0 / 3.0, -2.5e-7,
                     std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::max(),
                     std::ldexp(1.0, 53) - 1.0}) {
        const std::string text = harness::study::csv_number(v);
        char* end = nullptr;
        const double back = std::strtod(text.c_str(), &end);
        EXPECT_EQ(back, v) << text;
        EXPECT_EQ(*end, '\0') << text;
    }
    EXPECT_EQ(harness::study::csv_number(0.1), "0.1");
    EXPECT_EQ(harness::study::csv_number(1e-300), "1e-300");
    EXPECT_EQ(harness::study::csv_number(12345.0), "12345");
    EXPECT_EQ(harness::study::csv_number(-3.0), "-3");
    EXPECT_EQ(harness::study::csv_number(0.0), "0");
    EXPECT_EQ(harness::study::csv_number(-0.0), "0");
    EXPECT_EQ(harness::study::csv_number(1e15), "1000000000000000");
    EXPECT_EQ(harness::study::csv_number(kInf), "inf");
    EXPECT_EQ(harness::study::csv_number(-kInf), "-inf");
    // Past 2^53 a whole double is printed shortest: all its digits where that is shorter than
    // an exponent.
    EXPECT_EQ(harness::study::csv_number(std::ldexp(1.0, 60)), "1152921504606846976");
    EXPECT_EQ(harness::study::csv_number(1e300), "1e+300");
}

TEST(StudyPlotDeathTest, ACsvNumberIsNotNaN) {
    if (!refraster::kAssertions) GTEST_SKIP() << "assertions are off in this build";
    EXPECT_DEATH((void)harness::study::csv_number(kNaN), "not NaN");
}

TEST(StudyPlot, TheFigureIsSelfContainedWellFormedSvg) {
    PlotPanel empty;
    empty.title = "nothing measured";
    empty.series = {PlotSeries{"unmeasured", {{kNaN, kNaN, "x"}}, false}};
    const std::string svg = harness::study::svg_figure("precision <study> & \"friends\"",
                                                       {scatter_panel(), curve_panel(), empty}, 2);

    EXPECT_EQ(xml_problem(svg), "");
    EXPECT_EQ(xmllint_problem(svg), "");
    EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
    EXPECT_TRUE(contains(svg, "xmlns=\"http://www.w3.org/2000/svg\""));
    EXPECT_TRUE(contains(svg, "viewBox=\"0 0 "));
    EXPECT_TRUE(contains(svg, "font-family=\"sans-serif\""));
    EXPECT_FALSE(contains(svg, "<script"));
    EXPECT_FALSE(contains(svg, "href"));
    EXPECT_FALSE(contains(svg, "url("));
    EXPECT_TRUE(contains(svg, harness::markup::escape("precision <study> & \"friends\"")));
    EXPECT_TRUE(numbers_compact(svg));

    // Every series in a legend and every drawable label beside its point.
    for (const PlotPanel& p : {scatter_panel(), curve_panel(), empty}) {
        EXPECT_TRUE(contains(svg, ">" + harness::markup::escape(p.title) + "</text>")) << p.title;
        for (const PlotSeries& s : p.series) {
            EXPECT_TRUE(contains(svg, ">" + harness::markup::escape(s.name) + "</text>")) << s.name;
        }
    }
    for (const char* label : {"snap-8", "snap-12", "snap-16", "f32 'fast'", "f32 slow", "exact"}) {
        EXPECT_TRUE(contains(svg, ">" + harness::markup::escape(label) + "</text>")) << label;
    }
    // The points without an x are not drawn, nor their labels.
    EXPECT_FALSE(contains(svg, ">lost</text>"));
    EXPECT_FALSE(contains(svg, ">gone</text>"));
    EXPECT_TRUE(contains(svg, ">z24 step</text>"));
    EXPECT_TRUE(contains(svg, ">Pareto front</text>"));
    EXPECT_TRUE(contains(svg, ">no data</text>"));

    const std::string folded = lower(svg);
    EXPECT_FALSE(contains(folded, "nan"));
    EXPECT_FALSE(contains(folded, "inf"));
}

TEST(StudyPlot, ALogarithmicAxisDrawsZeroOnARowOfItsOwn) {
    const PlotPanel with_zero = scatter_panel();
    const std::string svg = harness::study::svg_figure("f", {with_zero});
    EXPECT_EQ(xml_problem(svg), "");
    // Decades from 1e-5 to 0.01, labelled as round numbers, and the "0" row below them.
    EXPECT_TRUE(contains(svg, ">1e-5</text>"));
    EXPECT_TRUE(contains(svg, ">0.001</text>"));
    EXPECT_TRUE(contains(svg, ">0.01</text>"));
    EXPECT_TRUE(contains(svg, ">0</text>"));

    // Without the zero there is no such row (the linear x axis starts well above 0).
    PlotPanel positive = with_zero;
    positive.series.pop_back();
    EXPECT_FALSE(contains(harness::study::svg_figure("f", {positive}), ">0</text>"));

    // A negative value shares the row, which then says so.
    PlotPanel negative = positive;
    negative.series.push_back(PlotSeries{"below", {{30.0, -1.0, "neg"}}, false});
    const std::string neg_svg = harness::study::svg_figure("f", {negative});
    EXPECT_TRUE(contains(neg_svg,
                         ">\xE2\x89\xA4"
                         "0</text>"));
    EXPECT_TRUE(contains(neg_svg, ">neg</text>"));
}

TEST(StudyPlot, TheFrontIsMarkedOnlyWhenAsked) {
    PlotPanel p = scatter_panel();
    EXPECT_TRUE(contains(harness::study::svg_figure("f", {p}), "Pareto front"));
    // The front is drawn as a dashed staircase of horizontal and vertical steps.
    EXPECT_TRUE(std::regex_search(harness::study::svg_figure("f", {p}),
                                  std::regex("<path d=\"M[-0-9.,]+( H[-0-9.]+ V[-0-9.]+)+\"")));
    p.pareto = false;
    EXPECT_FALSE(contains(harness::study::svg_figure("f", {p}), "Pareto front"));
}

std::size_t count(const std::string& haystack, const std::string& needle) {
    std::size_t n = 0;
    for (std::size_t at = haystack.find(needle); at != std::string::npos;
         at = haystack.find(needle, at + 1)) {
        ++n;
    }
    return n;
}

TEST(StudyPlot, CurvesBreakWhereAValueCannotBeDrawnAndScattersAreNotJoined) {
    // llvmpipe in one piece, softpipe in two around its infinity; its NaN at the end is dropped.
    EXPECT_EQ(count(harness::study::svg_figure("f", {curve_panel()}), "<polyline"), 3u);
    EXPECT_EQ(count(harness::study::svg_figure("f", {scatter_panel()}), "<polyline"), 0u);
}

TEST(StudyPlot, LabelsOfPointsInOnePlaceDoNotOverlap) {
    PlotPanel p;
    p.title = "crowd";
    PlotSeries s{"crowd", {}, false};
    for (const char* label : {"first", "second", "third", "fourth"}) {
        s.points.push_back({1.0, 1.0, label});
    }
    s.points.push_back({2.0, 2.0, "apart"});
    p.series = {s};
    const std::string svg = harness::study::svg_figure("f", {p});
    // The point is at the plot area's left edge, so its labels are all right of it, where no
    // two may share a line.
    std::vector<double> rows;
    for (const char* label : {"first", "second", "third", "fourth"}) {
        const std::regex text(std::string("<text x=\"([-0-9.]+)\" y=\"([-0-9.]+)\"[^>]*>") + label +
                              "</text>");
        std::smatch m;
        ASSERT_TRUE(std::regex_search(svg, m, text)) << label;
        rows.push_back(std::stod(m[2].str()));
    }
    for (std::size_t i = 0; i < rows.size(); ++i) {
        for (std::size_t j = i + 1; j < rows.size(); ++j) {
            EXPECT_GE(std::fabs(rows[i] - rows[j]), 10.0) << i << " " << j;
        }
    }
}

TEST(StudyPlot, DegenerateRangesStillGiveAValidFigure) {
    PlotPanel one;
    one.title = "one point";
    one.series = {PlotSeries{"only", {{3.0, 3.0, "here"}}, false}};
    PlotPanel equal;
    equal.title = "equal";
    equal.log_x = true;
    equal.log_y = true;
    equal.series = {PlotSeries{"flat", {{1e-3, 5.0, ""}, {1e-3, 5.0, ""}, {1e-3, 5.0, ""}}, true}};
    PlotPanel zeros;
    zeros.title = "zeros";
    zeros.log_y = true;
    zeros.series = {PlotSeries{"exact", {{0.0, 0.0, "z"}, {1.0, 0.0, "z"}}, true}};
    PlotPanel huge;
    huge.title = "huge";
    huge.series = {
        PlotSeries{"far", {{-1e308, 1e308, "f"}, {1e308, -1e308, "g"}, {1.0, 1.0, "h"}}, false}};
    const std::string svg = harness::study::svg_figure("degenerate", {one, equal, zeros, huge}, 3);
    EXPECT_EQ(xml_problem(svg), "");
    EXPECT_EQ(xmllint_problem(svg), "");
    const std::string folded = lower(svg);
    EXPECT_FALSE(contains(folded, "nan"));
    EXPECT_FALSE(contains(folded, "inf"));
    EXPECT_TRUE(numbers_compact(svg));
    EXPECT_TRUE(contains(svg, ">here</text>"));
    EXPECT_TRUE(contains(svg, ">h</text>"));
    // Every panel has a point to draw; only the figure without panels says "no data".
    EXPECT_FALSE(contains(svg, "no data"));
    EXPECT_TRUE(contains(harness::study::svg_figure("empty", {}), ">no data</text>"));
    EXPECT_EQ(xml_problem(harness::study::svg_figure("empty", {}, 0)), "");
}

}  // namespace
