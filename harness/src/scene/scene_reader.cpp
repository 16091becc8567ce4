// Scene format v1 reader: strict JSON parsing (duplicate keys refused, positions for syntax
// errors), then a validating walk that turns the document into a SceneFile, naming the JSON
// path of the first offending value, and the work limits of SceneLimits (docs/limits.md).
// Every message is one line: keys, paths and strings from the file are escaped, numbers are
// printed short.
//
// Two parsers, one set of rules. simdjson's DOM parser reads every file first: it is fast
// enough for scenes of millions of vertices, but it reports no position for a syntax error and
// accepts duplicate keys. The validating walk checks what it does not (duplicate keys,
// nesting) on every container it reads, and a count of the text's commas and brackets bounds
// the number of values; when the walk refuses something, a scan of the whole document first
// looks for a strict fault, which takes precedence. Whenever simdjson refuses a file or a
// strict fault is found, nlohmann's SAX parser reads the file again with the strict rules and
// gives the refusal its path or line and column; valid files never take that path. The walk
// builds paths only when it refuses something, so a valid file costs no string per value.
#include <simdjson.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <system_error>
#include <unordered_set>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "harness/front_end.hpp"
#include "harness/scene.hpp"
#include "refraster/renderer.hpp"

namespace harness {

using json = nlohmann::json;
namespace dom = simdjson::dom;

namespace {

// A container of the document as simdjson's iterable types; the caller has checked its type.
// (Named values, not temporaries: a range-for over a temporary result would dangle.)
dom::array as_array(dom::element e) {
    const auto r = e.get_array();
    return r.value_unsafe();
}
dom::object as_object(dom::element e) {
    const auto r = e.get_object();
    return r.value_unsafe();
}

std::string compose_message(const std::string& file, const std::string& path,
                            const std::string& detail, std::size_t line, std::size_t column) {
    // A file name may hold a newline too; the path and detail are escaped where they are made.
    std::string m = escape_for_message(file);
    if (line != 0) m += ":" + std::to_string(line) + ":" + std::to_string(column);
    m += ": ";
    if (!path.empty()) m += path + ": ";
    return m + detail;
}

// A string as a JSON string literal would hold it, on one line.
std::string quoted_in_full(std::string_view v) {
    std::string out = "\"";
    for (const char c : v) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return escape_for_message(out) + "\"";
}

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

// A JSON string literal for the normalized copy below: quotes, backslashes and control
// characters escaped; every other byte (valid UTF-8, checked by the parser) as it is.
void append_json_string(std::string& out, std::string_view s) {
    out += '"';
    for (const char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (u < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", u);
            out += buf;
        } else {
            out += c;
        }
    }
    out += '"';
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

// Upper bounds of the values and of the containers in `text`: every value but the root
// follows a comma or opens its container's first element, so values <= 1 + commas + '[' +
// '{', and containers <= '[' + '{' (characters inside strings only raise the bounds). The
// first lets a file with too many values be refused before simdjson builds a document whose
// size follows the number of values; the second tells whether the walk saw every container.
struct TextCounts {
    std::uint64_t values = 1;
    std::uint64_t containers = 0;
};
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

// The parsed document of a scene file: the root of simdjson's DOM, which `parser` owns, and
// the normalized text when the file took that path.
struct Document {
    dom::parser& parser;
    std::string normalized;
    dom::element root;
    TextCounts counts;  // of the text simdjson read
};

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
        throw SceneError(
            file_label, "",
            "cannot allocate the memory to parse " + std::to_string(text.size()) + " bytes");
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
    if (first.error() == simdjson::MEMALLOC) {
        throw SceneError(
            file_label, "",
            "cannot allocate the memory to parse " + std::to_string(text.size()) + " bytes");
    }
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

// The number of elements of an array: simdjson's count stops at 0xFFFFFF.
std::size_t element_count(dom::array a) {
    std::size_t n = a.size();
    if (n == 0xFFFFFF) {
        n = 0;
        for (auto it = a.begin(); it != a.end(); ++it) ++n;
    }
    return n;
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

// A value of the document and where it sits; every accessor refuses what the format forbids.
// The path is built only for a refusal, from the chain of parents, so a Node must not outlive
// the Node it was taken from.
//
// The walk also applies the strict rules simdjson does not (duplicate keys, nesting) to every
// container it accepts: each object passes require_object, which refuses a key seen twice,
// and each array passes array_size; both refuse a container nested too deep. Such a fault
// throws StrictFault, and the caller lets the strict parser name it. Every container of a
// valid scene is accepted by one of the two exactly once (each key of an object is allowed and
// read, each array's elements are read), and the walk counts them: the caller compares the
// count with the brackets of the text and scans the document when they differ.
struct StrictFault {};

struct WalkContext {
    const std::string& file;
    const SceneLimits& limits;
    std::uint64_t containers = 0;  // accepted by require_object or array_size
};

class Node {
  public:
    Node(dom::element v, WalkContext& context) : v_(v), context_(&context) {}
    Node(dom::element v, const Node& parent, std::string_view key)
        : v_(v),
          parent_(&parent),
          key_(key),
          by_key_(true),
          depth_(parent.depth_ + 1),
          context_(parent.context_) {}
    Node(dom::element v, const Node& parent, std::size_t index)
        : v_(v),
          parent_(&parent),
          index_(index),
          depth_(parent.depth_ + 1),
          context_(parent.context_) {}

    dom::element value() const { return v_; }
    bool is_null() const { return v_.type() == dom::element_type::NULL_VALUE; }
    bool is_object() const { return v_.type() == dom::element_type::OBJECT; }
    bool is_string() const { return v_.type() == dom::element_type::STRING; }

    std::string path() const {
        std::vector<const Node*> chain;
        for (const Node* n = this; n->parent_ != nullptr; n = n->parent_) chain.push_back(n);
        std::string s;
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
            s += (*it)->by_key_ ? key_component((*it)->key_)
                                : "[" + std::to_string((*it)->index_) + "]";
        }
        if (!s.empty() && s.front() == '.') s.erase(0, 1);
        return s.empty() ? "(root)" : s;
    }

    [[noreturn]] void fail(const std::string& detail) const {
        throw SceneError(context_->file, path(), detail);
    }

    // Containers of the document this one is inside.
    std::uint32_t depth() const { return depth_; }
    WalkContext& context() const { return *context_; }

    // An object whose keys are all in `allowed` (at most 64 names), each once.
    void require_object(std::initializer_list<std::string_view> allowed) const {
        require_object(std::span<const std::string_view>(allowed.begin(), allowed.size()));
    }
    void require_object(std::span<const std::string_view> allowed) const {
        if (!is_object()) fail("expected an object, got " + describe(v_));
        accept_container();
        std::uint64_t seen = 0;
        for (const dom::key_value_pair kv : as_object(v_)) {
            std::uint64_t bit = 1;
            bool ok = false;
            for (auto a : allowed) {
                if (kv.key == a) {
                    ok = true;
                    break;
                }
                bit <<= 1;
            }
            if (ok) {
                if ((seen & bit) != 0) throw StrictFault{};
                seen |= bit;
            } else {
                std::string list;
                for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
                Node(kv.value, *this, kv.key)
                    .fail("unknown key " + quoted_value(kv.key) + " (allowed: " + list + ")");
            }
        }
    }
    Node at(std::string_view key) const {
        auto n = get(key);
        if (!n) fail("missing required key " + quoted_value(key));
        return *n;
    }
    std::optional<Node> get(std::string_view key) const {
        if (!is_object()) return std::nullopt;
        // The first match: a second one makes require_object refuse the object.
        for (const dom::key_value_pair kv : as_object(v_)) {
            if (kv.key == key) return Node(kv.value, *this, kv.key);
        }
        return std::nullopt;
    }

    std::size_t array_size(std::size_t min, std::size_t max, const char* what) const {
        if (v_.type() != dom::element_type::ARRAY) {
            fail(std::string("expected ") + what + ", got " + describe(v_));
        }
        accept_container();
        const std::size_t n = element_count(as_array(v_));
        if (n < min || n > max) {
            fail(std::string("expected ") + what + ", got an array of " + std::to_string(n));
        }
        return n;
    }
    // An object whose keys the file chooses (names, not the format's keys), each once: its
    // number of members. `what` describes it in a refusal.
    std::size_t members(const char* what) const {
        if (!is_object()) fail(std::string("expected ") + what + ", got " + describe(v_));
        accept_container();
        std::unordered_set<std::string_view> seen;
        for (const dom::key_value_pair kv : as_object(v_)) {
            if (!seen.insert(kv.key).second) throw StrictFault{};
        }
        return seen.size();
    }
    // f(std::string_view key, const Node& value) for each member of an object checked by
    // members, in order.
    template <class F>
    void for_each_member(F&& f) const {
        for (const dom::key_value_pair kv : as_object(v_)) f(kv.key, Node(kv.value, *this, kv.key));
    }
    // Element i of an array checked by array_size; O(i), so for short arrays. Long ones go
    // through for_each.
    Node operator[](std::size_t i) const {
        const auto r = as_array(v_).at(i);
        return {r.value_unsafe(), *this, i};
    }
    // f(const Node& element) for each element of an array checked by array_size, in order.
    template <class F>
    void for_each(F&& f) const {
        std::size_t i = 0;
        for (const dom::element e : as_array(v_)) f(Node(e, *this, i++));
    }

    // A JSON number read as a double, then rounded once to float32; must stay finite.
    float f32() const {
        double d = 0;
        if (v_.get_double().get(d) != simdjson::SUCCESS) {
            fail("expected a number, got " + describe(v_));
        }
        const float f = static_cast<float>(d);
        if (!std::isfinite(f)) fail("number " + number_text(v_) + " does not fit in float32");
        return f;
    }
    float f32_in(float lo, float hi) const {
        const float f = f32();
        if (!(f >= lo && f <= hi)) {
            fail("expected a number in [" + number_text(static_cast<double>(lo)) + ", " +
                 number_text(static_cast<double>(hi)) + "], got " + number_text(v_));
        }
        return f;
    }
    // A number in (lo, hi] once rounded to float32: lo itself is refused.
    float f32_above(float lo, float hi) const {
        const float f = f32();
        if (!(f > lo && f <= hi)) {
            fail("expected a number in (" + number_text(static_cast<double>(lo)) + ", " +
                 number_text(static_cast<double>(hi)) + "], got " + number_text(v_));
        }
        return f;
    }
    // An integer; 3.0 counts as 3. Never passes through float32.
    std::int64_t integer(std::int64_t lo, std::int64_t hi) const {
        std::int64_t r = 0;
        switch (v_.type()) {
            case dom::element_type::INT64:
                r = v_.get_int64().value_unsafe();
                break;
            case dom::element_type::UINT64:
                // simdjson stores only integers above INT64_MAX as unsigned.
                fail_range(lo, hi);
            case dom::element_type::DOUBLE: {
                const double d = v_.get_double().value_unsafe();
                if (std::trunc(d) != d) fail("expected an integer, got " + number_text(v_));
                if (d < -9.0e18 || d > 9.0e18) fail_range(lo, hi);
                r = static_cast<std::int64_t>(d);
                break;
            }
            default:
                fail("expected an integer, got " + describe(v_));
        }
        if (r < lo || r > hi) fail_range(lo, hi);
        return r;
    }
    bool boolean() const {
        bool b = false;
        if (v_.get_bool().get(b) != simdjson::SUCCESS) {
            fail("expected true or false, got " + describe(v_));
        }
        return b;
    }
    std::string_view string_view() const {
        std::string_view s;
        if (v_.get_string().get(s) != simdjson::SUCCESS) {
            fail("expected a string, got " + describe(v_));
        }
        return s;
    }
    std::string string() const { return std::string(string_view()); }
    template <class E>
    E choice(std::initializer_list<std::pair<std::string_view, E>> options) const {
        return choice(
            std::span<const std::pair<std::string_view, E>>(options.begin(), options.size()));
    }
    template <class E>
    E choice(std::span<const std::pair<std::string_view, E>> options) const {
        std::string_view s;
        if (v_.get_string().get(s) != simdjson::SUCCESS) {
            std::string list;
            for (const auto& [n, _] : options) list += (list.empty() ? "" : ", ") + std::string(n);
            fail("expected one of " + list + ", got " + describe(v_));
        }
        for (const auto& [n, e] : options) {
            if (s == n) return e;
        }
        std::string list;
        for (const auto& [n, _] : options) list += (list.empty() ? "" : ", ") + std::string(n);
        fail("expected one of " + list + ", got " + quoted_value(s));
    }

  private:
    // An object or array the walk takes: counted, and refused when nested too deep.
    void accept_container() const {
        if (depth_ >= context_->limits.max_nesting_depth) throw StrictFault{};
        ++context_->containers;
    }
    [[noreturn]] void fail_range(std::int64_t lo, std::int64_t hi) const {
        fail("expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
             "], got " + number_text(v_));
    }

    dom::element v_;
    const Node* parent_ = nullptr;
    std::string_view key_;
    std::size_t index_ = 0;
    bool by_key_ = false;
    std::uint32_t depth_ = 0;
    WalkContext* context_;
};

// Limits from scene format v1, section "Limits and remaining semantics".
constexpr std::int64_t kMaxTargetSide = 16384;
constexpr std::int64_t kMaxTargetSamplesArea = 67'108'864;
constexpr std::int64_t kViewportOriginMin = -32768;
constexpr std::int64_t kViewportOriginMax = 32767;
// The format bounds scissor sizes only below; this bound keeps x + width inside int32.
constexpr std::int64_t kScissorLimit = std::int64_t{1} << 30;

// The extension "textures": textures by name, texture coordinates and the draw state key
// "texture" (docs/scene-format.md).
constexpr std::string_view kTexturesExtension = "textures";
constexpr std::int64_t kMaxTextureSide = 4096;

// A key that only an extension listed in "requires" allows.
[[noreturn]] void refuse_extension_key(const Node& v, std::string_view key,
                                       std::string_view extension) {
    v.fail("the key \"" + std::string(key) + "\" belongs to the extension \"" +
           std::string(extension) + "\"; list it in \"requires\" to use it");
}

// What a draw may say about textures: whether "requires" lists "textures", and the textures
// the file defines.
struct TextureScope {
    bool allowed = false;
    const std::map<std::string, refraster::Texture>* defined = nullptr;
};

// The extension "polygons": the primitive "polygon" (GL_POLYGON) and the draw state key
// "fill_rule" (docs/scene-format.md).
constexpr std::string_view kPolygonsExtension = "polygons";

refraster::Rect read_rect(const Node& n, std::int64_t origin_lo, std::int64_t origin_hi,
                          std::int64_t size_lo, std::int64_t size_hi) {
    n.array_size(4, 4, "[x, y, width, height]");
    return {static_cast<std::int32_t>(n[0].integer(origin_lo, origin_hi)),
            static_cast<std::int32_t>(n[1].integer(origin_lo, origin_hi)),
            static_cast<std::int32_t>(n[2].integer(size_lo, size_hi)),
            static_cast<std::int32_t>(n[3].integer(size_lo, size_hi))};
}

std::array<float, 4> read_color(const Node& n) {
    n.array_size(4, 4, "four numbers [r, g, b, a]");
    return {n[0].f32(), n[1].f32(), n[2].f32(), n[3].f32()};
}

// A vertex's "texcoord": [s, t] (r = 0, q = 1) or [s, t, r, q], each number as a colour's.
std::array<float, 4> read_texcoord(const Node& n) {
    const std::size_t size = n.array_size(2, 4, "[s, t] or [s, t, r, q]");
    if (size == 3) n.fail("expected [s, t] or [s, t, r, q], got an array of 3");
    std::array<float, 4> t{0.0f, 0.0f, 0.0f, 1.0f};
    std::size_t k = 0;
    n.for_each([&](const Node& e) { t[k++] = e.f32(); });
    return t;
}

// The draw state key "texture": texture unit 0. `name` receives the texture's name.
refraster::TextureState read_texture_state(const Node& n,
                                           const std::map<std::string, refraster::Texture>& defined,
                                           std::string& name) {
    using namespace refraster;
    n.require_object({"name", "min_filter", "mag_filter", "wrap_s", "wrap_t", "border_color", "env",
                      "coord_replace", "point_coord_origin"});
    TextureState t;
    const Node name_node = n.at("name");
    const auto it = defined.find(name_node.string());
    if (it == defined.end()) {
        std::string known;
        std::size_t listed = 0;
        for (const auto& [k, _] : defined) {
            if (listed == 8) {
                known += ", ... (" + std::to_string(defined.size()) + " in all)";
                break;
            }
            known += (listed++ == 0 ? "" : ", ") + quoted_value(k);
        }
        name_node.fail("no texture named " + quoted_value(name_node.string_view()) +
                       (defined.empty() ? std::string("; the scene defines none (\"textures\")")
                                        : "; the scene defines " + known));
    }
    name = it->first;
    t.texture = static_cast<std::uint32_t>(std::distance(defined.begin(), it));
    if (auto v = n.get("min_filter")) {
        t.min_filter = v->choice<TextureFilter>(
            {{"nearest", TextureFilter::Nearest},
             {"linear", TextureFilter::Linear},
             {"nearest_mipmap_nearest", TextureFilter::NearestMipmapNearest},
             {"linear_mipmap_nearest", TextureFilter::LinearMipmapNearest},
             {"nearest_mipmap_linear", TextureFilter::NearestMipmapLinear},
             {"linear_mipmap_linear", TextureFilter::LinearMipmapLinear}});
        const Texture& tex = it->second;
        if (uses_mipmaps(t.min_filter) && tex.levels.size() == 1 && !tex.generate_mipmaps) {
            v->fail("the filter " + quoted_value(v->string_view()) +
                    " samples mipmaps, and the texture " + quoted_value(it->first) +
                    " has neither \"levels\" nor \"mipmaps\": \"generate\"");
        }
    }
    if (auto v = n.get("mag_filter")) {
        t.mag_filter = v->choice<TextureFilter>(
            {{"nearest", TextureFilter::Nearest}, {"linear", TextureFilter::Linear}});
    }
    const auto wrap = [](const Node& v) {
        return v.choice<TextureWrap>({{"repeat", TextureWrap::Repeat},
                                      {"clamp_to_edge", TextureWrap::ClampToEdge},
                                      {"mirrored_repeat", TextureWrap::MirroredRepeat},
                                      {"clamp_to_border", TextureWrap::ClampToBorder}});
    };
    if (auto v = n.get("wrap_s")) t.wrap_s = wrap(*v);
    if (auto v = n.get("wrap_t")) t.wrap_t = wrap(*v);
    if (auto v = n.get("border_color")) t.border_color = read_color(*v);
    if (auto v = n.get("env")) {
        t.env = v->choice<TextureEnv>(
            {{"modulate", TextureEnv::Modulate}, {"replace", TextureEnv::Replace}});
    }
    if (auto v = n.get("coord_replace")) t.coord_replace = v->boolean();
    if (auto v = n.get("point_coord_origin")) {
        t.point_coord_origin =
            v->choice<PointCoordOrigin>({{"upper_left", PointCoordOrigin::UpperLeft},
                                         {"lower_left", PointCoordOrigin::LowerLeft}});
    }
    return t;
}

// A draw's "state". `texture_name` receives the name of the texture it samples, if any.
refraster::DrawState read_state(const Node& n, const refraster::Target& target,
                                const TextureScope& textures, bool polygons,
                                std::string& texture_name) {
    using namespace refraster;
    DrawState s;
    s.viewport = {0, 0, static_cast<std::int32_t>(target.width),
                  static_cast<std::int32_t>(target.height)};
    if (!textures.allowed && n.is_object()) {
        if (auto v = n.get("texture")) refuse_extension_key(*v, "texture", kTexturesExtension);
    }
    if (!polygons && n.is_object()) {
        if (auto v = n.get("fill_rule")) refuse_extension_key(*v, "fill_rule", kPolygonsExtension);
    }
    std::vector<std::string_view> keys{"viewport",     "depth_range",    "scissor",
                                       "cull",         "front_face",     "depth_test",
                                       "depth_write",  "shade",          "provoking_vertex",
                                       "polygon_mode", "polygon_offset", "line_width",
                                       "point_size",   "blend",          "multisample"};
    if (textures.allowed) keys.push_back("texture");
    if (polygons) keys.push_back("fill_rule");
    n.require_object(keys);
    if (auto v = n.get("viewport")) {
        s.viewport = read_rect(*v, kViewportOriginMin, kViewportOriginMax, 1, kMaxTargetSide);
    }
    if (auto v = n.get("depth_range")) {
        v->array_size(2, 2, "[near, far]");
        s.depth_near = (*v)[0].f32_in(0.0f, 1.0f);
        s.depth_far = (*v)[1].f32_in(0.0f, 1.0f);
    }
    if (auto v = n.get("scissor"); v && !v->is_null()) {
        s.scissor = read_rect(*v, -kScissorLimit, kScissorLimit, 0, kScissorLimit);
    }
    if (auto v = n.get("cull")) {
        s.cull = v->choice<CullMode>({{"none", CullMode::None},
                                      {"front", CullMode::Front},
                                      {"back", CullMode::Back},
                                      {"front_and_back", CullMode::FrontAndBack}});
    }
    if (auto v = n.get("front_face")) {
        s.front_face = v->choice<FrontFace>({{"ccw", FrontFace::Ccw}, {"cw", FrontFace::Cw}});
    }
    if (auto v = n.get("depth_test"); v && !v->is_null()) {
        s.depth_test = v->choice<CompareFunc>({{"never", CompareFunc::Never},
                                               {"less", CompareFunc::Less},
                                               {"equal", CompareFunc::Equal},
                                               {"lequal", CompareFunc::Lequal},
                                               {"greater", CompareFunc::Greater},
                                               {"notequal", CompareFunc::NotEqual},
                                               {"gequal", CompareFunc::Gequal},
                                               {"always", CompareFunc::Always}});
    }
    if (auto v = n.get("depth_write")) s.depth_write = v->boolean();
    if (auto v = n.get("shade")) {
        s.shade = v->choice<ShadeModel>({{"smooth", ShadeModel::Smooth},
                                         {"flat", ShadeModel::Flat},
                                         {"noperspective", ShadeModel::NoPerspective}});
    }
    if (auto v = n.get("provoking_vertex")) {
        s.provoking_vertex = v->choice<ProvokingVertex>(
            {{"last", ProvokingVertex::Last}, {"first", ProvokingVertex::First}});
    }
    if (auto v = n.get("polygon_mode")) {
        s.polygon_mode = v->choice<PolygonMode>({{"fill", PolygonMode::Fill},
                                                 {"line", PolygonMode::Line},
                                                 {"point", PolygonMode::Point}});
    }
    if (auto v = n.get("polygon_offset"); v && !v->is_null()) {
        v->require_object({"factor", "units"});
        s.polygon_offset = PolygonOffset{v->at("factor").f32(), v->at("units").f32()};
    }
    // Any width and size in (0, 255]: GL clamps what is below 1 to the implementation's
    // ALIASED_LINE_WIDTH_RANGE and POINT_SIZE_RANGE (1..255 in llvmpipe), so they draw as 1.
    if (auto v = n.get("line_width")) s.line_width = v->f32_above(0.0f, 255.0f);
    if (auto v = n.get("point_size")) s.point_size = v->f32_above(0.0f, 255.0f);
    if (auto v = n.get("blend"); v && !v->is_null()) {
        s.blend =
            v->choice<BlendPreset>({{"alpha", BlendPreset::Alpha}, {"add", BlendPreset::Add}});
    }
    // GL_MULTISAMPLE; an addition to format v1, allowed without "requires".
    if (auto v = n.get("multisample")) s.multisample = v->boolean();
    if (textures.allowed) {
        if (auto v = n.get("texture"); v && !v->is_null()) {
            s.texture = read_texture_state(*v, *textures.defined, texture_name);
        }
    }
    if (polygons) {
        if (auto v = n.get("fill_rule"); v && !v->is_null()) {
            s.fill_rule = v->choice<FillRule>(
                {{"evenodd", FillRule::EvenOdd}, {"nonzero", FillRule::NonZero}});
        }
    }
    return s;
}

// What the draws read so far ask for, against SceneLimits.
struct WorkSoFar {
    const SceneLimits& limits;
    std::uint64_t vertices = 0;
    std::uint64_t indices = 0;
    std::uint64_t primitives = 0;

    // Adds `count` to `total`; refuses at `where` when that passes `limit`.
    static void add(const Node& where, std::uint64_t& total, std::uint64_t count,
                    std::uint64_t limit, const char* what) {
        total += count;
        if (total > limit) {
            where.fail("this brings the scene to " + std::to_string(total) + " " + what +
                       ", over the limit of " + std::to_string(limit) + " (docs/limits.md)");
        }
    }
};

// Base64 (RFC 4648, section 4: A-Z a-z 0-9 + /, padded with '=' to a multiple of four
// characters) of the "vertex_arrays" extension, decoded strictly: no whitespace, no other
// alphabet, padding only at the end and its unused bits zero, so that one byte string has
// one spelling. Refusals name the string's path and the character's offset.
constexpr std::uint8_t kNotBase64 = 0x80;
constexpr auto kBase64Values = [] {
    std::array<std::uint8_t, 256> t{};
    t.fill(kNotBase64);
    const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (std::uint8_t i = 0; i < 64; ++i) t[static_cast<unsigned char>(alphabet[i])] = i;
    return t;
}();

std::string describe_character(std::string_view s, std::size_t at) {
    const auto u = static_cast<unsigned char>(s[at]);
    if (u >= 0x80) {
        char buf[16];
        std::snprintf(buf, sizeof buf, "byte 0x%02X", u);
        return buf;
    }
    return quoted_value(s.substr(at, 1));
}

// The bytes `s` decodes to when it is well formed: 3 a group of four characters, less the
// padding; 0 for a length that is no multiple of 4.
std::size_t base64_decoded_size(std::string_view s) {
    if (s.size() % 4 != 0) return 0;
    std::size_t pad = 0;
    if (!s.empty() && s.back() == '=') pad = s[s.size() - 2] == '=' ? 2 : 1;
    return s.size() / 4 * 3 - pad;
}

// Decodes `s` into `out`, which has room for s.size() / 4 * 3 bytes; returns the bytes written.
std::size_t decode_base64_into(const Node& n, std::string_view s, std::uint8_t* out) {
    if (s.size() % 4 != 0) {
        n.fail("base64 text of " + std::to_string(s.size()) +
               " characters; expected a multiple of 4 (padded with '=')");
    }
    std::size_t pad = 0;
    if (!s.empty() && s.back() == '=') pad = s[s.size() - 2] == '=' ? 2 : 1;
    const std::size_t body = s.size() - pad;
    const auto* in = reinterpret_cast<const unsigned char*>(s.data());
    const auto bad_character = [&](std::size_t from, std::size_t to) {
        for (std::size_t k = from; k < to; ++k) {
            if (kBase64Values[in[k]] == kNotBase64) {
                n.fail("character " + std::to_string(k) + " (" + describe_character(s, k) + ")" +
                       (s[k] == '=' ? " is padding before the end" : " is not base64"));
            }
        }
    };
    // Whole groups of four characters, then the last one with its padding.
    const std::size_t whole = pad == 0 ? s.size() : s.size() - 4;
    std::size_t o = 0;
    for (std::size_t i = 0; i < whole; i += 4, o += 3) {
        const std::uint8_t a = kBase64Values[in[i]];
        const std::uint8_t b = kBase64Values[in[i + 1]];
        const std::uint8_t c = kBase64Values[in[i + 2]];
        const std::uint8_t d = kBase64Values[in[i + 3]];
        if (((a | b | c | d) & kNotBase64) != 0) bad_character(i, i + 4);
        const std::uint32_t v =
            (std::uint32_t{a} << 18) | (std::uint32_t{b} << 12) | (std::uint32_t{c} << 6) | d;
        out[o] = static_cast<std::uint8_t>(v >> 16);
        out[o + 1] = static_cast<std::uint8_t>(v >> 8);
        out[o + 2] = static_cast<std::uint8_t>(v);
    }
    if (pad != 0) {
        bad_character(whole, body);
        std::uint32_t v = 0;
        for (std::size_t k = whole; k < body; ++k) v = (v << 6) | kBase64Values[in[k]];
        const std::size_t bytes = 3 - pad;
        const std::uint32_t unused_bits = pad == 2 ? 4 : 2;
        if ((v & ((1u << unused_bits) - 1)) != 0) {
            n.fail(
                "the bits below the last byte, before the padding, are not zero (base64 "
                "has one spelling of each byte string)");
        }
        v >>= unused_bits;
        for (std::size_t k = 0; k < bytes; ++k) {
            out[o + k] = static_cast<std::uint8_t>(v >> (8 * (bytes - 1 - k)));
        }
        o += bytes;
    }
    return o;
}

std::vector<std::uint8_t> decode_base64(const Node& n, std::string_view s) {
    std::vector<std::uint8_t> out(s.size() / 4 * 3);
    out.resize(decode_base64_into(n, s, out.data()));
    return out;
}

std::uint32_t little_endian_u32(const std::uint8_t* p) {
    return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
           (std::uint32_t{p[3]} << 24);
}

// The extension "vertex_arrays": a draw's vertices as one flat array per attribute.
constexpr std::string_view kVertexArraysExtension = "vertex_arrays";

// One attribute of "vertex_arrays" ({"components": N, "values": [...]} or {"components": N,
// "float32_base64": "..."}): count x components float32 values, vertex after vertex. Every
// value is checked as a number of a plain vertex is: rounded once to float32 and finite; in
// window space with four components, w > 0 as well.
struct AttributeArray {
    std::uint32_t components = 0;
    std::vector<float> values;
};

enum class AttributeKind : std::uint8_t { Position, Color, Texcoord };

AttributeArray read_attribute(const Node& a, std::size_t count, AttributeKind kind,
                              VertexSpace space) {
    const bool is_position = kind == AttributeKind::Position;
    AttributeArray out;
    a.require_object({"components", "values", "float32_base64"});
    {
        const Node c = a.at("components");
        if (kind == AttributeKind::Texcoord) {
            const auto n = c.integer(std::numeric_limits<std::int64_t>::min(),
                                     std::numeric_limits<std::int64_t>::max());
            if (n != 2 && n != 4) {
                c.fail("expected 2 ([s, t]) or 4 ([s, t, r, q]), got " + number_text(c.value()));
            }
            out.components = static_cast<std::uint32_t>(n);
        } else if (!is_position) {
            if (c.integer(std::numeric_limits<std::int64_t>::min(),
                          std::numeric_limits<std::int64_t>::max()) != 4) {
                c.fail("expected 4 ([r, g, b, a]), got " + number_text(c.value()));
            }
            out.components = 4;
        } else if (space == VertexSpace::Clip) {
            if (c.integer(std::numeric_limits<std::int64_t>::min(),
                          std::numeric_limits<std::int64_t>::max()) != 4) {
                c.fail("expected 4 ([x, y, z, w], space \"clip\"), got " + number_text(c.value()));
            }
            out.components = 4;
        } else {
            out.components = static_cast<std::uint32_t>(c.integer(2, 4));
        }
    }
    const bool window_w = is_position && space == VertexSpace::Window && out.components == 4;
    const auto values = a.get("values");
    const auto base64 = a.get("float32_base64");
    if (values && base64) {
        base64->fail("give either \"values\" or \"float32_base64\", not both");
    }
    if (!values && !base64) a.fail("missing required key \"values\" (or \"float32_base64\")");
    // count is at most the vertex limit and components at most 4: no overflow.
    const std::size_t total = count * out.components;
    out.values.resize(total);
    if (values) {
        const std::string what = std::to_string(total) + " numbers (count " +
                                 std::to_string(count) + " x " + std::to_string(out.components) +
                                 " components)";
        values->array_size(total, total, what.c_str());
        float* dst = out.values.data();
        // Numbers finite in float32 (and w > 0) in one loop; at a fault, the loop below reads
        // the array again to refuse it with its path.
        bool fast = true;
        for (const dom::element e : as_array(values->value())) {
            double d = 0;
            if (e.get_double().get(d) != simdjson::SUCCESS) {
                fast = false;
                break;
            }
            const float f = static_cast<float>(d);
            if (!std::isfinite(f) ||
                (window_w && (dst - out.values.data()) % 4 == 3 && !(f > 0.0f))) {
                fast = false;
                break;
            }
            *dst++ = f;
        }
        if (fast) return out;
        dst = out.values.data();
        values->for_each([&](const Node& e) {
            const float f = e.f32();
            if (window_w && (dst - out.values.data()) % 4 == 3 && !(f > 0.0f)) {
                e.fail("expected w > 0 in window space, got " + number_text(e.value()));
            }
            *dst++ = f;
        });
        return out;
    }
    const std::string_view text = base64->string_view();
    if (base64_decoded_size(text) != total * 4) {
        // The refusal: a fault of the text itself first, else the size.
        const std::vector<std::uint8_t> bytes = decode_base64(*base64, text);
        base64->fail("decodes to " + std::to_string(bytes.size()) + " bytes, expected " +
                     std::to_string(total * 4) + " (count " + std::to_string(count) + " x " +
                     std::to_string(out.components) + " components x 4 bytes)");
    }
    // Straight into the values (room for whole groups: the last may be padded), then read as
    // little-endian float32 in place.
    out.values.resize((text.size() / 4 * 3 + 3) / 4);
    auto* const bytes = reinterpret_cast<std::uint8_t*>(out.values.data());
    decode_base64_into(*base64, text, bytes);
    out.values.resize(total);
    for (std::size_t k = 0; k < total; ++k) {
        const float f = std::bit_cast<float>(little_endian_u32(bytes + 4 * k));
        const bool w = window_w && k % 4 == 3;
        if (!std::isfinite(f) || (w && !(f > 0.0f))) {
            const std::string where = "value " + std::to_string(k) + " (vertex " +
                                      std::to_string(k / out.components) + ", component " +
                                      std::to_string(k % out.components) + ")";
            if (std::isnan(f)) base64->fail(where + " is NaN; expected finite float32 values");
            if (std::isinf(f)) {
                base64->fail(where + " is infinite; expected finite float32 values");
            }
            base64->fail(where + ": expected w > 0 in window space, got " +
                         number_text(static_cast<double>(f)));
        }
        out.values[k] = f;
    }
    return out;
}

// A draw's "vertex_arrays": the same SceneVertex list the plain "vertices" would give.
// `textures`: "requires" lists "textures", which allows the attribute "texcoord".
void read_vertex_arrays(const Node& va, SceneDraw& d, WorkSoFar& work, bool textures) {
    if (!textures && va.is_object()) {
        if (auto v = va.get("texcoord")) refuse_extension_key(*v, "texcoord", kTexturesExtension);
    }
    if (textures) {
        va.require_object({"count", "position", "color", "texcoord"});
    } else {
        va.require_object({"count", "position", "color"});
    }
    const auto count = static_cast<std::size_t>(
        va.at("count").integer(0, std::numeric_limits<std::uint32_t>::max()));
    // Before anything of that size is allocated.
    WorkSoFar::add(va, work.vertices, count, work.limits.max_vertices, "vertices");
    const AttributeArray position =
        read_attribute(va.at("position"), count, AttributeKind::Position, d.space);
    std::optional<AttributeArray> color;
    if (auto c = va.get("color")) color = read_attribute(*c, count, AttributeKind::Color, d.space);
    std::optional<AttributeArray> texcoord;
    if (auto t = textures ? va.get("texcoord") : std::nullopt) {
        texcoord = read_attribute(*t, count, AttributeKind::Texcoord, d.space);
    }
    d.vertices.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        SceneVertex sv;
        sv.position_size = position.components;
        const float* p = position.values.data() + i * position.components;
        std::copy(p, p + position.components, sv.position.begin());
        if (color) std::copy_n(color->values.data() + i * 4, 4, sv.color.begin());
        if (texcoord) {
            const std::uint32_t n = texcoord->components;
            std::copy_n(texcoord->values.data() + i * n, n, sv.texcoord.begin());
        }
        d.vertices.push_back(sv);
    }
}

// "indices": {"uint32_base64": "..."} under "vertex_arrays": little-endian uint32 values.
std::vector<std::uint32_t> read_index_base64(const Node& n, std::size_t count, WorkSoFar& work) {
    n.require_object({"uint32_base64"});
    const Node s = n.at("uint32_base64");
    const std::vector<std::uint8_t> bytes = decode_base64(s, s.string_view());
    if (bytes.size() % 4 != 0) {
        s.fail("decodes to " + std::to_string(bytes.size()) +
               " bytes, not a whole number of 4-byte uint32 indices");
    }
    const std::size_t ni = bytes.size() / 4;
    WorkSoFar::add(n, work.indices, ni, work.limits.max_indices, "indices");
    std::vector<std::uint32_t> idx(ni);
    for (std::size_t i = 0; i < ni; ++i) {
        idx[i] = little_endian_u32(bytes.data() + 4 * i);
        if (count == 0) s.fail("index " + std::to_string(i) + " into an empty vertex list");
        if (idx[i] >= count) {
            s.fail("index " + std::to_string(i) + ": expected an integer in [0, " +
                   std::to_string(count - 1) + "], got " + std::to_string(idx[i]));
        }
    }
    return idx;
}

// A plain vertex, {"position": [...], "color": [...]} (and "texcoord" with the extension
// "textures"), read by the general path: every fault refused with its path.
void read_vertex(const Node& vn, VertexSpace space, SceneVertex& sv, bool textures) {
    if (!textures && vn.is_object()) {
        if (auto v = vn.get("texcoord")) refuse_extension_key(*v, "texcoord", kTexturesExtension);
    }
    if (textures) {
        vn.require_object({"position", "color", "texcoord"});
    } else {
        vn.require_object({"position", "color"});
    }
    const Node p = vn.at("position");
    if (space == VertexSpace::Clip) {
        p.array_size(4, 4, "[x, y, z, w] (space \"clip\")");
    } else {
        p.array_size(2, 4, "[x, y], [x, y, z] or [x, y, z, w] (space \"window\")");
    }
    std::uint32_t c = 0;
    p.for_each([&](const Node& e) {
        sv.position[c] = e.f32();
        if (c == 3 && space == VertexSpace::Window && !(sv.position[3] > 0.0f)) {
            e.fail("expected w > 0 in window space, got " + number_text(e.value()));
        }
        ++c;
    });
    sv.position_size = c;
    if (auto col = vn.get("color")) sv.color = read_color(*col);
    if (auto t = textures ? vn.get("texcoord") : std::nullopt) sv.texcoord = read_texcoord(*t);
}

// Between `min` and `max` numbers, each finite once rounded to float32, into `out`; false for
// anything else.
bool read_floats_fast(dom::element e, std::size_t min, std::size_t max, float* out,
                      std::size_t& n) {
    dom::array a;
    if (e.get_array().get(a) != simdjson::SUCCESS) return false;
    std::size_t k = 0;
    for (const dom::element x : a) {
        double d = 0;
        if (k == max || x.get_double().get(d) != simdjson::SUCCESS) return false;
        const float f = static_cast<float>(d);
        if (!std::isfinite(f)) return false;
        out[k++] = f;
    }
    n = k;
    return k >= min;
}

// The common shape of a plain vertex, {"position": [...], "color": [r, g, b, a]} (any key
// first, the colour optional; with `textures` an optional "texcoord" too), read in one pass over
// its keys: the same values as read_vertex. False for anything else, which read_vertex then
// takes from the start, to accept or to refuse with its path. On success adds the vertex's
// containers to `containers`; the caller has checked that their nesting is allowed.
bool read_vertex_fast(dom::element e, VertexSpace space, SceneVertex& sv, std::uint64_t& containers,
                      bool textures) {
    dom::object o;
    if (e.get_object().get(o) != simdjson::SUCCESS) return false;
    bool position = false;
    bool color = false;
    bool texcoord = false;
    for (const dom::key_value_pair kv : o) {
        std::size_t n = 0;
        if (kv.key == "position" && !position) {
            position = true;
            const std::size_t min = space == VertexSpace::Clip ? 4 : 2;
            if (!read_floats_fast(kv.value, min, 4, sv.position.data(), n)) return false;
            if (n == 4 && space == VertexSpace::Window && !(sv.position[3] > 0.0f)) return false;
            sv.position_size = static_cast<std::uint32_t>(n);
        } else if (kv.key == "color" && !color) {
            color = true;
            if (!read_floats_fast(kv.value, 4, 4, sv.color.data(), n)) return false;
        } else if (kv.key == "texcoord" && textures && !texcoord) {
            texcoord = true;
            if (!read_floats_fast(kv.value, 2, 4, sv.texcoord.data(), n) || n == 3) return false;
        } else {
            return false;
        }
    }
    if (!position) return false;
    containers += 2u + (color ? 1u : 0u) + (texcoord ? 1u : 0u);
    return true;
}

SceneDraw read_draw(const Node& n, const refraster::Target& target, WorkSoFar& work,
                    bool vertex_arrays_allowed, const TextureScope& textures, bool polygons) {
    using namespace refraster;
    SceneDraw d;
    if (!vertex_arrays_allowed && n.is_object()) {
        if (auto v = n.get("vertex_arrays")) {
            refuse_extension_key(*v, "vertex_arrays", kVertexArraysExtension);
        }
    }
    if (vertex_arrays_allowed) {
        n.require_object(
            {"primitive", "space", "matrix", "vertices", "vertex_arrays", "indices", "state"});
    } else {
        n.require_object({"primitive", "space", "matrix", "vertices", "indices", "state"});
    }
    const Node primitive = n.at("primitive");
    if (!polygons && primitive.is_string() && primitive.string_view() == "polygon") {
        primitive.fail(
            "the primitive \"polygon\" belongs to the extension \"polygons\"; list it in "
            "\"requires\" to use it");
    }
    // Format v1's primitives, and the extension's "polygon" last: offered only with it.
    static constexpr std::array<std::pair<std::string_view, PrimitiveType>, 8> kPrimitives{{
        {"points", PrimitiveType::Points},
        {"lines", PrimitiveType::Lines},
        {"line_strip", PrimitiveType::LineStrip},
        {"line_loop", PrimitiveType::LineLoop},
        {"triangles", PrimitiveType::Triangles},
        {"triangle_strip", PrimitiveType::TriangleStrip},
        {"triangle_fan", PrimitiveType::TriangleFan},
        {"polygon", PrimitiveType::Polygon},
    }};
    d.primitive = primitive.choice(std::span<const std::pair<std::string_view, PrimitiveType>>(
        kPrimitives.data(), polygons ? kPrimitives.size() : kPrimitives.size() - 1));
    if (auto v = n.get("space")) {
        d.space =
            v->choice<VertexSpace>({{"window", VertexSpace::Window}, {"clip", VertexSpace::Clip}});
    }
    if (auto v = n.get("matrix")) {
        if (d.space != VertexSpace::Clip) {
            v->fail("\"matrix\" is allowed only with \"space\": \"clip\"");
        }
        v->array_size(16, 16, "16 numbers (column-major)");
        std::array<float, 16> m{};
        std::size_t i = 0;
        v->for_each([&](const Node& e) { m[i++] = e.f32(); });
        d.matrix = m;
    }
    const auto arrays = vertex_arrays_allowed ? n.get("vertex_arrays") : std::nullopt;
    if (arrays) {
        if (n.get("vertices")) {
            arrays->fail("give either \"vertices\" or \"vertex_arrays\", not both");
        }
        d.from_vertex_arrays = true;
        read_vertex_arrays(*arrays, d, work, textures.allowed);
    } else {
        if (vertex_arrays_allowed && !n.get("vertices")) {
            n.fail("missing required key \"vertices\" (or \"vertex_arrays\")");
        }
        const Node verts = n.at("vertices");
        const std::size_t count =
            verts.array_size(0, std::numeric_limits<std::uint32_t>::max(), "an array of vertices");
        WorkSoFar::add(verts, work.vertices, count, work.limits.max_vertices, "vertices");
        d.vertices.reserve(count);
        // The fast path takes a vertex's object and its two arrays, one and two levels below
        // the list, only where that nesting is allowed.
        const bool fast = verts.depth() + 2 < work.limits.max_nesting_depth;
        std::size_t i = 0;
        for (const dom::element e : as_array(verts.value())) {
            SceneVertex sv;
            if (!fast ||
                !read_vertex_fast(e, d.space, sv, verts.context().containers, textures.allowed)) {
                sv = SceneVertex{};
                read_vertex(Node(e, verts, i), d.space, sv, textures.allowed);
            }
            d.vertices.push_back(sv);
            ++i;
        }
    }
    const std::size_t count = d.vertices.size();
    if (auto v = n.get("indices")) {
        if (vertex_arrays_allowed && v->is_object()) {
            d.indices = read_index_base64(*v, count, work);
        } else {
            const std::size_t ni =
                v->array_size(0, std::numeric_limits<std::uint32_t>::max(), "an array of indices");
            WorkSoFar::add(*v, work.indices, ni, work.limits.max_indices, "indices");
            std::vector<std::uint32_t> idx(ni);
            std::size_t i = 0;
            v->for_each([&](const Node& e) {
                if (count == 0) e.fail("index into an empty vertex list");
                idx[i++] =
                    static_cast<std::uint32_t>(e.integer(0, static_cast<std::int64_t>(count) - 1));
            });
            d.indices = std::move(idx);
        }
    }
    // Indices may repeat a vertex any number of times: the primitives are what costs.
    const std::size_t elements = d.indices ? d.indices->size() : d.vertices.size();
    WorkSoFar::add(n, work.primitives, refraster::primitive_count(d.primitive, elements),
                   work.limits.max_primitives, "primitives");
    if (auto v = n.get("state")) {
        d.state = read_state(*v, target, textures, polygons, d.texture);
        if (d.state.fill_rule) {
            // A fill rule lights the region of one polygon whatever its orientation: it needs
            // the primitive "polygon", polygon mode fill and no culling (docs/scene-format.md,
            // "Fill rules").
            const Node rule = v->at("fill_rule");
            if (d.primitive != PrimitiveType::Polygon) {
                rule.fail("a fill rule applies to the primitive \"polygon\" only, not to \"" +
                          std::string(refraster::to_string(d.primitive)) + "\"");
            }
            if (d.state.polygon_mode != PolygonMode::Fill) {
                rule.fail("a fill rule fills the polygon; it needs \"polygon_mode\": \"fill\"");
            }
            if (d.state.cull != CullMode::None) {
                rule.fail(
                    "a fill rule fills the polygon whatever its orientation; it needs "
                    "\"cull\": \"none\"");
            }
        }
    } else {
        d.state.viewport = {0, 0, static_cast<std::int32_t>(target.width),
                            static_cast<std::int32_t>(target.height)};
    }
    return d;
}

// The extensions this reader implements. "multisample": the draw state key "multisample"
// (GL_MULTISAMPLE) on 4x targets; the key is part of format v1 too, and a file may still list
// the name to say that it relies on it. "vertex_arrays": a draw's vertices as flat arrays per
// attribute, and indices as base64 (docs/scene-format.md); the loader turns them into the same
// vertices as the plain form, so every renderer draws them. "textures": textures by name,
// texture coordinates and each draw's texture unit state, which the draw list carries.
// "polygons": the primitive "polygon" and the draw state key "fill_rule".
bool is_implemented_extension(std::string_view name) {
    return name == "multisample" || name == kVertexArraysExtension || name == kTexturesExtension ||
           name == kPolygonsExtension;
}

// The texel bytes of the textures read so far, against SceneLimits::max_texel_bytes.
struct TexelBudget {
    const SceneLimits& limits;
    std::uint64_t bytes = 0;

    void add(const Node& where, std::uint64_t n) {
        bytes += n;
        if (bytes > limits.max_texel_bytes) {
            where.fail("this brings the scene's textures to " + std::to_string(bytes) +
                       " bytes of texels, over the limit of " +
                       std::to_string(limits.max_texel_bytes) + " (docs/limits.md)");
        }
    }
};

std::string size_text(std::uint32_t width, std::uint32_t height) {
    return std::to_string(width) + " x " + std::to_string(height);
}

// One image of a texture: its base (`level` 0) or level `level` of "levels", which must be
// exactly max(1, base_width >> level) x max(1, base_height >> level). Either "width", "height"
// and "data" (base64 of width x height RGBA8 texels, rows bottom to top), or "file" (a PNG,
// relative to `base_dir`) with "width" and "height" optional and then checked.
refraster::TextureImage read_texture_image(const Node& n, std::uint32_t level,
                                           std::uint32_t base_width, std::uint32_t base_height,
                                           const std::filesystem::path& base_dir,
                                           TexelBudget& budget) {
    const auto data = n.get("data");
    const auto file = n.get("file");
    if (data && file) file->fail("give either \"data\" or \"file\", not both");
    if (!data && !file) n.fail("missing required key \"data\" (or \"file\")");
    const std::uint32_t want_width = level == 0 ? 0 : std::max(1u, base_width >> level);
    const std::uint32_t want_height = level == 0 ? 0 : std::max(1u, base_height >> level);
    const auto level_size = [&] {
        return "level " + std::to_string(level) + " of a " + size_text(base_width, base_height) +
               " texture is " + size_text(want_width, want_height) + " (max(1, size >> " +
               std::to_string(level) + "))";
    };
    const auto read_side = [&](std::string_view key, std::uint32_t want) {
        const auto v = data ? std::optional<Node>(n.at(key)) : n.get(key);
        if (!v) return std::optional<std::uint32_t>();
        const auto side = static_cast<std::uint32_t>(v->integer(1, kMaxTextureSide));
        if (level != 0 && side != want) {
            v->fail(level_size() + "; got " + std::string(key) + " " + std::to_string(side));
        }
        return std::optional<std::uint32_t>(side);
    };
    const std::optional<std::uint32_t> width = read_side("width", want_width);
    const std::optional<std::uint32_t> height = read_side("height", want_height);
    refraster::TextureImage image;
    if (data) {
        image.width = *width;
        image.height = *height;
        const std::uint64_t bytes = std::uint64_t{image.width} * image.height * 4;
        budget.add(n, bytes);
        const std::string_view text = data->string_view();
        if (base64_decoded_size(text) != bytes) {
            // The refusal: a fault of the text itself first, else the size.
            const std::vector<std::uint8_t> decoded = decode_base64(*data, text);
            data->fail("decodes to " + std::to_string(decoded.size()) + " bytes, expected " +
                       std::to_string(bytes) + " (width " + std::to_string(image.width) +
                       " x height " + std::to_string(image.height) + " x 4 bytes of RGBA8 texels)");
        }
        // Room for whole groups of the text; the padding leaves the last one short.
        image.rgba.resize(text.size() / 4 * 3);
        decode_base64_into(*data, text, image.rgba.data());
        image.rgba.resize(static_cast<std::size_t>(bytes));
        return image;
    }
    const std::string written = file->string();
    if (written.empty()) file->fail("expected the path of a PNG file, got an empty string");
    const std::filesystem::path path = base_dir / written;
    const std::string shown = escape_for_message(path.string());
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status))
        file->fail("cannot read " + shown + ": no such file");
    if (!std::filesystem::is_regular_file(status)) {
        file->fail("cannot read " + shown + ": not a regular file");
    }
    const TextureFileReader reader = texture_file_reader();
    if (reader == nullptr) {
        file->fail("cannot read " + shown +
                   ": this program reads no image files (it is built without harness_image_io); "
                   "give the texels as \"data\"");
    }
    bool checked = false;
    const auto check_size = [&](std::uint32_t w, std::uint32_t h) {
        checked = true;
        if (w < 1 || h < 1 || w > kMaxTextureSide || h > kMaxTextureSide) {
            file->fail(shown + " is " + size_text(w, h) +
                       " pixels; a texture is 1 to 4096 pixels a side");
        }
        if (width && w != *width) {
            file->fail(shown + " is " + size_text(w, h) + " pixels, but \"width\" is " +
                       std::to_string(*width));
        }
        if (height && h != *height) {
            file->fail(shown + " is " + size_text(w, h) + " pixels, but \"height\" is " +
                       std::to_string(*height));
        }
        if (level != 0 && (w != want_width || h != want_height)) {
            file->fail(level_size() + "; " + shown + " is " + size_text(w, h));
        }
        budget.add(n, std::uint64_t{w} * h * 4);
    };
    try {
        image = reader(path, check_size);
    } catch (const SceneError&) {
        throw;
    } catch (const std::exception& e) {
        file->fail(escape_for_message(e.what()));
    }
    if (!checked) check_size(image.width, image.height);
    if (image.rgba.size() != std::size_t{image.width} * image.height * 4) {
        file->fail(shown + ": the image reader returned " + std::to_string(image.rgba.size()) +
                   " bytes for " + size_text(image.width, image.height) + " texels");
    }
    return image;
}

// One texture: its base image, then "levels" (the given mipmap levels 1, 2, ...) or "mipmaps":
// "generate".
refraster::Texture read_texture(const Node& n, const std::filesystem::path& base_dir,
                                TexelBudget& budget) {
    n.require_object({"width", "height", "data", "file", "levels", "mipmaps"});
    refraster::Texture t;
    t.levels.push_back(read_texture_image(n, 0, 0, 0, base_dir, budget));
    const std::uint32_t width = t.levels[0].width;
    const std::uint32_t height = t.levels[0].height;
    // The levels below the base, down to 1 x 1.
    std::uint32_t below = 0;
    for (std::uint32_t m = std::max(width, height); m > 1; m >>= 1) ++below;
    const auto levels = n.get("levels");
    const auto mipmaps = n.get("mipmaps");
    if (levels && mipmaps) mipmaps->fail("give either \"levels\" or \"mipmaps\", not both");
    if (levels) {
        if (below == 0) {
            levels->fail("a 1 x 1 texture has no levels below its base; leave out \"levels\"");
        }
        const std::string what = "an array of 1 to " + std::to_string(below) +
                                 " levels (levels 1 to " + std::to_string(below) + " of a " +
                                 size_text(width, height) + " texture, down to 1 x 1)";
        levels->array_size(1, below, what.c_str());
        std::uint32_t level = 1;
        levels->for_each([&](const Node& e) {
            e.require_object({"width", "height", "data", "file"});
            t.levels.push_back(read_texture_image(e, level++, width, height, base_dir, budget));
        });
    }
    if (mipmaps) {
        t.generate_mipmaps = mipmaps->choice<bool>({{"generate", true}});
        // The levels glGenerateMipmap makes count too: every renderer holds them.
        std::uint64_t bytes = 0;
        for (std::uint32_t l = 1; l <= below; ++l) {
            bytes += std::uint64_t{std::max(1u, width >> l)} * std::max(1u, height >> l) * 4;
        }
        budget.add(*mipmaps, bytes);
    }
    return t;
}

// The top-level "textures": {"NAME": {...}, ...}.
std::map<std::string, refraster::Texture> read_textures(const Node& n,
                                                        const std::filesystem::path& base_dir,
                                                        const SceneLimits& limits) {
    const std::size_t count = n.members("an object of textures by name");
    if (count > limits.max_textures) {
        n.fail(std::to_string(count) + " textures exceed the limit of " +
               std::to_string(limits.max_textures) + " textures a scene (docs/limits.md)");
    }
    TexelBudget budget{limits};
    std::map<std::string, refraster::Texture> out;
    n.for_each_member([&](std::string_view name, const Node& t) {
        out.emplace(std::string(name), read_texture(t, base_dir, budget));
    });
    return out;
}

// Whether the root's "requires" lists `name`, looked at before anything is checked: which keys
// the root may hold depends on it. read_scene checks "requires" itself afterwards.
bool requires_lists(const Node& root, std::string_view name) {
    if (!root.is_object()) return false;
    const auto r = root.get("requires");
    dom::array a;
    if (!r || r->value().get_array().get(a) != simdjson::SUCCESS) return false;
    for (const dom::element e : a) {
        std::string_view s;
        if (e.get_string().get(s) == simdjson::SUCCESS && s == name) return true;
    }
    return false;
}

std::atomic<TextureFileReader> g_texture_file_reader{nullptr};

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
    : std::runtime_error(compose_message(file, json_path, message, line, column)),
      file_(std::move(file)),
      json_path_(std::move(json_path)),
      detail_(std::move(message)),
      line_(line),
      column_(column) {}

namespace {

SceneFile read_scene(const Node& root, const SceneLimits& limits) {
    using namespace refraster;
    const bool textures_allowed = requires_lists(root, kTexturesExtension);
    if (!textures_allowed && root.is_object()) {
        if (auto v = root.get("textures")) {
            refuse_extension_key(*v, "textures", kTexturesExtension);
        }
    }
    if (textures_allowed) {
        root.require_object({"format", "name", "description", "requires", "target", "clear",
                             "expect", "textures", "draws"});
    } else {
        root.require_object(
            {"format", "name", "description", "requires", "target", "clear", "expect", "draws"});
    }
    SceneFile s;
    const Node format = root.at("format");
    if (format.string_view() != kSceneFormatV1) {
        format.fail(std::string("expected \"") + kSceneFormatV1 + "\", got " +
                    describe(format.value()));
    }
    if (auto v = root.get("name")) s.name = v->string();
    if (auto v = root.get("description")) s.description = v->string();
    if (auto v = root.get("requires")) {
        v->array_size(0, 64, "an array of extension names");
        v->for_each([&](const Node& e) { s.requires_extensions.push_back(e.string()); });
    }
    const bool vertex_arrays_allowed =
        std::find(s.requires_extensions.begin(), s.requires_extensions.end(),
                  kVertexArraysExtension) != s.requires_extensions.end();

    const Node t = root.at("target");
    t.require_object({"width", "height", "color", "depth", "samples"});
    s.target.width = static_cast<std::uint32_t>(t.at("width").integer(1, kMaxTargetSide));
    s.target.height = static_cast<std::uint32_t>(t.at("height").integer(1, kMaxTargetSide));
    if (auto v = t.get("color")) {
        s.target.color = v->choice<ColorFormat>(
            {{"rgba8", ColorFormat::Rgba8}, {"rgba32f", ColorFormat::Rgba32f}});
    }
    if (auto v = t.get("depth")) {
        s.target.depth = v->choice<DepthFormat>({{"none", DepthFormat::None},
                                                 {"z16", DepthFormat::Z16},
                                                 {"z24", DepthFormat::Z24},
                                                 {"z32f", DepthFormat::Z32f}});
    }
    if (auto v = t.get("samples")) {
        const auto n = v->integer(1, 4);
        if (n != 1 && n != 4) v->fail("expected 1 or 4, got " + number_text(v->value()));
        s.target.samples = static_cast<std::uint32_t>(n);
    }
    const std::uint64_t area = std::uint64_t{s.target.width} * s.target.height * s.target.samples;
    if (area > limits.max_target_pixels) {
        t.fail("width x height x samples = " + std::to_string(area) + " exceeds the limit of " +
               std::to_string(limits.max_target_pixels));
    }

    if (auto c = root.get("clear")) {
        c->require_object({"color", "depth"});
        if (auto v = c->get("color")) s.clear.color = read_color(*v);
        if (auto v = c->get("depth")) s.clear.depth = v->f32_in(0.0f, 1.0f);
    }
    if (auto e = root.get("expect")) {
        e->require_object({"color_tolerance", "max_mismatched_pixels"});
        if (auto v = e->get("color_tolerance")) {
            s.expect.color_tolerance =
                static_cast<std::uint32_t>(v->integer(0, std::numeric_limits<std::int32_t>::max()));
        }
        if (auto v = e->get("max_mismatched_pixels")) {
            s.expect.max_mismatched_pixels =
                static_cast<std::uint64_t>(v->integer(0, kMaxTargetSamplesArea));
        }
    }

    if (auto v = textures_allowed ? root.get("textures") : std::nullopt) {
        // Relative file names start from the scene file's directory.
        s.textures =
            read_textures(*v, std::filesystem::path(root.context().file).parent_path(), limits);
    }
    const TextureScope textures{textures_allowed, &s.textures};
    const bool polygons_allowed =
        std::find(s.requires_extensions.begin(), s.requires_extensions.end(), kPolygonsExtension) !=
        s.requires_extensions.end();

    const Node draws = root.at("draws");
    const std::size_t nd =
        draws.array_size(0, std::numeric_limits<std::uint32_t>::max(), "an array of draws");
    if (nd > limits.max_draws) {
        draws.fail(std::to_string(nd) + " draws exceed the limit of " +
                   std::to_string(limits.max_draws) + " draws a scene (docs/limits.md)");
    }
    WorkSoFar work{limits};
    s.draws.reserve(nd);
    draws.for_each([&](const Node& d) {
        s.draws.push_back(
            read_draw(d, s.target, work, vertex_arrays_allowed, textures, polygons_allowed));
    });
    return s;
}

void check_file_size(std::uintmax_t size, const std::string& file_label,
                     const SceneLimits& limits) {
    if (size > limits.max_file_bytes) {
        throw SceneError(file_label, "",
                         "file of " + std::to_string(size) +
                             " bytes exceeds the scene size limit of " +
                             std::to_string(limits.max_file_bytes) + " bytes");
    }
}

// The refusal the strict parser gives a file that breaks a strict rule.
[[noreturn]] void refuse_strictly(std::string_view text, const std::string& file_label,
                                  const SceneLimits& limits) {
    check_strictly(text, file_label, limits, nullptr);
    throw SceneError(file_label, "", "the strict rules refuse this JSON, its parser does not");
}

// `padded`: SIMDJSON_PADDING readable bytes follow the text, so simdjson reads it in place.
SceneFile parse_scene_text(std::string_view text, bool padded, const std::string& file_label,
                           const SceneLimits& limits) {
    check_file_size(text.size(), file_label, limits);
    // One parser a thread, kept between loads: the pages of its buffers (about 4 bytes of
    // structural index and 8 of tape a byte of text, in part untouched) are faulted in once
    // rather than at every load of a large file.
    thread_local dom::parser parser;
    Document doc{parser, {}, {}, {}};
    parse_document(doc, text, padded, file_label, limits);
    // The walk checks the strict rules on what it reads. A strict fault takes precedence over
    // any other refusal, wherever it sits in the file: the strict parser names the first one.
    WalkContext context{file_label, limits};
    std::optional<SceneFile> scene;
    try {
        scene = read_scene(Node(doc.root, context), limits);
    } catch (const StrictFault&) {
        refuse_strictly(text, file_label, limits);
    } catch (const SceneError&) {
        if (!StrictScan(limits).ok(doc.root, 0)) refuse_strictly(text, file_label, limits);
        throw;
    }
    // Brackets inside strings (or a container the walk did not take) make the counts differ:
    // then the scan checks the whole document.
    if (context.containers != doc.counts.containers && !StrictScan(limits).ok(doc.root, 0)) {
        refuse_strictly(text, file_label, limits);
    }
    return std::move(*scene);
}

Scene finish_scene(SceneFile file, const std::string& file_label, const SceneLimits& limits) {
    Scene scene;
    scene.path = file_label;
    scene.file = std::move(file);
    scene.draw_list = run_front_end(scene.file, file_label);
    // The fragment estimate needs clip-space positions, so it follows the front end; nothing
    // has been drawn yet.
    std::uint64_t fragments = 0;
    for (std::size_t d = 0; d < scene.draw_list.draws.size(); ++d) {
        fragments += estimate_work(scene.draw_list.draws[d], scene.draw_list.target).fragments;
        if (fragments > limits.max_fragments) {
            throw SceneError(file_label, "draws[" + std::to_string(d) + "]",
                             "this brings the scene's estimated fragments to " +
                                 std::to_string(fragments) + ", over the limit of " +
                                 std::to_string(limits.max_fragments) + " (docs/limits.md)");
        }
    }
    // Required extensions this reader does not implement make the scene NotSupported.
    for (const auto& e : scene.file.requires_extensions) {
        if (!is_implemented_extension(e)) scene.unsupported_extensions.push_back(e);
    }
    return scene;
}

}  // namespace

void set_texture_file_reader(TextureFileReader reader) {
    g_texture_file_reader.store(reader);
}

TextureFileReader texture_file_reader() {
    return g_texture_file_reader.load();
}

SceneFile parse_scene(std::string_view text, const std::string& file_label,
                      const SceneLimits& limits) {
    return parse_scene_text(text, false, file_label, limits);
}

Scene load_scene_text(std::string_view text, const std::string& file_label,
                      const SceneLimits& limits) {
    return finish_scene(parse_scene_text(text, false, file_label, limits), file_label, limits);
}

Scene load_scene(const std::filesystem::path& path, const SceneLimits& limits) {
    const std::string label = path.string();
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) {
        throw SceneError(label, "", "cannot open: no such file");
    }
    if (std::filesystem::is_directory(status)) {
        throw SceneError(label, "", "is a directory, expected a scene file");
    }
    if (!std::filesystem::is_regular_file(status)) {
        throw SceneError(label, "", "is not a regular file");
    }
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) throw SceneError(label, "", "cannot read its size: " + ec.message());
    // Checked again on the text; here so that a huge file is not read at all.
    check_file_size(size, label, limits);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SceneError(label, "", "cannot open for reading");
    // Read straight into a buffer with simdjson's padding after the text, so that the parser
    // needs no copy of it; left uninitialized, as the read fills it.
    const auto n = static_cast<std::size_t>(size);
    auto buffer = std::make_unique_for_overwrite<char[]>(n + simdjson::SIMDJSON_PADDING);
    std::fill_n(buffer.get() + n, simdjson::SIMDJSON_PADDING, '\0');
    in.read(buffer.get(), static_cast<std::streamsize>(n));
    if (static_cast<std::uintmax_t>(in.gcount()) != size) {
        throw SceneError(label, "", "read failed");
    }
    SceneFile file = parse_scene_text(std::string_view(buffer.get(), n), true, label, limits);
    // The text is not needed any more: freed before the front end's draw list is built, while
    // the parser keeps its buffers for the next load.
    buffer.reset();
    Scene s = finish_scene(std::move(file), label, limits);
    s.path = path;
    return s;
}

}  // namespace harness
