// markup.cpp: escaping and the SVG root element (markup.hpp).
#include "harness/markup.hpp"

#include <cmath>

namespace harness::markup {

std::string escape(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&#39;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

std::string svg_open(std::initializer_list<Attribute> attributes, std::string_view id) {
    std::string out = "<svg";
    if (!id.empty()) out += " id=\"" + escape(id) + "\"";
    out += " xmlns=\"http://www.w3.org/2000/svg\"";
    for (const Attribute& a : attributes) {
        out += ' ';
        out += a.name;
        out += "=\"" + escape(a.value) + "\"";
    }
    return out + ">";
}

std::string svg_close() {
    return "</svg>";
}

double tick_step(double raw, double slack) {
    const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
    for (const double m : {1.0, 2.0, 5.0}) {
        if (m * magnitude >= raw * slack) return m * magnitude;
    }
    return 10.0 * magnitude;
}

}  // namespace harness::markup
