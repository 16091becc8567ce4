// Scene files in a chosen vertex form (scene_text.hpp). Everything but the vertices and
// indices comes from scene_to_json, the loader's inverse, so that the forms differ only where
// the format lets them.
#include "harness/scene_text.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <nlohmann/json.hpp>
#include <random>
#include <stdexcept>

#include "harness/scene_writer.hpp"

namespace harness {

namespace {

using ojson = nlohmann::ordered_json;

// The shortest decimal that reads back, as a double rounded once to float32, to `f`: the
// shortest text of the double equal to f (a shorter float32-only text could round twice).
void append_number(std::string& out, float f) {
    char buf[40];
    const auto r = std::to_chars(buf, buf + sizeof buf, static_cast<double>(f));
    out.append(buf, r.ptr);
}

constexpr char kBase64Alphabet[] =
    "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

void append_base64(std::string& out, std::span<const std::uint8_t> bytes) {
    std::size_t i = 0;
    for (; i + 3 <= bytes.size(); i += 3) {
        const std::uint32_t v =
            (std::uint32_t{bytes[i]} << 16) | (std::uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
        for (int s = 18; s >= 0; s -= 6) out += kBase64Alphabet[(v >> s) & 63];
    }
    const std::size_t rest = bytes.size() - i;
    if (rest != 0) {
        std::uint32_t v = std::uint32_t{bytes[i]} << 16;
        if (rest == 2) v |= std::uint32_t{bytes[i + 1]} << 8;
        out += kBase64Alphabet[(v >> 18) & 63];
        out += kBase64Alphabet[(v >> 12) & 63];
        out += rest == 2 ? kBase64Alphabet[(v >> 6) & 63] : '=';
        out += '=';
    }
}

void append_u32_le(std::vector<std::uint8_t>& bytes, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
}

// `values` (count x components floats) as "values" or "float32_base64".
void append_attribute(std::string& out, const std::vector<float>& values, std::uint32_t components,
                      VertexForm form) {
    out += "{\"components\": " + std::to_string(components);
    if (form == VertexForm::Values) {
        out += ", \"values\": [";
        for (std::size_t i = 0; i < values.size(); ++i) {
            if (i != 0) out += i % components == 0 ? ",\n     " : ", ";
            append_number(out, values[i]);
        }
        out += "]}";
        return;
    }
    std::vector<std::uint8_t> bytes;
    bytes.reserve(values.size() * 4);
    for (const float f : values) append_u32_le(bytes, std::bit_cast<std::uint32_t>(f));
    out += ", \"float32_base64\": \"";
    append_base64(out, bytes);
    out += "\"}";
}

void append_floats(std::string& out, const float* values, std::size_t n) {
    for (std::size_t k = 0; k < n; ++k) {
        if (k != 0) out += ", ";
        append_number(out, values[k]);
    }
}

void append_vertices(std::string& out, const SceneDraw& d, VertexForm form) {
    if (form == VertexForm::Plain) {
        out += "\"vertices\": [";
        for (std::size_t i = 0; i < d.vertices.size(); ++i) {
            const SceneVertex& v = d.vertices[i];
            out += i == 0 ? "\n    {\"position\": [" : ",\n    {\"position\": [";
            for (std::uint32_t k = 0; k < v.position_size; ++k) {
                if (k != 0) out += ", ";
                append_number(out, v.position[k]);
            }
            out += "], \"color\": [";
            append_floats(out, v.color.data(), 4);
            if (!is_default_texcoord(v.texcoord)) {
                out += "], \"texcoord\": [";
                append_floats(out, v.texcoord.data(),
                              is_two_component_texcoord(v.texcoord) ? 2 : 4);
            }
            out += "]}";
        }
        out += d.vertices.empty() ? "]" : "\n   ]";
        return;
    }
    const std::uint32_t size = d.vertices.empty() ? 4 : d.vertices.front().position_size;
    std::vector<float> position;
    std::vector<float> color;
    position.reserve(d.vertices.size() * size);
    color.reserve(d.vertices.size() * 4);
    // Texture coordinates only when some vertex has one, with two components when every
    // vertex's r and q are 0 and 1.
    bool texcoords = false;
    bool two = true;
    for (const SceneVertex& v : d.vertices) {
        if (v.position_size != size) {
            throw std::invalid_argument(
                "vertex_arrays need one position size for all of a draw's vertices");
        }
        position.insert(position.end(), v.position.begin(), v.position.begin() + size);
        color.insert(color.end(), v.color.begin(), v.color.end());
        texcoords = texcoords || !is_default_texcoord(v.texcoord);
        two = two && is_two_component_texcoord(v.texcoord);
    }
    out += "\"vertex_arrays\": {\"count\": " + std::to_string(d.vertices.size()) +
           ",\n    \"position\": ";
    append_attribute(out, position, size, form);
    out += ",\n    \"color\": ";
    append_attribute(out, color, 4, form);
    if (texcoords) {
        const std::uint32_t n = two ? 2 : 4;
        std::vector<float> texcoord;
        texcoord.reserve(d.vertices.size() * n);
        for (const SceneVertex& v : d.vertices) {
            texcoord.insert(texcoord.end(), v.texcoord.begin(), v.texcoord.begin() + n);
        }
        out += ",\n    \"texcoord\": ";
        append_attribute(out, texcoord, n, form);
    }
    out += "}";
}

void append_indices(std::string& out, const std::vector<std::uint32_t>& indices, VertexForm form) {
    out += "\"indices\": ";
    if (form == VertexForm::Base64) {
        std::vector<std::uint8_t> bytes;
        bytes.reserve(indices.size() * 4);
        for (const std::uint32_t i : indices) append_u32_le(bytes, i);
        out += "{\"uint32_base64\": \"";
        append_base64(out, bytes);
        out += "\"}";
        return;
    }
    out += "[";
    for (std::size_t i = 0; i < indices.size(); ++i) {
        if (i != 0) out += ", ";
        out += std::to_string(indices[i]);
    }
    out += "]";
}

}  // namespace

std::string base64_text(std::span<const std::uint8_t> bytes) {
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    append_base64(out, bytes);
    return out;
}

bool is_default_texcoord(const std::array<float, 4>& t) {
    return std::bit_cast<std::array<std::uint32_t, 4>>(t) ==
           std::bit_cast<std::array<std::uint32_t, 4>>(SceneVertex{}.texcoord);
}

bool is_two_component_texcoord(const std::array<float, 4>& t) {
    return std::bit_cast<std::uint32_t>(t[2]) == std::bit_cast<std::uint32_t>(0.0f) &&
           std::bit_cast<std::uint32_t>(t[3]) == std::bit_cast<std::uint32_t>(1.0f);
}

std::string scene_json_text(const SceneFile& s, VertexForm form) {
    // The file without vertices and indices, as the loader's inverse writes it.
    SceneFile shell;
    shell.name = s.name;
    shell.description = s.description;
    shell.requires_extensions = s.requires_extensions;
    // The vertices written below may hold texture coordinates, which the shell lacks.
    if (uses_textures(s) &&
        std::find(shell.requires_extensions.begin(), shell.requires_extensions.end(), "textures") ==
            shell.requires_extensions.end()) {
        shell.requires_extensions.emplace_back("textures");
    }
    shell.target = s.target;
    shell.clear = s.clear;
    shell.expect = s.expect;
    shell.textures = s.textures;
    for (const SceneDraw& d : s.draws) {
        SceneDraw e;
        e.primitive = d.primitive;
        e.space = d.space;
        e.matrix = d.matrix;
        e.state = d.state;
        e.texture = d.texture;
        shell.draws.push_back(std::move(e));
    }
    ojson j = ojson::parse(scene_to_json(shell));
    if (form != VertexForm::Plain) {
        ojson req = j.contains("requires") ? j["requires"] : ojson::array();
        if (std::find(req.begin(), req.end(), "vertex_arrays") == req.end()) {
            req.push_back("vertex_arrays");
        }
        // "requires" right after "description" (or "name"), where scene_to_json puts it.
        ojson k;
        for (auto it = j.begin(); it != j.end(); ++it) {
            if (it.key() == "target" && !k.contains("requires")) k["requires"] = req;
            if (it.key() == "requires") {
                k["requires"] = req;
            } else {
                k[it.key()] = it.value();
            }
        }
        j = std::move(k);
    }
    return lay_out_scene_json(j, [&](std::string& out, std::size_t di, const ojson& dj) {
        const SceneDraw& d = s.draws[di];
        bool first_field = true;
        for (auto f = dj.begin(); f != dj.end(); ++f) {
            if (f.key() == "indices") continue;
            open_draw_field(out, first_field);
            if (f.key() == "vertices") {
                append_vertices(out, d, form);
                if (d.indices) {
                    open_draw_field(out, first_field);
                    append_indices(out, *d.indices, form);
                }
            } else {
                out += ojson(f.key()).dump() + ": " + f.value().dump();
            }
        }
    });
}

void open_draw_field(std::string& out, bool& first) {
    out += first ? "\n   " : ",\n   ";
    first = false;
}

std::string lay_out_scene_json(const ojson& j, const DrawFieldWriter& draw) {
    std::string out = "{\n";
    bool first_key = true;
    for (auto it = j.begin(); it != j.end(); ++it) {
        out += first_key ? " " : ",\n ";
        first_key = false;
        out += ojson(it.key()).dump() + ": ";
        if (it.key() != "draws") {
            out += it.value().dump();
            continue;
        }
        out += "[";
        for (std::size_t di = 0; di < it.value().size(); ++di) {
            out += di == 0 ? "\n  {" : ",\n  {";
            draw(out, di, it.value()[di]);
            out += "\n  }";
        }
        out += "\n ]";
    }
    return out + "\n}\n";
}

SceneFile many_triangles_scene(std::uint64_t triangles, std::uint64_t seed) {
    SceneFile s;
    s.name = "many_triangles";
    s.description = std::to_string(triangles) + " small triangles, seed " + std::to_string(seed);
    s.target.width = 1024;
    s.target.height = 1024;
    s.target.depth = refraster::DepthFormat::Z24;
    SceneDraw d;
    d.primitive = refraster::PrimitiveType::Triangles;
    d.state.viewport = {0, 0, 1024, 1024};
    d.state.depth_test = refraster::CompareFunc::Less;
    std::mt19937_64 rng(seed);
    const auto grid = [&](std::uint64_t steps, float unit) {
        return static_cast<float>(rng() % steps) * unit;
    };
    d.vertices.reserve(static_cast<std::size_t>(triangles) * 3);
    for (std::uint64_t t = 0; t < triangles; ++t) {
        // A corner anywhere on the target, the others within 8 pixels of it.
        const float x = grid(1016 * 256, 1.0f / 256);
        const float y = grid(1016 * 256, 1.0f / 256);
        for (int k = 0; k < 3; ++k) {
            SceneVertex v;
            v.position_size = 3;
            v.position = {x + grid(8 * 256, 1.0f / 256), y + grid(8 * 256, 1.0f / 256),
                          grid(256, 1.0f / 256), 1.0f};
            v.color = {grid(17, 1.0f / 16), grid(17, 1.0f / 16), grid(17, 1.0f / 16), 1.0f};
            d.vertices.push_back(v);
        }
    }
    s.draws.push_back(std::move(d));
    return s;
}

}  // namespace harness
