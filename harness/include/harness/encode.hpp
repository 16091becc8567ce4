// encode.hpp: one encoder for each kind of output a name, path or message can reach, so that
// no text read from a file, a scene's path or a record can end an element, a string, a field
// or a line early, or reach a terminal as a control sequence.
//
// Implements:
// - html_text / html_attribute / xml_text / xml_attribute: & < > " ' as character references;
//   every character XML 1.0 forbids (C0 controls but tab, newline and carriage return, U+FFFE,
//   U+FFFF) and every byte that is not UTF-8 become U+FFFD, so that a page, an SVG file or
//   junit.xml stays well-formed; in attribute values tab, newline and carriage return are
//   written as references too, which attribute-value normalisation would otherwise turn into
//   spaces.
// - json_string: a JSON string literal, quotes included: " and \\ escaped with a backslash,
//   newline, carriage return and tab as \n \r \t, the other C0 controls and DEL as \u00XX;
//   every other byte as it is (valid UTF-8 stays valid).
// - script_safe_json: JSON text made safe inside an HTML <script> element: < > & as \u003c
//   \u003e \u0026 (no "</script>" or "<!--" can appear), U+2028 and U+2029 as \u2028 \u2029
//   (line terminators in older JavaScript), bytes that are not UTF-8 as \ufffd. These
//   characters occur in JSON text only inside strings, where the escapes mean the same.
// - json_in_script: script_safe_json(json_string(text)).
// - csv_field: RFC 4180: a field holding a comma, a double quote, CR or LF is quoted, its
//   quotes doubled; any other field is written as it is.
// - terminal: what a terminal shows as written and nothing else: printable ASCII and UTF-8
//   characters pass (a backslash too: the escapes are for what a terminal would act on, not a
//   reversible encoding); C0 and C1 controls, DEL, the bidirectional
//   overrides and isolates (U+202A..U+202E, U+2066..U+2069), U+2028/U+2029 and bytes that are
//   not UTF-8 become visible escapes: \n, \t, \r, \xHH (a byte) or \u{HHHH} (a character).
//
// - shell_word: one word for a POSIX shell, as it is when it holds only letters, digits and
//   _./-=,:+@% (and is not empty), else in single quotes, each quote written '\''.
//
// Deliberately does not: decide what may be named (conformance/case_name.hpp does for case
// names).
#pragma once

#include <string>
#include <string_view>

namespace harness::encode {

std::string html_text(std::string_view text);
std::string html_attribute(std::string_view text);
std::string xml_text(std::string_view text);
std::string xml_attribute(std::string_view text);
std::string json_string(std::string_view text);
std::string script_safe_json(std::string_view json_text);
std::string json_in_script(std::string_view text);
std::string csv_field(std::string_view text);
std::string terminal(std::string_view text);
std::string shell_word(std::string_view text);

// The length of the UTF-8 character at the start of `text` and its code point: 0 when the
// bytes there are not one (a stray continuation byte, an overlong form, a surrogate, above
// U+10FFFF, or cut short).
std::size_t utf8_char(std::string_view text, char32_t& code_point);

}  // namespace harness::encode
