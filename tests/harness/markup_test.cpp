// Tests of the markup pieces every page, report and figure shares (harness/markup.hpp): the
// escape of the five characters, the SVG root element's attribute order, the 1-2-5 steps of a
// linear chart axis, the decades of a logarithmic one and the multiples of a linear one.
#include "harness/markup.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace {

using harness::markup::decade_ticks;
using harness::markup::escape;
using harness::markup::linear_ticks;
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

TEST(Markup, DecadeTicksArePowersOfTenWithTwoToNineBetween) {
    const auto ticks = decade_ticks(-1, 1);
    ASSERT_EQ(ticks.major.size(), 3u);
    EXPECT_EQ(ticks.major[0].value, 0.1);
    EXPECT_EQ(ticks.major[1].value, 1.0);
    EXPECT_EQ(ticks.major[2].value, 10.0);
    EXPECT_EQ(ticks.major[2].mantissa, 1);
    EXPECT_EQ(ticks.major[2].exponent, 1);
    // 2..9 in each decade below the last power, none above it.
    ASSERT_EQ(ticks.minor.size(), 16u);
    EXPECT_EQ(ticks.minor[0].mantissa, 2);
    EXPECT_EQ(ticks.minor[0].exponent, -1);
    EXPECT_EQ(ticks.minor[0].value, 2 * 0.1);
    EXPECT_EQ(ticks.minor[7].value, 9 * 0.1);
    EXPECT_EQ(ticks.minor[8].value, 2.0);
    EXPECT_EQ(ticks.minor[15].mantissa, 9);
    EXPECT_EQ(ticks.minor[15].exponent, 0);
    EXPECT_EQ(ticks.minor[15].value, 9.0);
    // One decade is its power alone; an empty range has nothing.
    EXPECT_EQ(decade_ticks(3, 3).major.size(), 1u);
    EXPECT_TRUE(decade_ticks(3, 3).minor.empty());
    EXPECT_TRUE(decade_ticks(2, 1).major.empty());
    EXPECT_TRUE(decade_ticks(2, 1).minor.empty());
}

TEST(Markup, LinearTicksAreIntegerMultiplesOfTheStep) {
    EXPECT_EQ(linear_ticks(0.0, 1.0, 0.25), (std::vector<double>{0.0, 0.25, 0.5, 0.75, 1.0}));
    // Counted, not added up: ten steps of 0.1 added up make 0.9999999999999999, not 1.
    const std::vector<double> tenths = linear_ticks(0.0, 1.0, 0.1);
    ASSERT_EQ(tenths.size(), 11u);
    for (std::size_t k = 0; k < tenths.size(); ++k) {
        EXPECT_EQ(tenths[k], static_cast<double>(k) * 0.1) << k;
    }
    EXPECT_EQ(tenths.back(), 1.0);
    // Negative ends, and bounds a hair inside a multiple still keep its tick.
    EXPECT_EQ(linear_ticks(-5.0, 5.0, 5.0), (std::vector<double>{-5.0, 0.0, 5.0}));
    EXPECT_EQ(linear_ticks(2.0 + 1e-12, 4.0 - 1e-12, 1.0), (std::vector<double>{2.0, 3.0, 4.0}));
    EXPECT_TRUE(linear_ticks(1.1, 1.9, 1.0).empty());
    // The limit caps a range too narrow for its magnitude.
    EXPECT_EQ(linear_ticks(0.0, 100.0, 1.0, 7).size(), 7u);
    EXPECT_EQ(linear_ticks(1e17, 1e17 + 64.0, 1e-3).size(), 50u);
}

}  // namespace
