// markup.cpp: escaping, the SVG root element and chart axis ticks (markup.hpp).
#include "harness/markup.hpp"

#include <cmath>

#include "harness/encode.hpp"

namespace harness::markup {

std::string escape(std::string_view text) {
    return encode::html_text(text);
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

DecadeTicks decade_ticks(int first_exponent, int last_exponent) {
    DecadeTicks out;
    for (int k = first_exponent; k <= last_exponent; ++k) {
        out.major.push_back({1, k, std::pow(10.0, k)});
        if (k == last_exponent) break;
        for (int m = 2; m <= 9; ++m) out.minor.push_back({m, k, m * std::pow(10.0, k)});
    }
    return out;
}

std::vector<double> linear_ticks(double lo, double hi, double step, std::size_t limit) {
    std::vector<double> out;
    const double first = std::ceil(lo / step - 1e-9);
    const double last = std::floor(hi / step + 1e-9);
    for (double k = first; k <= last && out.size() < limit; k += 1.0) out.push_back(k * step);
    return out;
}

}  // namespace harness::markup
