// markup.hpp: the pieces of HTML and SVG that every page, report and figure the project writes
// has in common.
//
// Implements: escaping text for HTML and XML, in element content and in attribute values
// alike; the root element of an SVG document, standalone or inline in an HTML page; the step
// between a chart axis's ticks, and the ticks themselves: the decades of a logarithmic axis
// with their 2..9 marks, and the multiples of the step on a linear one.
//
// Deliberately does not: format numbers (each writer keeps its own precision, so that its
// output stays as it is), or lay anything out.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace harness::markup {

// `text` with & < > " ' replaced by their character references, so that it reads as written
// between tags and inside an attribute value quoted either way, and what XML 1.0 forbids
// (controls but tab, newline and carriage return; bytes that are not UTF-8) as U+FFFD:
// harness::encode::html_text (encode.hpp).
std::string escape(std::string_view text);

// One attribute of an element: its value is escaped when written.
struct Attribute {
    std::string_view name;
    std::string value;
};

// `<svg id="ID" xmlns="http://www.w3.org/2000/svg" NAME="VALUE" ...>`: the id first when there
// is one (a page's script and style find the chart by it), then the namespace, which a
// standalone file needs and an inline one tolerates, then `attributes` in order.
std::string svg_open(std::initializer_list<Attribute> attributes, std::string_view id = {});

// The end of the element svg_open began.
std::string svg_close();

// The step of a linear chart axis whose ticks would be `raw` apart: the first of 1, 2 and 5 x
// 10^k (10^k the power of ten at or below `raw`) that is at least `raw * slack`, else 10^(k+1).
// A slack a little below 1 keeps a step that rounding made a hair too small.
double tick_step(double raw, double slack = 1.0);

// A tick of a logarithmic axis: `mantissa` x 10^`exponent`, and that value. The two integers
// are kept so that a writer can label the tick or place it without taking a logarithm again.
struct DecadeTick {
    int mantissa = 1;
    int exponent = 0;
    double value = 1.0;
};

// The ticks of a logarithmic axis.
struct DecadeTicks {
    std::vector<DecadeTick> major;  // 10^k, ascending
    std::vector<DecadeTick> minor;  // m x 10^k for m = 2..9, ascending
};

// The powers of ten from 10^first_exponent to 10^last_exponent as `major`, and the 2..9 x 10^k
// between each and the next as `minor` (none above the last power, which closes the range).
// Both are empty when last_exponent < first_exponent. A value is m * pow(10, k), the same
// double whichever writer asks.
DecadeTicks decade_ticks(int first_exponent, int last_exponent);

// The multiples k x `step` (k an integer) from `lo` to `hi`, ascending, each computed as k times
// the step rather than by adding steps up, so that rounding does not accumulate along the axis.
// An end a billionth of a step outside still counts, so that a bound which rounding left a hair
// short of a multiple keeps its tick. At most `limit` of them: past 2^53, k + 1 == k, and a
// range that narrow would otherwise never end.
std::vector<double> linear_ticks(double lo, double hi, double step, std::size_t limit = 50);

}  // namespace harness::markup
