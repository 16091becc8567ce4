// markup.hpp: the pieces of HTML and SVG that every page, report and figure the project writes
// has in common.
//
// Implements: escaping text for HTML and XML, in element content and in attribute values
// alike; the root element of an SVG document, standalone or inline in an HTML page; the step
// between a chart axis's ticks.
//
// Deliberately does not: format numbers (each writer keeps its own precision, so that its
// output stays as it is), or lay anything out.
#pragma once

#include <initializer_list>
#include <string>
#include <string_view>

namespace harness::markup {

// `text` with & < > " ' replaced by their character references, so that it reads as written
// between tags and inside an attribute value quoted either way.
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

}  // namespace harness::markup
