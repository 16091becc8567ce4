// Tests of the teaching page (harness/teach_page.hpp): its text as written (the data embedded
// once and safely, nothing referred to outside the file, the controls, the differences, the
// notes and the command), and the page in headless Chromium (a link opens at a step, the
// buttons and the keys step, a pixel link shows its reason, stepping redraws the algorithm's
// image and nothing else).
//
// Deliberately does not: test the `teach` command or any textbook algorithm; the documents here
// are written by hand.
#include "harness/teach_page.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/image_io.hpp"
#include "test_util.hpp"

namespace {

using nlohmann::json;

// A width x height target of black pixels; `lit` pixels white.
json image(int width, int height, const std::vector<std::pair<int, int>>& lit) {
    std::vector<int> rgba(static_cast<std::size_t>(width * height * 4), 0);
    for (std::size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;
    for (const auto& [x, y] : lit) {
        for (std::size_t k = 0; k < 3; ++k)
            rgba[static_cast<std::size_t>((y * width + x) * 4) + k] = 255;
    }
    return json(rgba);
}

// A document as `teach` writes it: a width x height target, `step_count` steps, step k lighting
// row 2 + 2k from x = 1 to width - 2 (and rejecting the pixel above its first), and two
// differences, one reason holding "</script>".
json document(int width, int height, int step_count) {
    json steps = json::array();
    std::vector<std::pair<int, int>> lit;
    for (int k = 0; k < step_count; ++k) {
        const int y = 2 + 2 * k;
        json pixels = json::array();
        for (int x = 1; x < width - 1; ++x) {
            pixels.push_back({x, y, 1.0});
            lit.emplace_back(x, y);
        }
        pixels.push_back({1, y + 1, 0.0});
        steps.push_back(
            {{"title", "row " + std::to_string(y) + ": fill the span, step " + std::to_string(k)},
             {"group", k < 2 ? "polygon 0" : "polygon 1"},
             {"line", k == 0 ? 1 : 2},
             {"state", json::array({json::array({"y", std::to_string(y)}),
                                    json::array({"span", "1.." + std::to_string(width - 2)})})},
             {"pixels", pixels},
             {"overlay",
              {{{"x0", 0.5},
                {"y0", y + 0.5},
                {"x1", width - 0.5},
                {"y1", y + 0.5},
                {"role", "span"}}}}});
    }
    std::vector<std::pair<int, int>> gl = lit;
    gl.erase(gl.begin());   // (1, 2): the algorithm's only
    gl.emplace_back(0, 2);  // (0, 2): GL's only
    return {
        {"algorithm", "scanline_even_odd"},
        {"title", "Scanline polygon fill (even-odd)"},
        {"scene", "teach.tiny"},
        {"scene_file", "examples/teach/tiny.json"},
        {"width", width},
        {"height", height},
        {"gl_source", "the reference rasterizer, profile llvmpipe-22.3"},
        {"algorithm_rgba", image(width, height, lit)},
        {"gl_rgba", image(width, height, gl)},
        {"differences",
         {{{"x", 1},
           {"y", 2},
           {"algorithm", 1.0},
           {"gl", false},
           {"reason", "the span starts at the edge's pixel, GL at the first centre inside"}},
          {{"x", 0},
           {"y", 2},
           {"algorithm", 0.0},
           {"gl", true},
           {"reason", "GL's tie rule </script><b>lights</b> it & more"}}}},
        {"summary", "2 pixels differ: 1 lit by the fill only, 1 by GL only"},
        {"input",
         {{{"x0", 0.5}, {"y0", 1.5}, {"x1", width - 1.5}, {"y1", height - 2.5}, {"role", "edge"}}}},
        {"steps", steps},
        {"pseudo_code", {"build the edge table", "fill the row's spans <between> crossings"}},
        {"notes", {"Spans are filled between edge crossings at pixel centres."}}};
}

std::size_t count(const std::string& s, const std::string& what) {
    std::size_t n = 0;
    for (auto at = s.find(what); at != std::string::npos; at = s.find(what, at + what.size())) ++n;
    return n;
}

// The data element's text, and the page with that text cut out.
struct Split {
    std::string data;
    std::string rest;
};
Split split_data(const std::string& html) {
    const std::string open = "<script type=\"application/json\" id=\"teach-data\">";
    const auto begin = html.find(open);
    if (begin == std::string::npos) return {};
    const auto text = begin + open.size();
    const auto end = html.find("</script>", text);
    if (end == std::string::npos) return {};
    return {html.substr(text, end - text), html.substr(0, text) + html.substr(end)};
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

TEST(TeachPage, EmbedsTheDataOnceAndNothingInItEndsTheElement) {
    const json data = document(8, 8, 3);
    const std::string html = harness::teach_page_html(data);
    EXPECT_EQ(count(html, "id=\"teach-data\""), 1u);
    const Split s = split_data(html);
    ASSERT_FALSE(s.data.empty());
    // The element ends at its own closing tag: the text up to the first "</script>" after it is
    // the whole document, and holds no '<' at all (so no "</script", "<!--" in any case).
    EXPECT_EQ(json::parse(s.data), data);
    EXPECT_EQ(s.data.find('<'), std::string::npos);
    EXPECT_NE(s.data.find("\\u003c/script\\u003e"), std::string::npos);
    // Written as text elsewhere, the same reason is HTML-escaped.
    EXPECT_NE(
        s.rest.find("GL&#39;s tie rule &lt;/script&gt;&lt;b&gt;lights&lt;/b&gt; it &amp; more"),
        std::string::npos);
    EXPECT_EQ(s.rest.find("</script><b>"), std::string::npos);
}

TEST(TeachPage, RefersToNothingOutsideTheFile) {
    const std::string rest = lower(split_data(harness::teach_page_html(document(8, 8, 3))).rest);
    ASSERT_FALSE(rest.empty());
    EXPECT_EQ(rest.find("http"), std::string::npos);
    for (const char* ref : {" src=", "<link", "@import", "url(", "fetch(", "xmlhttprequest",
                            "@font-face", "<iframe", "<img"}) {
        EXPECT_EQ(rest.find(ref), std::string::npos) << ref;
    }
    EXPECT_EQ(count(rest, "<script"), 2u);  // the data and the page's own script
}

TEST(TeachPage, HoldsTheViewsAndTheStepControls) {
    const std::string html = harness::teach_page_html(document(8, 8, 3));
    for (const char* id :
         {"step-first",   "step-prev",     "step-next",   "step-last",  "step-index",
          "step-title",   "step-number",   "step-count",  "step-state", "zoom",
          "step-mode",    "img-algorithm", "img-gl",      "img-mask",   "pixel-readout",
          "pixel-reason", "mask-legend",   "differences", "notes",      "command"}) {
        EXPECT_EQ(count(html, std::string("id=\"") + id + "\""), 1u) << id;
    }
    // Before any script runs: step 0 of 3, its title, the zoom that makes 8 pixels 256.
    EXPECT_NE(html.find("id=\"step-index\">0<"), std::string::npos);
    EXPECT_NE(html.find("id=\"step-count\">3<"), std::string::npos);
    EXPECT_NE(html.find("id=\"step-title\">row 2: fill the span, step 0<"), std::string::npos);
    EXPECT_NE(html.find("id=\"zoom\" type=\"range\" min=\"1\" max=\"32\" value=\"32\""),
              std::string::npos);
    EXPECT_NE(harness::teach_page_html(document(32, 32, 1)).find("max=\"32\" value=\"8\""),
              std::string::npos);
    // The mask legend names every class.
    for (const char* cls : {"lit by the algorithm only", "lit by GL only",
                            "partial weights that differ", "equal (dark grey"}) {
        EXPECT_NE(html.find(cls), std::string::npos) << cls;
    }
}

TEST(TeachPage, ListsTheDifferencesOrSaysThereAreNone) {
    const std::string html = harness::teach_page_html(document(8, 8, 3));
    EXPECT_EQ(count(html, "<tr class=\"diff\""), 2u);
    EXPECT_NE(html.find("data-x=\"1\" data-y=\"2\"><td class=\"num\">1</td><td "
                        "class=\"num\">2</td><td class=\"num\">1</td><td>not lit</td>"),
              std::string::npos);
    EXPECT_NE(html.find("data-x=\"0\" data-y=\"2\"><td class=\"num\">0</td><td "
                        "class=\"num\">2</td><td class=\"num\">0</td><td>lit</td>"),
              std::string::npos);
    EXPECT_EQ(html.find("No pixel differs"), std::string::npos);

    json same = document(8, 8, 3);
    same["differences"] = json::array();
    const std::string none = harness::teach_page_html(same);
    EXPECT_EQ(count(none, "<tr class=\"diff\""), 0u);
    EXPECT_NE(none.find("id=\"no-differences\">No pixel differs"), std::string::npos);
}

TEST(TeachPage, NamesTheSceneTheSourceTheNotesAndTheCommand) {
    json data = document(8, 8, 3);
    const std::string html = harness::teach_page_html(data);
    EXPECT_NE(html.find("<code id=\"scene\">teach.tiny</code>"), std::string::npos);
    EXPECT_NE(html.find("the reference rasterizer, profile llvmpipe-22.3"), std::string::npos);
    EXPECT_NE(html.find("id=\"summary\">2 pixels differ: 1 lit by the fill only, 1 by GL only<"),
              std::string::npos);
    EXPECT_NE(html.find("<li>Spans are filled between edge crossings at pixel centres.</li>"),
              std::string::npos);
    EXPECT_NE(html.find("refraster teach examples/teach/tiny.json --algorithm scanline_even_odd "
                        "--output <span id=\"command-dir\">DIR</span>"),
              std::string::npos);
    // A file name a shell would split is quoted.
    data["scene_file"] = "my scenes/it's.json";
    EXPECT_NE(harness::teach_page_html(data).find(
                  "refraster teach &#39;my scenes/it&#39;\\&#39;&#39;s.json&#39;"),
              std::string::npos);
}

TEST(TeachPage, AcceptsAnOrderedDocumentAndAPartialOne) {
    const nlohmann::ordered_json ordered = document(8, 8, 3);
    const std::string html = harness::teach_page_html(ordered);
    EXPECT_EQ(json::parse(split_data(html).data), document(8, 8, 3));
    // Fields missing or of the wrong type draw as empty, never throw.
    const std::string bare = harness::teach_page_html(json{{"title", "t"}, {"steps", 3}});
    EXPECT_NE(bare.find("This algorithm recorded no steps."), std::string::npos);
    EXPECT_NE(bare.find("id=\"no-differences\""), std::string::npos);
    EXPECT_NO_THROW(harness::teach_page_html(json::array()));
}

// Headless Chromium.

std::string chromium(const testutil::TempDir& dir) {
    return "timeout 120 chromium --headless --no-sandbox --disable-gpu --no-first-run "
           "--disable-background-networking --disable-component-update --disable-sync "
           "--user-data-dir=" +
           testutil::shell_quote((dir.path() / "chrome").string()) +
           " --virtual-time-budget=2000 --window-size=1200,900 --hide-scrollbars ";
}

std::string url(const std::filesystem::path& page, const std::string& hash) {
    return testutil::shell_quote("file://" + page.string() + "#" + hash);
}

std::string dump_dom(const testutil::TempDir& dir, const std::filesystem::path& page,
                     const std::string& hash) {
    return testutil::command_output(chromium(dir) + "--dump-dom " + url(page, hash) +
                                    " 2>/dev/null");
}

// The text of the element with id `id` up to its first '<'.
std::string text_of(const std::string& dom, const std::string& id) {
    const std::string tag = "id=\"" + id + "\"";
    const auto at = dom.find(tag);
    if (at == std::string::npos) return "<missing>";
    const auto begin = dom.find('>', at);
    return dom.substr(begin + 1, dom.find('<', begin) - begin - 1);
}

// An attribute of the element with id `id`.
std::string attribute(const std::string& dom, const std::string& id, const std::string& name) {
    const auto at = dom.find("id=\"" + id + "\"");
    if (at == std::string::npos) return "";
    const auto open = dom.rfind('<', at), close = dom.find('>', at);
    const auto a = dom.find(" " + name + "=\"", open);
    if (a == std::string::npos || a > close) return "";
    const auto v = a + name.size() + 3;
    return dom.substr(v, dom.find('"', v) - v);
}

class TeachPageChromium : public ::testing::Test {
  protected:
    void SetUp() override {
        data_ = document(16, 16, 5);
        page_ = dir_.write("index.html", harness::teach_page_html(data_));
    }
    std::string title(std::size_t k) const { return data_["steps"][k]["title"].get<std::string>(); }
    std::string dom(const std::string& hash) const {
        const std::string d = dump_dom(dir_, page_, hash);
        EXPECT_NE(d.find("data-ready=\"1\""), std::string::npos)
            << "the page's script did not finish at #" << hash
            << " (is the chromium package installed?)";
        return d;
    }
    testutil::TempDir dir_{"teach-page"};
    json data_;
    std::filesystem::path page_;
};

// #step=K opens the page's Step K, counted from 1 as the page counts (step=0 and 1 both open the
// first; before, #step=K was the 0-based index and opened Step K+1).
TEST_F(TeachPageChromium, TheHashOpensAtAStep) {
    std::string d = dom("step=1");
    EXPECT_EQ(text_of(d, "step-index"), "0");
    EXPECT_EQ(text_of(d, "step-title"), title(0));
    EXPECT_EQ(text_of(d, "step-number"), "1");
    EXPECT_NE(d.find("<td>span</td><td>1..14</td>"), std::string::npos);  // the state table
    EXPECT_EQ(text_of(dom("step=0"), "step-index"), "0");
    d = dom("step=3");
    EXPECT_EQ(text_of(d, "step-number"), "3");
    EXPECT_EQ(text_of(d, "step-index"), "2");
    EXPECT_EQ(text_of(d, "step-title"), title(2));
    EXPECT_NE(d.find("<td>y</td><td>6</td>"), std::string::npos);
    d = dom("step=99");  // past the end: the last step
    EXPECT_EQ(text_of(d, "step-index"), "4");
}

TEST_F(TeachPageChromium, ButtonsAndKeysStep) {
    std::string d = dom("press=next,next,ArrowRight");
    EXPECT_EQ(text_of(d, "step-index"), "3");
    EXPECT_EQ(text_of(d, "step-title"), title(3));
    d = dom("press=last,prev");
    EXPECT_EQ(text_of(d, "step-index"), "3");  // n - 2
    EXPECT_EQ(text_of(d, "step-title"), title(3));
    d = dom("step=3&press=End,ArrowLeft,ArrowLeft,Home,next");
    EXPECT_EQ(text_of(d, "step-index"), "1");
    EXPECT_EQ(text_of(d, "step-title"), title(1));
    d = dom("press=first,prev,prev");  // clamped at the first step
    EXPECT_EQ(text_of(d, "step-index"), "0");
}

// Stepping a part at a time (the steps' groups: a segment, a polygon), by button and by key,
// and playing to the last step.
TEST_F(TeachPageChromium, PartsAndPlayStep) {
    std::string d = dom("press=part-next");
    EXPECT_EQ(text_of(d, "step-index"), "2");
    EXPECT_EQ(text_of(d, "step-part"), "polygon 1: steps 3 to 5 (part 2 of 2)");
    d = dom("press=End,PageUp");  // to the start of the part
    EXPECT_EQ(text_of(d, "step-index"), "2");
    d = dom("press=End,PageUp,PageUp");  // and to the previous part's
    EXPECT_EQ(text_of(d, "step-index"), "0");
    EXPECT_EQ(text_of(d, "step-part"), "polygon 0: steps 1 to 2 (part 1 of 2)");
    d = dom("press=PageDown,PageDown");  // no part after the last
    EXPECT_EQ(text_of(d, "step-index"), "2");
    // Played at 60 steps a second, the page reaches the last step within Chromium's virtual
    // time and stops there.
    d = dom("speed=60&press=play");
    EXPECT_EQ(text_of(d, "step-index"), "4");
    EXPECT_EQ(text_of(d, "step-play"), "Play");
    EXPECT_EQ(attribute(d, "step-slider", "max"), "5");
}

// The pseudo-code beside the steps, the current step's line highlighted.
TEST_F(TeachPageChromium, ThePseudoCodeHighlightsTheStepsLine) {
    const auto current = [](const std::string& d) {
        const auto at = d.find("<li class=\"current\"><code>");
        if (at == std::string::npos) return std::string("<none>");
        const auto text = at + std::string("<li class=\"current\"><code>").size();
        return d.substr(text, d.find('<', text) - text);
    };
    EXPECT_EQ(current(dom("step=1")), "build the edge table");
    EXPECT_EQ(current(dom("step=3")), "fill the row's spans &lt;between&gt; crossings");
    EXPECT_EQ(current(dom("press=next")), "fill the row's spans &lt;between&gt; crossings");
}

TEST_F(TeachPageChromium, APixelLinkShowsItsValuesAndReason) {
    const std::string d = dom("pixel=0,2");
    EXPECT_NE(text_of(d, "pixel-readout")
                  .find("pixel (0, 2): algorithm rgba(0, 0, 0, 255), weight 0; GL rgba(255, "
                        "255, 255, 255), lit"),
              std::string::npos)
        << text_of(d, "pixel-readout");
    EXPECT_EQ(text_of(d, "pixel-reason"),
              "GL's tie rule &lt;/script&gt;&lt;b&gt;lights&lt;/b&gt; it &amp; more");
    EXPECT_NE(d.find("<tr class=\"diff selected\" tabindex=\"0\" data-index=\"1\""),
              std::string::npos);
}

// Crops the screenshot to an element's rectangle "left,top,width,height" (from its data-rect),
// inset by 2 screen pixels; rows top first.
std::vector<std::uint8_t> crop(const refraster::Framebuffer& shot, const std::string& rect) {
    int r[4] = {0, 0, 0, 0};
    if (std::sscanf(rect.c_str(), "%d,%d,%d,%d", &r[0], &r[1], &r[2], &r[3]) != 4) return {};
    std::vector<std::uint8_t> out;
    for (int y = r[1] + 2; y < r[1] + r[3] - 2; ++y) {
        for (int x = r[0] + 2; x < r[0] + r[2] - 2; ++x) {
            if (x < 0 || y < 0 || x >= static_cast<int>(shot.width) ||
                y >= static_cast<int>(shot.height)) {
                return {};
            }
            const auto row = shot.height - 1 - static_cast<std::uint32_t>(y);  // rows bottom up
            const auto* p =
                &shot.color8[4 * (std::size_t{row} * shot.width + static_cast<std::uint32_t>(x))];
            out.insert(out.end(), p, p + 4);
        }
    }
    return out;
}

bool has_colour(const std::vector<std::uint8_t>& px, int r, int g, int b) {
    for (std::size_t i = 0; i + 3 < px.size(); i += 4) {
        if (std::abs(px[i] - r) < 12 && std::abs(px[i + 1] - g) < 12 &&
            std::abs(px[i + 2] - b) < 12) {
            return true;
        }
    }
    return false;
}

TEST_F(TeachPageChromium, SteppingRedrawsTheAlgorithmsImageOnly) {
    const std::string d = dom("step=1");
    const std::string alg_rect = attribute(d, "img-algorithm", "data-rect");
    const std::string gl_rect = attribute(d, "img-gl", "data-rect");
    const std::string mask_rect = attribute(d, "img-mask", "data-rect");
    EXPECT_EQ(alg_rect.substr(alg_rect.find(',', alg_rect.find(',') + 1)), ",256,256")
        << alg_rect;  // 16 pixels at 16x
    const auto shoot = [&](const std::string& hash, const std::string& file) {
        const auto path = dir_.path() / file;
        const std::string cmd = chromium(dir_) +
                                "--screenshot=" + testutil::shell_quote(path.string()) + " " +
                                url(page_, hash) + " > /dev/null 2>&1";
        EXPECT_EQ(std::system(cmd.c_str()), 0);
        return harness::read_color_image(path);
    };
    const auto first = shoot("step=1", "first.png");
    const auto last = shoot("step=5", "last.png");
    const auto a0 = crop(first, alg_rect), a1 = crop(last, alg_rect);
    ASSERT_FALSE(a0.empty()) << alg_rect;
    ASSERT_EQ(a0.size(), a1.size());
    std::size_t changed = 0;
    for (std::size_t i = 0; i < a0.size(); i += 4) {
        changed += a0[i] != a1[i] || a0[i + 1] != a1[i + 1] || a0[i + 2] != a1[i + 2];
    }
    EXPECT_GT(changed, 4000u);
    // The decided pixels are drawn white, the current step's included: at step 0 one row of 14
    // pixels (outlined, as the current step), at step 4 five (16 screen pixels a side each, less
    // the grid and the outlines).
    const auto white = [](const std::vector<std::uint8_t>& px) {
        std::size_t n = 0;
        for (std::size_t i = 0; i + 3 < px.size(); i += 4) {
            n += px[i] > 250 && px[i + 1] > 250 && px[i + 2] > 250;
        }
        return n;
    };
    EXPECT_GT(white(a0), 14u * 40u);
    EXPECT_GT(white(a1), white(a0) + 3u * 14u * 100u);
    // GL's image does not step.
    const auto g0 = crop(first, gl_rect), g1 = crop(last, gl_rect);
    ASSERT_FALSE(g0.empty()) << gl_rect;
    EXPECT_EQ(g0, g1);
    // The mask shows the algorithm-only pixel (orange) and the GL-only one (blue).
    const auto mask = crop(first, mask_rect);
    EXPECT_TRUE(has_colour(mask, 255, 109, 0));
    EXPECT_TRUE(has_colour(mask, 41, 121, 255));
    EXPECT_FALSE(has_colour(a0, 41, 121, 255));
}

}  // namespace
