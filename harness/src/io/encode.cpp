// encode.cpp: the encoders of encode.hpp.
#include "harness/encode.hpp"

#include <algorithm>
#include <cstdio>

namespace harness::encode {

namespace {

constexpr std::string_view kReplacement = "\xEF\xBF\xBD";  // U+FFFD

// Upper case for the terminal's escapes; lower case for JSON's \u escapes, as JSON writers
// usually give them.
std::string hex(unsigned value, int digits, bool lower = false) {
    char buf[16];
    std::snprintf(buf, sizeof buf, lower ? "%0*x" : "%0*X", digits, value);
    return buf;
}

// XML 1.0's Char production: tab, newline, carriage return and U+0020 up, but the
// surrogates (never decoded) and U+FFFE, U+FFFF.
bool xml_allows(char32_t c) {
    return c == 0x9 || c == 0xA || c == 0xD || (c >= 0x20 && c != 0xFFFE && c != 0xFFFF);
}

std::string markup(std::string_view text, bool attribute) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        char32_t c = 0;
        const std::size_t n = utf8_char(text.substr(i), c);
        if (n == 0 || !xml_allows(c)) {
            out += kReplacement;
            i += n == 0 ? 1 : n;
            continue;
        }
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
            case '\t':
                out += attribute ? "&#9;" : "\t";
                break;
            case '\n':
                out += attribute ? "&#10;" : "\n";
                break;
            case '\r':
                out += attribute ? "&#13;" : "\r";
                break;
            default:
                out.append(text.substr(i, n));
        }
        i += n;
    }
    return out;
}

}  // namespace

std::size_t utf8_char(std::string_view text, char32_t& code_point) {
    if (text.empty()) return 0;
    const auto b = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned lead = b(0);
    if (lead < 0x80) {
        code_point = lead;
        return 1;
    }
    std::size_t n = 0;
    char32_t c = 0, min = 0;
    if (lead >= 0xC2 && lead <= 0xDF) {
        n = 2, c = lead & 0x1F, min = 0x80;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        n = 3, c = lead & 0x0F, min = 0x800;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        n = 4, c = lead & 0x07, min = 0x10000;
    } else {
        return 0;
    }
    if (text.size() < n) return 0;
    for (std::size_t k = 1; k < n; ++k) {
        if ((b(k) & 0xC0) != 0x80) return 0;
        c = (c << 6) | (b(k) & 0x3F);
    }
    if (c < min || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) return 0;
    code_point = c;
    return n;
}

std::string html_text(std::string_view text) {
    return markup(text, false);
}
std::string html_attribute(std::string_view text) {
    return markup(text, true);
}
std::string xml_text(std::string_view text) {
    return markup(text, false);
}
std::string xml_attribute(std::string_view text) {
    return markup(text, true);
}

std::string json_string(std::string_view text) {
    std::string out = "\"";
    out.reserve(text.size() + 2);
    for (const char c : text) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c == '\t') {
            out += "\\t";
        } else if (u < 0x20 || u == 0x7F) {
            out += "\\u" + hex(u, 4, true);
        } else {
            out += c;
        }
    }
    return out + "\"";
}

std::string script_safe_json(std::string_view json_text) {
    std::string out;
    out.reserve(json_text.size() + json_text.size() / 16);
    for (std::size_t i = 0; i < json_text.size();) {
        char32_t c = 0;
        const std::size_t n = utf8_char(json_text.substr(i), c);
        if (n == 0) {
            out += "\\ufffd";
            ++i;
            continue;
        }
        if (c == '<' || c == '>' || c == '&' || c == 0x2028 || c == 0x2029) {
            out += "\\u" + hex(c, 4, true);
        } else {
            out.append(json_text.substr(i, n));
        }
        i += n;
    }
    return out;
}

std::string json_in_script(std::string_view text) {
    return script_safe_json(json_string(text));
}

std::string csv_field(std::string_view text) {
    if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

std::string terminal(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        char32_t c = 0;
        const std::size_t n = utf8_char(text.substr(i), c);
        if (n == 0) {
            out += "\\x" + hex(static_cast<unsigned char>(text[i]), 2);
            ++i;
            continue;
        }
        if (c == '\n') {
            out += "\\n";
        } else if (c == '\t') {
            out += "\\t";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c < 0x20 || c == 0x7F) {
            out += "\\x" + hex(c, 2);
        } else if ((c >= 0x80 && c <= 0x9F) || (c >= 0x202A && c <= 0x202E) ||
                   (c >= 0x2066 && c <= 0x2069) || c == 0x2028 || c == 0x2029) {
            out += "\\u{" + hex(c, 4) + "}";
        } else {
            out.append(text.substr(i, n));
        }
        i += n;
    }
    return out;
}

std::string shell_word(std::string_view text) {
    const bool plain = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
               std::string_view("_./-=,:+@%").find(c) != std::string_view::npos;
    });
    if (plain) return std::string(text);
    std::string q = "'";
    for (char c : text) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

}  // namespace harness::encode
