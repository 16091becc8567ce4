// Scene format v1 reader: strict JSON parsing (duplicate keys refused, positions for syntax
// errors), then a validating walk that turns the document into a SceneFile, naming the JSON
// path of the first offending value, and the work limits of SceneLimits (docs/limits.md).
// Every message is one line: keys, paths and strings from the file are escaped, numbers are
// printed short.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <system_error>

#include "harness/front_end.hpp"
#include "harness/scene.hpp"
#include "refraster/renderer.hpp"

namespace harness {

using json = nlohmann::json;

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
std::string number_text(const json& v) {
    if (v.is_number_unsigned()) return std::to_string(v.get<std::uint64_t>());
    if (v.is_number_integer()) return std::to_string(v.get<std::int64_t>());
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v.get<double>());
    return buf;
}
std::string number_text(double d) {
    return number_text(json(d));
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

std::string child_path(const std::string& parent, const std::string& key) {
    std::string c = key_component(key);
    if (c.front() == '.') c.erase(0, 1);
    if (parent == "(root)") return c;
    return parent + (c.front() == '[' ? "" : ".") + c;
}
std::string child_path(const std::string& parent, std::size_t index) {
    return (parent == "(root)" ? std::string() : parent) + "[" + std::to_string(index) + "]";
}

// Builds the document while tracking the path of the value being read, so that duplicate
// keys and unrepresentable numbers are refused with a path, and syntax errors with a line and
// column. nlohmann's own DOM parser keeps the last duplicate silently.
class StrictSaxBuilder : public nlohmann::json_sax<json> {
  public:
    StrictSaxBuilder(std::string_view text, const SceneLimits& limits)
        : text_(text), limits_(limits) {}

    json root;
    std::string error_path;
    std::string error_detail;
    std::size_t error_position = 0;
    bool syntax_error = false;

    bool null() override { return add(json(nullptr)); }
    bool boolean(bool v) override { return add(json(v)); }
    bool number_integer(number_integer_t v) override { return add(json(v)); }
    bool number_unsigned(number_unsigned_t v) override { return add(json(v)); }
    bool number_float(number_float_t v, const string_t& s) override {
        if (!std::isfinite(v)) return fail_value("number " + token_text(s) + " is out of range");
        return add(json(v));
    }
    bool string(string_t& v) override { return add(json(std::move(v))); }
    bool binary(binary_t&) override { return fail_value("binary values are not JSON"); }

    bool start_object(std::size_t) override {
        if (!add(json::object())) return false;
        return open(current_);
    }
    bool key(string_t& k) override {
        json& obj = *stack_.back();
        if (obj.contains(k)) {
            path_.push_key(k);
            error_path = path_.str();
            path_.pop();
            error_detail = "duplicate key " + quoted_value(k);
            return false;
        }
        obj[k] = nullptr;
        pending_key_ = k;
        return true;
    }
    bool end_object() override { return close(); }
    bool start_array(std::size_t) override {
        if (!add(json::array())) return false;
        return open(current_);
    }
    bool end_array() override { return close(); }

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
    bool fail_value(std::string detail) {
        error_path = value_path();
        error_detail = std::move(detail);
        return false;
    }
    std::string value_path() {
        if (stack_.empty()) return path_.str();
        if (stack_.back()->is_array()) {
            path_.push_index(stack_.back()->size());
        } else {
            path_.push_key(pending_key_);
        }
        std::string p = path_.str();
        path_.pop();
        return p;
    }
    bool add(json v) {
        // The document in memory costs tens of bytes a value, whatever the file spells it with.
        if (++values_ > limits_.max_json_values) {
            return fail_value("the file holds more than " +
                              std::to_string(limits_.max_json_values) +
                              " JSON values, the limit of a scene (docs/limits.md)");
        }
        if (stack_.empty()) {
            root = std::move(v);
            current_ = &root;
            return true;
        }
        json& parent = *stack_.back();
        if (parent.is_array()) {
            path_index_ = parent.size();
            parent.push_back(std::move(v));
            current_ = &parent.back();
            current_is_index_ = true;
        } else {
            json& slot = parent[pending_key_];
            slot = std::move(v);
            current_ = &slot;
            current_is_index_ = false;
        }
        return true;
    }
    bool open(json* container) {
        // nlohmann's SAX parser is iterative, so depth costs no stack; the limit keeps paths,
        // messages and the document's recursive destructor and dump small.
        if (stack_.size() >= limits_.max_nesting_depth) {
            // The path of the container that goes one level too deep.
            if (stack_.empty()) {
                error_path = path_.str();
            } else {
                if (current_is_index_) {
                    path_.push_index(path_index_);
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
            if (current_is_index_) {
                path_.push_index(path_index_);
            } else {
                path_.push_key(pending_key_);
            }
        }
        stack_.push_back(container);
        return true;
    }
    bool close() {
        stack_.pop_back();
        if (!stack_.empty()) path_.pop();
        return true;
    }

    std::string_view text_;
    const SceneLimits& limits_;
    std::uint64_t values_ = 0;
    std::vector<json*> stack_;
    JsonPath path_;
    std::string pending_key_;
    json* current_ = nullptr;
    bool current_is_index_ = false;
    std::size_t path_index_ = 0;
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

std::string describe(const json& v) {
    switch (v.type()) {
        case json::value_t::null:
            return "null";
        case json::value_t::boolean:
            return v.get<bool>() ? "true" : "false";
        case json::value_t::string:
            return "the string " + quoted_value(v.get_ref<const std::string&>());
        case json::value_t::array:
            return "an array of " + std::to_string(v.size());
        case json::value_t::object:
            return "an object";
        default:
            return number_text(v);
    }
}

// A value of the document with its path; every accessor refuses what the format forbids.
class Node {
  public:
    Node(const json& v, std::string path, const std::string& file)
        : v_(v), path_(std::move(path)), file_(file) {}

    const json& value() const { return v_; }
    const std::string& path() const { return path_; }

    [[noreturn]] void fail(const std::string& detail) const {
        throw SceneError(file_, path_, detail);
    }

    void require_object(std::initializer_list<std::string_view> allowed) const {
        if (!v_.is_object()) fail("expected an object, got " + describe(v_));
        for (const auto& [k, _] : v_.items()) {
            bool ok = false;
            for (auto a : allowed) ok = ok || k == a;
            if (!ok) {
                std::string list;
                for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
                Node(v_.at(k), child_path(path_, k), file_)
                    .fail("unknown key " + quoted_value(k) + " (allowed: " + list + ")");
            }
        }
    }
    bool has(const std::string& key) const { return v_.contains(key); }
    Node at(const std::string& key) const {
        if (!v_.contains(key)) fail("missing required key " + quoted_value(key));
        return {v_.at(key), child_path(path_, key), file_};
    }
    std::optional<Node> get(const std::string& key) const {
        if (!v_.contains(key)) return std::nullopt;
        return Node(v_.at(key), child_path(path_, key), file_);
    }

    std::size_t array_size(std::size_t min, std::size_t max, const char* what) const {
        if (!v_.is_array()) fail(std::string("expected ") + what + ", got " + describe(v_));
        if (v_.size() < min || v_.size() > max) {
            fail(std::string("expected ") + what + ", got an array of " +
                 std::to_string(v_.size()));
        }
        return v_.size();
    }
    Node operator[](std::size_t i) const { return {v_.at(i), child_path(path_, i), file_}; }

    // A JSON number read as a double, then rounded once to float32; must stay finite.
    float f32() const {
        if (!v_.is_number()) fail("expected a number, got " + describe(v_));
        const double d = v_.get<double>();
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
        if (v_.is_number_integer()) {
            if (v_.is_number_unsigned() &&
                v_.get<std::uint64_t>() >
                    static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
                fail_range(lo, hi);
            }
            r = v_.get<std::int64_t>();
        } else if (v_.is_number_float()) {
            const double d = v_.get<double>();
            if (std::trunc(d) != d) fail("expected an integer, got " + number_text(v_));
            if (d < -9.0e18 || d > 9.0e18) fail_range(lo, hi);
            r = static_cast<std::int64_t>(d);
        } else {
            fail("expected an integer, got " + describe(v_));
        }
        if (r < lo || r > hi) fail_range(lo, hi);
        return r;
    }
    bool boolean() const {
        if (!v_.is_boolean()) fail("expected true or false, got " + describe(v_));
        return v_.get<bool>();
    }
    std::string string() const {
        if (!v_.is_string()) fail("expected a string, got " + describe(v_));
        return v_.get<std::string>();
    }
    template <class E>
    E choice(std::initializer_list<std::pair<std::string_view, E>> options) const {
        std::string list;
        for (const auto& [n, _] : options) list += (list.empty() ? "" : ", ") + std::string(n);
        if (!v_.is_string()) fail("expected one of " + list + ", got " + describe(v_));
        const auto s = v_.get<std::string>();
        for (const auto& [n, e] : options) {
            if (s == n) return e;
        }
        fail("expected one of " + list + ", got " + quoted_value(s));
    }

  private:
    [[noreturn]] void fail_range(std::int64_t lo, std::int64_t hi) const {
        fail("expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
             "], got " + number_text(v_));
    }

    const json& v_;
    std::string path_;
    const std::string& file_;
};

// Limits from scene format v1, section "Limits and remaining semantics".
constexpr std::int64_t kMaxTargetSide = 16384;
constexpr std::int64_t kMaxTargetSamplesArea = 67'108'864;
constexpr std::int64_t kViewportOriginMin = -32768;
constexpr std::int64_t kViewportOriginMax = 32767;
// The format bounds scissor sizes only below; this bound keeps x + width inside int32.
constexpr std::int64_t kScissorLimit = std::int64_t{1} << 30;

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

refraster::DrawState read_state(const Node& n, const refraster::Target& target) {
    using namespace refraster;
    DrawState s;
    s.viewport = {0, 0, static_cast<std::int32_t>(target.width),
                  static_cast<std::int32_t>(target.height)};
    n.require_object({"viewport", "depth_range", "scissor", "cull", "front_face", "depth_test",
                      "depth_write", "shade", "provoking_vertex", "polygon_mode", "polygon_offset",
                      "line_width", "point_size", "blend", "multisample"});
    if (auto v = n.get("viewport")) {
        s.viewport = read_rect(*v, kViewportOriginMin, kViewportOriginMax, 1, kMaxTargetSide);
    }
    if (auto v = n.get("depth_range")) {
        v->array_size(2, 2, "[near, far]");
        s.depth_near = (*v)[0].f32_in(0.0f, 1.0f);
        s.depth_far = (*v)[1].f32_in(0.0f, 1.0f);
    }
    if (auto v = n.get("scissor"); v && !v->value().is_null()) {
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
    if (auto v = n.get("depth_test"); v && !v->value().is_null()) {
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
    if (auto v = n.get("polygon_offset"); v && !v->value().is_null()) {
        v->require_object({"factor", "units"});
        s.polygon_offset = PolygonOffset{v->at("factor").f32(), v->at("units").f32()};
    }
    // Any width and size in (0, 255]: GL clamps what is below 1 to the implementation's
    // ALIASED_LINE_WIDTH_RANGE and POINT_SIZE_RANGE (1..255 in llvmpipe), so they draw as 1.
    if (auto v = n.get("line_width")) s.line_width = v->f32_above(0.0f, 255.0f);
    if (auto v = n.get("point_size")) s.point_size = v->f32_above(0.0f, 255.0f);
    if (auto v = n.get("blend"); v && !v->value().is_null()) {
        s.blend =
            v->choice<BlendPreset>({{"alpha", BlendPreset::Alpha}, {"add", BlendPreset::Add}});
    }
    // GL_MULTISAMPLE; an addition to format v1, allowed without "requires".
    if (auto v = n.get("multisample")) s.multisample = v->boolean();
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

SceneDraw read_draw(const Node& n, const refraster::Target& target, WorkSoFar& work) {
    using namespace refraster;
    SceneDraw d;
    n.require_object({"primitive", "space", "matrix", "vertices", "indices", "state"});
    d.primitive = n.at("primitive")
                      .choice<PrimitiveType>({{"points", PrimitiveType::Points},
                                              {"lines", PrimitiveType::Lines},
                                              {"line_strip", PrimitiveType::LineStrip},
                                              {"line_loop", PrimitiveType::LineLoop},
                                              {"triangles", PrimitiveType::Triangles},
                                              {"triangle_strip", PrimitiveType::TriangleStrip},
                                              {"triangle_fan", PrimitiveType::TriangleFan}});
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
        for (std::size_t i = 0; i < 16; ++i) m[i] = (*v)[i].f32();
        d.matrix = m;
    }
    const Node verts = n.at("vertices");
    const std::size_t count =
        verts.array_size(0, std::numeric_limits<std::uint32_t>::max(), "an array of vertices");
    WorkSoFar::add(verts, work.vertices, count, work.limits.max_vertices, "vertices");
    d.vertices.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const Node vn = verts[i];
        vn.require_object({"position", "color"});
        SceneVertex sv;
        const Node p = vn.at("position");
        if (d.space == VertexSpace::Clip) {
            p.array_size(4, 4, "[x, y, z, w] (space \"clip\")");
        } else {
            p.array_size(2, 4, "[x, y], [x, y, z] or [x, y, z, w] (space \"window\")");
        }
        sv.position_size = static_cast<std::uint32_t>(p.value().size());
        for (std::size_t c = 0; c < sv.position_size; ++c) sv.position[c] = p[c].f32();
        if (d.space == VertexSpace::Window && sv.position_size == 4 && !(sv.position[3] > 0.0f)) {
            p[3].fail("expected w > 0 in window space, got " + number_text(p[3].value()));
        }
        if (auto c = vn.get("color")) sv.color = read_color(*c);
        d.vertices.push_back(sv);
    }
    if (auto v = n.get("indices")) {
        const std::size_t ni =
            v->array_size(0, std::numeric_limits<std::uint32_t>::max(), "an array of indices");
        WorkSoFar::add(*v, work.indices, ni, work.limits.max_indices, "indices");
        std::vector<std::uint32_t> idx(ni);
        for (std::size_t i = 0; i < ni; ++i) {
            const Node e = (*v)[i];
            if (count == 0) e.fail("index into an empty vertex list");
            idx[i] = static_cast<std::uint32_t>(e.integer(0, static_cast<std::int64_t>(count) - 1));
        }
        d.indices = std::move(idx);
    }
    // Indices may repeat a vertex any number of times: the primitives are what costs.
    const std::size_t elements = d.indices ? d.indices->size() : d.vertices.size();
    WorkSoFar::add(n, work.primitives, refraster::primitive_count(d.primitive, elements),
                   work.limits.max_primitives, "primitives");
    if (auto v = n.get("state")) {
        d.state = read_state(*v, target);
    } else {
        d.state.viewport = {0, 0, static_cast<std::int32_t>(target.width),
                            static_cast<std::int32_t>(target.height)};
    }
    return d;
}

// The extensions this reader implements. "multisample": the draw state key "multisample"
// (GL_MULTISAMPLE) on 4x targets; the key is part of format v1 too, and a file may still list
// the name to say that it relies on it.
bool is_implemented_extension(std::string_view name) {
    return name == "multisample";
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
    : std::runtime_error(compose_message(file, json_path, message, line, column)),
      file_(std::move(file)),
      json_path_(std::move(json_path)),
      detail_(std::move(message)),
      line_(line),
      column_(column) {}

SceneFile parse_scene(std::string_view text, const std::string& file_label,
                      const SceneLimits& limits) {
    using namespace refraster;
    if (text.size() > limits.max_file_bytes) {
        throw SceneError(file_label, "",
                         "file of " + std::to_string(text.size()) +
                             " bytes exceeds the scene size limit of " +
                             std::to_string(limits.max_file_bytes) + " bytes");
    }
    StrictSaxBuilder sax(text, limits);
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
    const Node root(sax.root, "(root)", file_label);
    root.require_object(
        {"format", "name", "description", "requires", "target", "clear", "expect", "draws"});
    SceneFile s;
    const Node format = root.at("format");
    if (format.string() != kSceneFormatV1) {
        format.fail(std::string("expected \"") + kSceneFormatV1 + "\", got " +
                    describe(format.value()));
    }
    if (auto v = root.get("name")) s.name = v->string();
    if (auto v = root.get("description")) s.description = v->string();
    if (auto v = root.get("requires")) {
        const std::size_t n = v->array_size(0, 64, "an array of extension names");
        for (std::size_t i = 0; i < n; ++i) s.requires_extensions.push_back((*v)[i].string());
    }

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

    const Node draws = root.at("draws");
    const std::size_t nd =
        draws.array_size(0, std::numeric_limits<std::uint32_t>::max(), "an array of draws");
    if (nd > limits.max_draws) {
        draws.fail(std::to_string(nd) + " draws exceed the limit of " +
                   std::to_string(limits.max_draws) + " draws a scene (docs/limits.md)");
    }
    WorkSoFar work{limits};
    s.draws.reserve(nd);
    for (std::size_t i = 0; i < nd; ++i) s.draws.push_back(read_draw(draws[i], s.target, work));
    return s;
}

Scene load_scene_text(std::string_view text, const std::string& file_label,
                      const SceneLimits& limits) {
    Scene scene;
    scene.path = file_label;
    scene.file = parse_scene(text, file_label, limits);
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
    if (size > limits.max_file_bytes) {
        throw SceneError(label, "",
                         "file of " + std::to_string(size) +
                             " bytes exceeds the scene size limit of " +
                             std::to_string(limits.max_file_bytes) + " bytes");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SceneError(label, "", "cannot open for reading");
    std::string text(static_cast<std::size_t>(size), '\0');
    in.read(text.data(), static_cast<std::streamsize>(size));
    if (static_cast<std::uintmax_t>(in.gcount()) != size) {
        throw SceneError(label, "", "read failed");
    }
    Scene s = load_scene_text(text, label, limits);
    s.path = path;
    return s;
}

}  // namespace harness
