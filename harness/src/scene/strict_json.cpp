// strict_json.cpp: the scene loader's strict JSON layer (strict_json.hpp): the strict SAX
// checker, the count of values in the text, the scan of simdjson's document, and the one-line
// messages of SceneError.
#include "strict_json.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <new>
#include <nlohmann/json.hpp>

#include "harness/encode.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace harness {

namespace {

std::string compose_message(const std::string& file, const std::string& path,
                            const std::string& detail, std::size_t line, std::size_t column) {
    // A file name may hold a newline too; the path and detail are escaped where they are made.
    std::string m = escape_for_message(file);
    if (line != 0) m += ":" + std::to_string(line) + ":" + std::to_string(column);
    m += ": ";
    if (!path.empty()) m += path + ": ";
    return m + detail;
}

}  // namespace

std::string escape_for_message(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        const auto u = static_cast<unsigned char>(c);
        switch (c) {
            case '\n':
                out += "\\n";
                break;
            case '\r':
                out += "\\r";
                break;
            case '\t':
                out += "\\t";
                break;
            case '\b':
                out += "\\b";
                break;
            case '\f':
                out += "\\f";
                break;
            default:
                if (u < 0x20 || u == 0x7f) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", u);
                    out += buf;
                } else {
                    out += c;
                }
        }
    }
    return out;
}

SceneError::SceneError(std::string file, std::string json_path, std::string message,
                       std::size_t line, std::size_t column)
    : refraster::Error(refraster::ExitClass::BadInput,
                       compose_message(file, json_path, message, line, column)),
      file_(std::move(file)),
      json_path_(std::move(json_path)),
      detail_(std::move(message)),
      line_(line),
      column_(column) {}

namespace strict_json {

using json = nlohmann::json;

namespace {

// A string as a JSON string literal would hold it, on one line.
std::string quoted_in_full(std::string_view v) {
    std::string out = "\"";
    for (const char c : v) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return escape_for_message(out) + "\"";
}

// A number token as written, shortened: the parser could not represent it, so no value is
// left to print in %.9g.
std::string token_text(std::string_view tok) {
    constexpr std::size_t kShown = 24;
    if (tok.size() <= kShown) return escape_for_message(tok);
    return escape_for_message(tok.substr(0, 12)) + "... (" + std::to_string(tok.size()) +
           " characters)";
}

// A JSON path in the scene format's syntax: draws[2].vertices[7].position[1].
class JsonPath {
  public:
    void push_key(const std::string& k) { parts_.push_back(key_component(k)); }
    void push_index(std::size_t i) { parts_.push_back("[" + std::to_string(i) + "]"); }
    void pop() { parts_.pop_back(); }
    std::string str() const {
        std::string s;
        for (const auto& p : parts_) s += p;
        if (!s.empty() && s.front() == '.') s.erase(0, 1);
        return s.empty() ? "(root)" : s;
    }

  private:
    std::vector<std::string> parts_;
};

// A JSON string literal for the normalized copy below (every byte of valid UTF-8, which the
// parser has checked, as it is).
void append_json_string(std::string& out, std::string_view s) {
    out += encode::json_string(s);
}

// The strict rules, applied while nlohmann's SAX parser reads the text: duplicate keys,
// nesting, the number of values and numbers out of range are refused with a path, syntax
// errors with a line and column. It keeps no document, only the open containers (their
// element counts and keys), so that its memory stays a small part of the text's even for a
// file of millions of values. On request it writes a normalized copy of the text (numbers
// as plain integers or shortest round-trip doubles) for the one case where simdjson refuses
// a strict JSON file: an integer of more digits than 64 bits hold, which JSON allows and
// which is read as a double, as the format reads every number.
class StrictChecker : public nlohmann::json_sax<json> {
  public:
    StrictChecker(const SceneLimits& limits, std::string* normalized)
        : limits_(limits), out_(normalized) {}

    std::string error_path;
    std::string error_detail;
    std::size_t error_position = 0;
    bool syntax_error = false;

    bool null() override { return scalar("null"); }
    bool boolean(bool v) override { return scalar(v ? "true" : "false"); }
    bool number_integer(number_integer_t v) override {
        return scalar(out_ ? std::to_string(v) : std::string());
    }
    bool number_unsigned(number_unsigned_t v) override {
        return scalar(out_ ? std::to_string(v) : std::string());
    }
    bool number_float(number_float_t v, const string_t& s) override {
        if (!std::isfinite(v)) return fail_value("number " + token_text(s) + " is out of range");
        std::string text;
        if (out_) {
            char buf[40];
            const auto r = std::to_chars(buf, buf + sizeof buf, v);
            text.assign(buf, r.ptr);
            // "1e+30" reads back as a double, but "100" would read back as an integer.
            if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
        }
        return scalar(text);
    }
    bool string(string_t& v) override {
        if (!add()) return false;
        if (out_) append_json_string(*out_, v);
        return true;
    }
    bool binary(binary_t&) override { return fail_value("binary values are not JSON"); }

    bool start_object(std::size_t) override { return open(false); }
    bool key(string_t& k) override {
        Open& obj = stack_.back();
        if (!obj.keys.insert(k).second) {
            path_.push_key(k);
            error_path = path_.str();
            path_.pop();
            error_detail = "duplicate key " + quoted_value(k);
            return false;
        }
        if (out_) {
            if (obj.count != 0) *out_ += ',';
            append_json_string(*out_, k);
            *out_ += ':';
        }
        ++obj.count;
        pending_key_ = k;
        return true;
    }
    bool end_object() override { return close('}'); }
    bool start_array(std::size_t) override { return open(true); }
    bool end_array() override { return close(']'); }

    bool parse_error(std::size_t position, const std::string&,
                     const nlohmann::detail::exception& ex) override {
        // Number overflow (1e400) arrives here rather than in number_float.
        if (ex.id == 406) {
            std::string w = ex.what();
            const auto q = w.find("number overflow parsing '");
            std::string tok = q == std::string::npos ? "" : w.substr(q + 25);
            if (!tok.empty() && tok.back() == '\'') tok.pop_back();
            return fail_value("number " + token_text(tok) + " is out of range");
        }
        syntax_error = true;
        error_position = position;
        std::string w = ex.what();
        // Keep nlohmann's description, drop its "[json.exception...] parse error at line L,
        // column C: " prefix: the caller prints its own line and column.
        const auto col = w.find("column ");
        const auto colon = col == std::string::npos ? std::string::npos : w.find(": ", col);
        std::string detail = colon == std::string::npos ? w : w.substr(colon + 2);
        // Its "last read" excerpt holds the whole token, which may be a number of a thousand
        // digits: keep its first characters. It escapes control characters as <U+000A>; DEL
        // and the like still need escaping.
        constexpr std::string_view kLastRead = "last read: '";
        constexpr std::size_t kShown = 40;
        if (const auto at = detail.find(kLastRead); at != std::string::npos) {
            const std::size_t from = at + kLastRead.size();
            const auto quote = detail.find("'; ", from);
            const std::size_t to = quote == std::string::npos ? detail.size() : quote;
            if (to - from > kShown) {
                std::size_t cut = from + kShown - 3;
                while (cut > from && (static_cast<unsigned char>(detail[cut]) & 0xc0) == 0x80) {
                    --cut;
                }
                detail.replace(cut, to - cut, "...");
            }
        }
        error_detail = escape_for_message(detail);
        return false;
    }

  private:
    struct Open {
        bool is_array = false;
        std::size_t count = 0;  // elements, or members so far
        std::unordered_set<std::string> keys;
    };

    bool fail_value(std::string detail) {
        error_path = value_path();
        error_detail = std::move(detail);
        return false;
    }
    // The path of the value about to be added.
    std::string value_path() {
        if (stack_.empty()) return path_.str();
        if (stack_.back().is_array) {
            path_.push_index(stack_.back().count);
        } else {
            path_.push_key(pending_key_);
        }
        std::string p = path_.str();
        path_.pop();
        return p;
    }
    // Counts one more value; in an array it is the next element.
    bool add() {
        // The document in memory costs bytes a value, whatever the file spells it with.
        if (++values_ > limits_.max_json_values) {
            return fail_value("the file holds more than " +
                              std::to_string(limits_.max_json_values) +
                              " JSON values, the limit of a scene (docs/limits.md)");
        }
        if (!stack_.empty() && stack_.back().is_array) {
            if (out_ && stack_.back().count != 0) *out_ += ',';
            ++stack_.back().count;
        }
        return true;
    }
    bool scalar(const std::string& text) {
        if (!add()) return false;
        if (out_) *out_ += text;
        return true;
    }
    bool open(bool is_array) {
        // The element index add() is about to give the container, for its path.
        const std::size_t index =
            !stack_.empty() && stack_.back().is_array ? stack_.back().count : 0;
        if (!add()) return false;
        // nlohmann's SAX parser is iterative, so depth costs no stack; the limit keeps paths,
        // messages and the walk small.
        if (stack_.size() >= limits_.max_nesting_depth) {
            // The path of the container that goes one level too deep.
            if (stack_.empty()) {
                error_path = path_.str();
            } else {
                if (stack_.back().is_array) {
                    path_.push_index(index);
                } else {
                    path_.push_key(pending_key_);
                }
                error_path = path_.str();
                path_.pop();
            }
            error_detail =
                "nesting deeper than " + std::to_string(limits_.max_nesting_depth) + " levels";
            return false;
        }
        if (!stack_.empty()) {
            if (stack_.back().is_array) {
                path_.push_index(index);
            } else {
                path_.push_key(pending_key_);
            }
        }
        stack_.push_back(Open{is_array, 0, {}});
        if (out_) *out_ += is_array ? '[' : '{';
        return true;
    }
    bool close(char bracket) {
        stack_.pop_back();
        if (!stack_.empty()) path_.pop();
        if (out_) *out_ += bracket;
        return true;
    }

    const SceneLimits& limits_;
    std::string* out_;
    std::uint64_t values_ = 0;
    std::vector<Open> stack_;
    JsonPath path_;
    std::string pending_key_;
};

void line_and_column(std::string_view text, std::size_t position, std::size_t& line,
                     std::size_t& column) {
    line = 1;
    column = 1;
    const std::size_t end = std::min(position == 0 ? 0 : position - 1, text.size());
    for (std::size_t i = 0; i < end; ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
}

// Reads `text` with the strict rules; throws the refusal. Returns only for a strict JSON
// document, writing its normalized copy to `normalized` when given.
void check_strictly(std::string_view text, const std::string& file_label, const SceneLimits& limits,
                    std::string* normalized) {
    StrictChecker sax(limits, normalized);
    const bool ok = json::sax_parse(text.begin(), text.end(), &sax, json::input_format_t::json,
                                    /*strict=*/true, /*ignore_comments=*/false);
    if (!ok || sax.syntax_error || !sax.error_detail.empty()) {
        if (sax.syntax_error) {
            std::size_t line = 0;
            std::size_t column = 0;
            line_and_column(text, sax.error_position, line, column);
            throw SceneError(file_label, "", "invalid JSON: " + sax.error_detail, line, column);
        }
        throw SceneError(file_label, sax.error_path, sax.error_detail);
    }
}

// The bounds of TextCounts, counted in one pass over the text.
TextCounts count_in_text(std::string_view text) {
    std::uint64_t commas = 0;
    std::uint64_t opens = 0;
    std::size_t i = 0;
    const auto* p = reinterpret_cast<const unsigned char*>(text.data());
#if defined(__SSE2__)
    // Byte lanes count down by one a hit (a match is -1) for up to 255 blocks of 16 bytes, then
    // are summed.
    const __m128i comma = _mm_set1_epi8(',');
    const __m128i bracket = _mm_set1_epi8('[');
    const __m128i brace = _mm_set1_epi8('{');
    const __m128i zero = _mm_setzero_si128();
    const auto lanes_total = [&](__m128i lanes) {
        const __m128i sums = _mm_sad_epu8(_mm_sub_epi8(zero, lanes), zero);
        return static_cast<std::uint64_t>(_mm_cvtsi128_si32(sums)) +
               static_cast<std::uint64_t>(_mm_extract_epi16(sums, 4));
    };
    while (i + 16 <= text.size()) {
        const std::size_t blocks = std::min<std::size_t>((text.size() - i) / 16, 255);
        __m128i c = zero;
        __m128i o = zero;
        for (std::size_t b = 0; b < blocks; ++b, i += 16) {
            const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + i));
            c = _mm_add_epi8(c, _mm_cmpeq_epi8(v, comma));
            o = _mm_add_epi8(o, _mm_or_si128(_mm_cmpeq_epi8(v, bracket), _mm_cmpeq_epi8(v, brace)));
        }
        commas += lanes_total(c);
        opens += lanes_total(o);
    }
#endif
    for (; i < text.size(); ++i) {
        commas += p[i] == ',';
        opens += (p[i] == '[') | (p[i] == '{');
    }
    return {1 + commas + opens, opens};
}

// The strict rules simdjson does not apply, checked on its document in document order:
// false at the first duplicate key, container nested too deep or value past the limit.
class StrictScan {
  public:
    explicit StrictScan(const SceneLimits& limits) : limits_(limits) {}

    bool ok(dom::element e, std::uint32_t enclosing) {
        if (++values_ > limits_.max_json_values) return false;
        switch (e.type()) {
            case dom::element_type::ARRAY: {
                if (enclosing >= limits_.max_nesting_depth) return false;
                for (const dom::element c : as_array(e)) {
                    if (!ok(c, enclosing + 1)) return false;
                }
                return true;
            }
            case dom::element_type::OBJECT: {
                if (enclosing >= limits_.max_nesting_depth) return false;
                const dom::object o = as_object(e);
                // Scene objects have a handful of keys: compare each with those before it;
                // a large object (no scene needs one) goes through a hash set.
                constexpr std::size_t kSmall = 16;
                std::string_view seen[kSmall];
                std::size_t n = 0;
                std::unordered_set<std::string_view> many;
                for (const dom::key_value_pair kv : o) {
                    if (n < kSmall) {
                        for (std::size_t i = 0; i < n; ++i) {
                            if (seen[i] == kv.key) return false;
                        }
                        seen[n] = kv.key;
                        if (++n == kSmall) many.insert(seen, seen + kSmall);
                    } else if (!many.insert(kv.key).second) {
                        return false;
                    }
                    if (!ok(kv.value, enclosing + 1)) return false;
                }
                return true;
            }
            default:
                return true;
        }
    }

  private:
    const SceneLimits& limits_;
    std::uint64_t values_ = 0;
};

}  // namespace

// A key as one path component: .name when it is a plain identifier, otherwise ["escaped"] so
// that a key holding dots, brackets or newlines still reads as one component on one line.
std::string key_component(std::string_view k) {
    const bool plain = !k.empty() && std::all_of(k.begin(), k.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
               c == '_';
    });
    if (plain) return "." + std::string(k);
    return "[" + quoted_in_full(k) + "]";
}

// A string from the file inside a message: quoted, escaped, cut after 40 bytes (at a UTF-8
// character boundary) so that a long value does not drown the message.
std::string quoted_value(std::string_view v) {
    constexpr std::size_t kShown = 40;
    if (v.size() <= kShown) return quoted_in_full(v);
    std::size_t cut = kShown - 3;
    while (cut > 0 && (static_cast<unsigned char>(v[cut]) & 0xc0) == 0x80) --cut;
    std::string q = quoted_in_full(v.substr(0, cut));
    return q.insert(q.size() - 1, "...");
}

// A number inside a message: integers exactly, other values in %.9g (enough to tell float32
// values apart), never the hundreds of digits a file may spell them with.
std::string number_text(double d) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", d);
    return buf;
}
std::string number_text(dom::element v) {
    switch (v.type()) {
        case dom::element_type::INT64:
            return std::to_string(v.get_int64().value_unsafe());
        case dom::element_type::UINT64:
            return std::to_string(v.get_uint64().value_unsafe());
        default:
            return number_text(v.get_double().value_unsafe());
    }
}

// Parses `text` (followed by simdjson::SIMDJSON_PADDING readable bytes when `padded`) with
// every strict rule; throws the refusal.
void parse_document(Document& doc, std::string_view text, bool padded,
                    const std::string& file_label, const SceneLimits& limits) {
    // Deeper files are refused anyway; the bound keeps simdjson's depth tables small.
    const std::size_t depth =
        std::clamp<std::size_t>(std::size_t{limits.max_nesting_depth} + 2, 64, 4096);
    // A parser's buffers are kept for the next load (parse_scene_text): only a larger file
    // or another depth allocates them again.
    const std::size_t capacity = std::max<std::size_t>(text.size(), 64);
    if ((doc.parser.capacity() < capacity || doc.parser.max_depth() != depth) &&
        doc.parser.allocate(capacity, depth) != simdjson::SUCCESS) {
        // Running out of memory is not the file's fault: the tool reports it as such (exit 3).
        throw std::bad_alloc();
    }
    // Below two bytes a value no file can pass the limit, so only larger files need the count.
    doc.counts = count_in_text(text);
    if (text.size() / 2 >= limits.max_json_values && doc.counts.values > limits.max_json_values) {
        check_strictly(text, file_label, limits, nullptr);  // refuses unless strings inflated it
    }
    auto first = doc.parser.parse(text.data(), text.size(), /*realloc_if_needed=*/!padded);
    if (first.error() == simdjson::SUCCESS) {
        // Duplicate keys and nesting are the walk's to check (Node).
        doc.root = first.value_unsafe();
        return;
    }
    if (first.error() == simdjson::MEMALLOC) throw std::bad_alloc();
    // The refusal, with its path or position; or the normalized copy of a strict file that
    // simdjson could not hold.
    check_strictly(text, file_label, limits, &doc.normalized);
    auto second = doc.parser.parse(doc.normalized);
    if (second.error() == simdjson::SUCCESS) {
        doc.root = second.value_unsafe();
        doc.counts = count_in_text(doc.normalized);
        return;
    }
    throw SceneError(
        file_label, "",
        std::string("cannot read this JSON: ") + simdjson::error_message(first.error()));
}

std::string describe(dom::element v) {
    switch (v.type()) {
        case dom::element_type::NULL_VALUE:
            return "null";
        case dom::element_type::BOOL:
            return v.get_bool().value_unsafe() ? "true" : "false";
        case dom::element_type::STRING:
            return "the string " + quoted_value(v.get_string().value_unsafe());
        case dom::element_type::ARRAY:
            return "an array of " + std::to_string(element_count(as_array(v)));
        case dom::element_type::OBJECT:
            return "an object";
        default:
            return number_text(v);
    }
}

bool follows_strict_rules(dom::element root, const SceneLimits& limits) {
    return StrictScan(limits).ok(root, 0);
}

[[noreturn]] void refuse_strictly(std::string_view text, const std::string& file_label,
                                  const SceneLimits& limits) {
    check_strictly(text, file_label, limits, nullptr);
    throw SceneError(file_label, "", "the strict rules refuse this JSON, its parser does not");
}

}  // namespace strict_json

}  // namespace harness
