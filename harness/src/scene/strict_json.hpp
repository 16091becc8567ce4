// strict_json.hpp: the JSON layer of the scene loader (strict_json.cpp), beneath the format
// walk of scene_reader.cpp.
//
// Implements: parsing a scene file's text with the strict rules (duplicate keys, nesting, the
// number of values and number ranges refused with the JSON path of the offending value, syntax
// errors with a line and column), and Node, the walk's view of one value of the document: the
// accessors refuse what the format forbids with the value's JSON path, and apply the strict
// rules simdjson does not to every container they accept.
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
//
// Every message is one line: keys, paths and strings from the file are escaped, numbers are
// printed short.
#pragma once

#include <simdjson.h>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_set>
#include <utility>
#include <vector>

#include "harness/scene.hpp"

namespace harness::strict_json {

namespace dom = simdjson::dom;

// A container of the document as simdjson's iterable types; the caller has checked its type.
// (Named values, not temporaries: a range-for over a temporary result would dangle.)
inline dom::array as_array(dom::element e) {
    const auto r = e.get_array();
    return r.value_unsafe();
}
inline dom::object as_object(dom::element e) {
    const auto r = e.get_object();
    return r.value_unsafe();
}

// The number of elements of an array: simdjson's count stops at 0xFFFFFF.
inline std::size_t element_count(dom::array a) {
    std::size_t n = a.size();
    if (n == 0xFFFFFF) {
        n = 0;
        for (auto it = a.begin(); it != a.end(); ++it) ++n;
    }
    return n;
}

// A key as one path component: .name when it is a plain identifier, otherwise ["escaped"] so
// that a key holding dots, brackets or newlines still reads as one component on one line.
std::string key_component(std::string_view k);

// A string from the file inside a message: quoted, escaped, cut after 40 bytes (at a UTF-8
// character boundary) so that a long value does not drown the message.
std::string quoted_value(std::string_view v);

// A number inside a message: integers exactly, other values in %.9g (enough to tell float32
// values apart), never the hundreds of digits a file may spell them with.
std::string number_text(double d);
std::string number_text(dom::element v);

// A value inside a message: null, true, false, a quoted string, "an array of N", "an object"
// or the number.
std::string describe(dom::element v);

// Upper bounds of the values and of the containers in `text`: every value but the root
// follows a comma or opens its container's first element, so values <= 1 + commas + '[' +
// '{', and containers <= '[' + '{' (characters inside strings only raise the bounds). The
// first lets a file with too many values be refused before simdjson builds a document whose
// size follows the number of values; the second tells whether the walk saw every container.
struct TextCounts {
    std::uint64_t values = 1;
    std::uint64_t containers = 0;
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
                    const std::string& file_label, const SceneLimits& limits);

// Whether the document follows the strict rules simdjson does not apply: no duplicate key, no
// container nested too deep, no value past the limit.
bool follows_strict_rules(dom::element root, const SceneLimits& limits);

// The refusal the strict parser gives a file that breaks a strict rule.
[[noreturn]] void refuse_strictly(std::string_view text, const std::string& file_label,
                                  const SceneLimits& limits);

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

}  // namespace harness::strict_json
