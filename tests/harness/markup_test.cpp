// Tests of the markup pieces every page, report and figure shares (harness/markup.hpp): the
// escape of the five characters, the SVG root element's attribute order, and the 1-2-5 steps
// of a linear chart axis.
#include "harness/markup.hpp"

#include <gtest/gtest.h>

namespace {

using harness::markup::escape;
using harness::markup::svg_close;
using harness::markup::svg_open;
using harness::markup::tick_step;

TEST(Markup, EscapesTheFiveCharactersAndNothingElse) {
    EXPECT_EQ(escape("a & b < c > d \"e\" 'f'"),
              "a &amp; b &lt; c &gt; d &quot;e&quot; &#39;f&#39;");
    // An existing reference is escaped again: the text is taken as written.
    EXPECT_EQ(escape("&amp;"), "&amp;amp;");
    // UTF-8 and control characters pass through.
    EXPECT_EQ(escape("\xE2\x89\xA4\x30\n\t"), "\xE2\x89\xA4\x30\n\t");
    EXPECT_EQ(escape(""), "");
}

TEST(Markup, SvgRootElementPutsTheIdThenTheNamespaceThenTheAttributes) {
    EXPECT_EQ(svg_open({{"width", "10"}, {"height", "20"}}),
              "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"20\">");
    EXPECT_EQ(svg_open({{"aria-label", "a <b> & \"c\""}}, "chart"),
              "<svg id=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" "
              "aria-label=\"a &lt;b&gt; &amp; &quot;c&quot;\">");
    EXPECT_EQ(svg_close(), "</svg>");
}

TEST(Markup, TickStepsAreOneTwoOrFiveTimesAPowerOfTen) {
    EXPECT_DOUBLE_EQ(tick_step(1.0), 1.0);
    EXPECT_DOUBLE_EQ(tick_step(1.5), 2.0);
    EXPECT_DOUBLE_EQ(tick_step(3.0), 5.0);
    EXPECT_DOUBLE_EQ(tick_step(7.0), 10.0);
    EXPECT_DOUBLE_EQ(tick_step(0.03), 0.05);
    EXPECT_DOUBLE_EQ(tick_step(200.0), 200.0);
    // A slack below 1 keeps the smaller step for a value a hair above it.
    EXPECT_DOUBLE_EQ(tick_step(2.0000001), 5.0);
    EXPECT_DOUBLE_EQ(tick_step(2.0000001, 0.999), 2.0);
}

}  // namespace
