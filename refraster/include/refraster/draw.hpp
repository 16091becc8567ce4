// draw.hpp: the API-neutral draw list every renderer consumes.
//
// Implements: the render target description, the clear values, and an ordered list of draws,
// each with clip-space float32 vertices (produced once by the harness front end), optional
// indices and the fixed-function state of scene format v1 (docs/scene-format.md).
//
// Deliberately does not: parse files, transform vertices, or validate ranges. Whoever builds a
// DrawList (harness/front_end) guarantees what the scene format guarantees: finite clip
// coordinates, indices within the vertex count, sizes within the documented limits. Those are
// the renderer's preconditions, asserted in debug and checked builds (assert.hpp).
//
// Coordinates are those of OpenGL: clip space as gl_Position, window space with its origin at
// the bottom-left corner of the target.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "refraster/assert.hpp"

namespace refraster {

enum class PrimitiveType : std::uint8_t {
    Points,
    Lines,
    LineStrip,
    LineLoop,
    Triangles,
    TriangleStrip,
    TriangleFan,
    // GL_POLYGON (compatibility profile; scene format extension "polygons"): the draw's
    // vertices are one polygon, split into triangles as Mesa's draw module and llvmpipe split
    // it (assembly.hpp), flat-shaded from its first vertex.
    Polygon,
};

enum class ColorFormat : std::uint8_t { Rgba8, Rgba32f };
enum class DepthFormat : std::uint8_t { None, Z16, Z24, Z32f };
enum class CullMode : std::uint8_t { None, Front, Back, FrontAndBack };
enum class FrontFace : std::uint8_t { Ccw, Cw };
enum class CompareFunc : std::uint8_t {
    Never,
    Less,
    Equal,
    Lequal,
    Greater,
    NotEqual,
    Gequal,
    Always,
};
// How attributes are interpolated: GLSL `smooth`, `flat` and `noperspective`.
enum class ShadeModel : std::uint8_t { Smooth, Flat, NoPerspective };
enum class ProvokingVertex : std::uint8_t { Last, First };
enum class PolygonMode : std::uint8_t { Fill, Line, Point };
// Blend presets; factors are the same for colour and alpha (scene format v1).
//   Alpha: src * SRC_ALPHA + dst * ONE_MINUS_SRC_ALPHA.   Add: src * ONE + dst * ONE.
enum class BlendPreset : std::uint8_t { None, Alpha, Add };
// How a polygon draw with a fill rule decides which pixels it lights (extension "polygons";
// docs/scene-format.md): the even-odd rule (an odd number of crossings of the polygon's
// boundary) or the non-zero rule (a winding number that is not zero modulo 256, the stencil
// buffer's 8 bits), each tested at the pixel centre.
enum class FillRule : std::uint8_t { EvenOdd, NonZero };

// Texture sampling state (scene format extension "textures"; docs/scene-format.md). The names
// are GL's: GL_NEAREST ... GL_LINEAR_MIPMAP_LINEAR, GL_REPEAT ... GL_CLAMP_TO_BORDER.
enum class TextureFilter : std::uint8_t {
    Nearest,
    Linear,
    NearestMipmapNearest,
    LinearMipmapNearest,
    NearestMipmapLinear,
    LinearMipmapLinear,
};
enum class TextureWrap : std::uint8_t { Repeat, ClampToEdge, MirroredRepeat, ClampToBorder };
// How the texel combines with the interpolated colour: GL_MODULATE (colour times texel) or
// GL_REPLACE (the texel alone).
enum class TextureEnv : std::uint8_t { Modulate, Replace };
// Where a point sprite's coordinates start (GL_POINT_SPRITE_COORD_ORIGIN): t = 0 at the top
// of the point (GL's default) or at its bottom.
enum class PointCoordOrigin : std::uint8_t { UpperLeft, LowerLeft };

inline constexpr bool uses_mipmaps(TextureFilter f) {
    return f != TextureFilter::Nearest && f != TextureFilter::Linear;
}

// One level of a texture: RGBA8 texels, rows bottom to top as glTexImage2D takes them.
struct TextureImage {
    std::uint32_t width = 1;
    std::uint32_t height = 1;
    std::vector<std::uint8_t> rgba;  // width * height * 4 bytes
    friend bool operator==(const TextureImage&, const TextureImage&) = default;
};

// A 2D texture: its base level and, for mipmapping, the levels below it. With
// `generate_mipmaps` the levels below the base are glGenerateMipmap's, which each renderer
// makes by its own rule (the reference: docs/precision.md, "Textures"); `levels` then holds
// the base alone. Otherwise levels 1.. are those given, each max(1, size >> level), possibly
// fewer than the full chain (the last one given is GL_TEXTURE_MAX_LEVEL).
struct Texture {
    std::vector<TextureImage> levels;
    bool generate_mipmaps = false;
    friend bool operator==(const Texture&, const Texture&) = default;
};

// A draw's texture unit 0: which texture of the DrawList and how it is sampled.
struct TextureState {
    std::uint32_t texture = 0;  // index in DrawList::textures
    TextureFilter min_filter = TextureFilter::Linear;
    TextureFilter mag_filter = TextureFilter::Linear;  // Nearest or Linear
    TextureWrap wrap_s = TextureWrap::Repeat;
    TextureWrap wrap_t = TextureWrap::Repeat;
    std::array<float, 4> border_color{0.0f, 0.0f, 0.0f, 0.0f};
    TextureEnv env = TextureEnv::Modulate;
    // Point sprite coordinates (GL_COORD_REPLACE, gl_PointCoord): a draw that rasterizes
    // points samples at the fragment's place in its point, s across from 0 at the left to 1
    // at the right and t from 0 at `point_coord_origin` to 1 at the other side, instead of
    // the vertex's coordinates; other draws ignore it.
    bool coord_replace = false;
    PointCoordOrigin point_coord_origin = PointCoordOrigin::UpperLeft;
    friend bool operator==(const TextureState&, const TextureState&) = default;
};

// A rectangle in window pixels: origin (x, y) at its bottom-left corner.
struct Rect {
    std::int32_t x = 0;
    std::int32_t y = 0;
    std::int32_t width = 0;
    std::int32_t height = 0;
    friend bool operator==(const Rect&, const Rect&) = default;
};

struct PolygonOffset {
    float factor = 0.0f;
    float units = 0.0f;
    friend bool operator==(const PolygonOffset&, const PolygonOffset&) = default;
};

// Everything a draw may set; every draw starts from these defaults (nothing carries over).
struct DrawState {
    Rect viewport;  // the whole target unless the scene says otherwise
    float depth_near = 0.0f;
    float depth_far = 1.0f;
    std::optional<Rect> scissor;
    CullMode cull = CullMode::None;
    FrontFace front_face = FrontFace::Ccw;
    std::optional<CompareFunc> depth_test;  // nullopt: the depth test is disabled
    bool depth_write = true;
    ShadeModel shade = ShadeModel::Smooth;
    ProvokingVertex provoking_vertex = ProvokingVertex::Last;
    PolygonMode polygon_mode = PolygonMode::Fill;
    std::optional<PolygonOffset> polygon_offset;
    float line_width = 1.0f;
    float point_size = 1.0f;
    BlendPreset blend = BlendPreset::None;
    // GL_MULTISAMPLE. It only matters on a 4x target: false draws with the single-sample
    // rules; the depth test and write use sample 0, the colour goes to every sample
    // (docs/precision.md, "Multisampling (4x)").
    bool multisample = true;
    // Texturing (extension "textures"): the fragment colour becomes the texel (replace) or
    // the interpolated colour times it (modulate), the texel sampled at the vertex attribute
    // "texcoord" (s, t, r, q) projected as (s/q, t/q) (docs/scene-format.md).
    std::optional<TextureState> texture;
    // A polygon's fill rule (extension "polygons"): nullopt draws GL_POLYGON's own triangles;
    // a rule lights the pixels the rule puts inside the polygon, each drawn once, by the first
    // of the polygon's triangles that covers it (docs/scene-format.md, "Fill rules").
    std::optional<FillRule> fill_rule;
    friend bool operator==(const DrawState&, const DrawState&) = default;
};

// One vertex attribute besides the position, e.g. {"color", 4}, {"texcoord", 4}.
struct AttributeDesc {
    std::string name;
    std::uint32_t components = 4;
    friend bool operator==(const AttributeDesc&, const AttributeDesc&) = default;
};

// Vertices as one float32 array. Each vertex is a record of `stride()` floats: the clip-space
// position (x, y, z, w) first, then each attribute's components in the order of `attributes`.
// Any number of attributes fits; format v1 uses "color" (4 components) and, with textures,
// "texcoord" (4) after it.
struct VertexArray {
    static constexpr std::uint32_t kPositionComponents = 4;

    std::vector<AttributeDesc> attributes;
    std::vector<float> data;

    std::uint32_t stride() const {
        std::uint32_t n = kPositionComponents;
        for (const auto& a : attributes) n += a.components;
        return n;
    }
    std::size_t size() const { return stride() == 0 ? 0 : data.size() / stride(); }
    std::span<const float> vertex(std::size_t i) const {
        return {data.data() + i * stride(), stride()};
    }
    std::span<const float, 4> position(std::size_t i) const {
        return std::span<const float, 4>(data.data() + i * stride(), 4);
    }
    // Offset of attribute `a` inside a vertex record, in floats.
    std::uint32_t attribute_offset(std::size_t a) const {
        std::uint32_t off = kPositionComponents;
        for (std::size_t k = 0; k < a; ++k) off += attributes[k].components;
        return off;
    }
    friend bool operator==(const VertexArray&, const VertexArray&) = default;
};

struct Draw {
    PrimitiveType primitive = PrimitiveType::Triangles;
    DrawState state;
    VertexArray vertices;
    // nullopt when the draw uses its vertices in order; otherwise each index < vertices.size().
    std::optional<std::vector<std::uint32_t>> indices;

    // The vertex count the primitive assembler sees.
    std::size_t element_count() const { return indices ? indices->size() : vertices.size(); }
    std::uint32_t element(std::size_t i) const {
        REFRASTER_ASSERT(i < element_count(), "an element of the draw");
        const std::uint32_t e = indices ? (*indices)[i] : static_cast<std::uint32_t>(i);
        REFRASTER_ASSERT(e < vertices.size(), "indices within the vertex count");
        return e;
    }
    friend bool operator==(const Draw&, const Draw&) = default;

    // Every primitive of the draw reaches the rasterizer as points: a points draw, or
    // triangles drawn with polygon mode point.
    bool rasterizes_points() const {
        return primitive == PrimitiveType::Points ||
               (primitive >= PrimitiveType::Triangles && state.polygon_mode == PolygonMode::Point);
    }
    // Every primitive of the draw reaches the rasterizer as lines: a line primitive, or
    // triangles drawn with polygon mode line.
    bool rasterizes_lines() const {
        return (primitive >= PrimitiveType::Lines && primitive <= PrimitiveType::LineLoop) ||
               (primitive >= PrimitiveType::Triangles && state.polygon_mode == PolygonMode::Line);
    }
    // The draw samples its texture at point sprite coordinates (TextureState::coord_replace).
    bool samples_point_coords() const {
        return state.texture && state.texture->coord_replace && rasterizes_points();
    }
};

struct Target {
    std::uint32_t width = 1;
    std::uint32_t height = 1;
    ColorFormat color = ColorFormat::Rgba8;
    DepthFormat depth = DepthFormat::None;
    std::uint32_t samples = 1;
    friend bool operator==(const Target&, const Target&) = default;
};

struct ClearValues {
    std::array<float, 4> color{0.0f, 0.0f, 0.0f, 0.0f};
    float depth = 1.0f;  // passed to glClearDepth as a double; quantised as the driver does
    friend bool operator==(const ClearValues&, const ClearValues&) = default;
};

struct DrawList {
    Target target;
    ClearValues clear;
    std::vector<Draw> draws;
    std::vector<Texture> textures;  // what DrawState::texture names
    friend bool operator==(const DrawList&, const DrawList&) = default;
};

std::string_view to_string(PrimitiveType p);
std::string_view to_string(FillRule r);
std::string_view to_string(ColorFormat f);
std::string_view to_string(DepthFormat f);

}  // namespace refraster
