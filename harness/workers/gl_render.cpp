// gl_render.cpp: see gl_render.hpp.
#define GL_GLEXT_PROTOTYPES 1
#include "gl_render.hpp"

#include <GL/gl.h>
#include <GL/glext.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <vector>

#include "refraster/framebuffer.hpp"
#include "wire.hpp"

namespace harness::gl {

namespace {

using refraster::ColorFormat;
using refraster::DepthFormat;

// A GL call failed in a way that is the backend's fault, not the scene's.
class GlFailure : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// The scene asks for something this driver cannot do.
class Unsupported : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

const char* gl_error_name(GLenum e) {
    switch (e) {
        case GL_INVALID_ENUM:
            return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE:
            return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION:
            return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION:
            return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY:
            return "GL_OUT_OF_MEMORY";
        case GL_STACK_OVERFLOW:
            return "GL_STACK_OVERFLOW";
        case GL_STACK_UNDERFLOW:
            return "GL_STACK_UNDERFLOW";
        default:
            return "unknown GL error";
    }
}

std::string hex(unsigned v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%04x", v);
    return buf;
}

void check_gl(const char* step) {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        throw GlFailure(std::string("GL error ") + hex(e) + " (" + gl_error_name(e) + ") at " +
                        step);
    }
}

// Errors left over from an earlier request must not be blamed on this one. GL keeps at most
// one flag per error kind, so the loop is short; the bound guards against a broken driver.
void drain_gl_errors() {
    for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i) {
    }
}

std::string gl_string(GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
}

GLint gl_int(GLenum name) {
    GLint v = 0;
    glGetIntegerv(name, &v);
    return v;
}

GLenum color_internal_format(ColorFormat f) {
    return f == ColorFormat::Rgba8 ? GL_RGBA8 : GL_RGBA32F;
}

// A target without depth still gets z24: see the spec, a depth-less colour buffer can change
// llvmpipe's clipping path.
GLenum depth_internal_format(DepthFormat f) {
    switch (f) {
        case DepthFormat::Z16:
            return GL_DEPTH_COMPONENT16;
        case DepthFormat::Z32f:
            return GL_DEPTH_COMPONENT32F;
        case DepthFormat::Z24:
        case DepthFormat::None:
            return GL_DEPTH_COMPONENT24;
    }
    return GL_DEPTH_COMPONENT24;
}

GLenum primitive_mode(refraster::PrimitiveType p) {
    using refraster::PrimitiveType;
    switch (p) {
        case PrimitiveType::Points:
            return GL_POINTS;
        case PrimitiveType::Lines:
            return GL_LINES;
        case PrimitiveType::LineStrip:
            return GL_LINE_STRIP;
        case PrimitiveType::LineLoop:
            return GL_LINE_LOOP;
        case PrimitiveType::Triangles:
            return GL_TRIANGLES;
        case PrimitiveType::TriangleStrip:
            return GL_TRIANGLE_STRIP;
        case PrimitiveType::TriangleFan:
            return GL_TRIANGLE_FAN;
    }
    return GL_TRIANGLES;
}

GLenum compare_func(refraster::CompareFunc f) {
    using refraster::CompareFunc;
    switch (f) {
        case CompareFunc::Never:
            return GL_NEVER;
        case CompareFunc::Less:
            return GL_LESS;
        case CompareFunc::Equal:
            return GL_EQUAL;
        case CompareFunc::Lequal:
            return GL_LEQUAL;
        case CompareFunc::Greater:
            return GL_GREATER;
        case CompareFunc::NotEqual:
            return GL_NOTEQUAL;
        case CompareFunc::Gequal:
            return GL_GEQUAL;
        case CompareFunc::Always:
            return GL_ALWAYS;
    }
    return GL_ALWAYS;
}

GLenum polygon_mode(refraster::PolygonMode m) {
    using refraster::PolygonMode;
    switch (m) {
        case PolygonMode::Fill:
            return GL_FILL;
        case PolygonMode::Line:
            return GL_LINE;
        case PolygonMode::Point:
            return GL_POINT;
    }
    return GL_FILL;
}

void set_enabled(GLenum cap, bool on) {
    if (on) {
        glEnable(cap);
    } else {
        glDisable(cap);
    }
}

// The GLSL version line. 1.30 is the oldest with `in`/`out` and the three interpolation
// qualifiers, and every Mesa compatibility context (softpipe's 3.3 included) accepts it.
constexpr const char* kGlslVersion = "#version 130\n";

const char* qualifier(refraster::ShadeModel s) {
    switch (s) {
        case refraster::ShadeModel::Smooth:
            return "smooth";
        case refraster::ShadeModel::Flat:
            return "flat";
        case refraster::ShadeModel::NoPerspective:
            return "noperspective";
    }
    return "smooth";
}

constexpr GLuint kPositionLocation = 0;
constexpr GLuint kColorLocation = 1;

GLuint compile_shader(GLenum type, const std::string& source) {
    const GLuint sh = glCreateShader(type);
    const char* text = source.c_str();
    glShaderSource(sh, 1, &text, nullptr);
    glCompileShader(sh);
    GLint ok = GL_FALSE;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        std::array<char, 2048> log{};
        glGetShaderInfoLog(sh, static_cast<GLsizei>(log.size()), nullptr, log.data());
        glDeleteShader(sh);
        std::string msg(log.data());
        std::replace(msg.begin(), msg.end(), '\n', ' ');
        throw GlFailure("shader compilation failed: " + msg);
    }
    return sh;
}

// The owner pass needs gl_PrimitiveID in the fragment shader (GLSL 1.50) and an unsigned
// integer output; everything else is the colour program's.
constexpr const char* kGlslOwnerVersion = "#version 150 compatibility\n";

GLuint build_program(refraster::ShadeModel shade, bool owners) {
    const std::string q = qualifier(shade);
    const std::string version = owners ? kGlslOwnerVersion : kGlslVersion;
    const std::string vs = version +
                           "in vec4 position;\n"
                           "in vec4 color;\n" +
                           q +
                           " out vec4 v_color;\n"
                           "void main() {\n"
                           "    gl_Position = position;\n"
                           "    v_color = color;\n"
                           "}\n";
    const std::string fs =
        owners
            ? version + q +
                  " in vec4 v_color;\n"
                  "out vec4 frag_color;\n"
                  "out uint frag_owner;\n"
                  "uniform uint draw_index;\n"
                  "void main() {\n"
                  "    frag_color = v_color;\n"
                  "    frag_owner = (draw_index << 24) | (uint(gl_PrimitiveID + 1) & 0xffffffu);\n"
                  "}\n"
            : version + q +
                  " in vec4 v_color;\n"
                  "out vec4 frag_color;\n"
                  "void main() {\n"
                  "    frag_color = v_color;\n"
                  "}\n";
    const GLuint v = compile_shader(GL_VERTEX_SHADER, vs);
    GLuint f = 0;
    try {
        f = compile_shader(GL_FRAGMENT_SHADER, fs);
    } catch (...) {
        glDeleteShader(v);
        throw;
    }
    const GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    glBindAttribLocation(p, kPositionLocation, "position");
    glBindAttribLocation(p, kColorLocation, "color");
    glBindFragDataLocation(p, 0, "frag_color");
    if (owners) glBindFragDataLocation(p, 1, "frag_owner");
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok = GL_FALSE;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        std::array<char, 2048> log{};
        glGetProgramInfoLog(p, static_cast<GLsizei>(log.size()), nullptr, log.data());
        glDeleteProgram(p);
        std::string msg(log.data());
        std::replace(msg.begin(), msg.end(), '\n', ' ');
        throw GlFailure("program link failed: " + msg);
    }
    check_gl("building the shader program");
    return p;
}

// "K=V;K=V" for every LP_* and GALLIUM_* variable, sorted so that equal environments give
// equal strings.
std::string mesa_environment() {
    std::vector<std::string> vars;
    for (char** e = environ; e && *e; ++e) {
        const std::string_view kv(*e);
        if (kv.starts_with("LP_") || kv.starts_with("GALLIUM_")) vars.emplace_back(kv);
    }
    std::sort(vars.begin(), vars.end());
    std::string out;
    for (const auto& v : vars) {
        if (!out.empty()) out += ';';
        out += v;
    }
    return out;
}

// The installed version of a Debian package, from dpkg's database; empty when not found.
std::string debian_package_version(std::string_view package) {
    std::ifstream in("/var/lib/dpkg/status");
    if (!in) return {};
    std::string line;
    bool in_package = false;
    bool installed = false;
    std::string version;
    auto finish = [&]() -> bool { return in_package && installed && !version.empty(); };
    while (std::getline(in, line)) {
        if (line.empty()) {
            if (finish()) return version;
            in_package = installed = false;
            version.clear();
            continue;
        }
        if (line.starts_with("Package: ")) {
            in_package = std::string_view(line).substr(9) == package;
        } else if (line.starts_with("Status: ")) {
            installed = line.ends_with(" installed");
        } else if (line.starts_with("Version: ")) {
            version = line.substr(9);
        }
    }
    return finish() ? version : std::string();
}

struct TargetObjects {
    refraster::Target key;
    bool valid = false;
    GLuint fbo = 0;  // single-sample: rendered into (1x) or resolved into (4x), then read
    GLuint color_rb = 0;
    GLuint depth_rb = 0;
    GLuint ms_fbo = 0;  // 4x only
    GLuint ms_color_rb = 0;
    GLuint ms_depth_rb = 0;

    void release() {
        const GLuint fbos[] = {fbo, ms_fbo};
        const GLuint rbs[] = {color_rb, depth_rb, ms_color_rb, ms_depth_rb};
        glDeleteFramebuffers(2, fbos);
        glDeleteRenderbuffers(4, rbs);
        *this = TargetObjects{};
    }
};

}  // namespace

struct Renderer::Impl {
    harness::Provenance provenance;
    std::array<GLuint, 6> programs{};  // by ShadeModel, then with owners; 0 until first use
    bool owners = false;               // this render writes the owner attachment
    GLuint owner_rb = 0;
    GLuint current_draw = 0;
    GLuint vao = 0;
    GLuint vbo = 0;
    GLuint ibo = 0;
    TargetObjects target;
    GLint max_samples = 0;
    GLint max_renderbuffer = 0;
    std::array<GLint, 2> max_viewport{};
    std::array<GLfloat, 2> line_width_range{};
    std::array<GLfloat, 2> point_size_range{};

    GLuint program(refraster::ShadeModel shade) {
        GLuint& p = programs[static_cast<std::size_t>(shade) + (owners ? 3 : 0)];
        if (p == 0) p = build_program(shade, owners);
        return p;
    }
    void attach_owners(const refraster::Target& t);
    void detach_owners();

    void prepare_target(const refraster::Target& t);
    void set_fixed_state(bool multisample);
    void clear(const refraster::DrawList& list);
    void draw(const refraster::Target& t, const refraster::Draw& d);
    refraster::Framebuffer read_back(const refraster::Target& t);
};

void Renderer::Impl::prepare_target(const refraster::Target& t) {
    if (t.samples != 1 && t.samples != 4) {
        throw Unsupported("samples " + std::to_string(t.samples) + " (only 1 and 4 exist)");
    }
    if (t.samples == 4 && max_samples < 4) {
        throw Unsupported("4x multisampling: this driver reports GL_MAX_SAMPLES " +
                          std::to_string(max_samples));
    }
    if (t.width == 0 || t.height == 0 || t.width > static_cast<GLuint>(max_renderbuffer) ||
        t.height > static_cast<GLuint>(max_renderbuffer)) {
        throw Unsupported("target " + std::to_string(t.width) + "x" + std::to_string(t.height) +
                          " (GL_MAX_RENDERBUFFER_SIZE " + std::to_string(max_renderbuffer) + ")");
    }
    if (target.valid && target.key == t) return;
    target.release();

    const auto w = static_cast<GLsizei>(t.width);
    const auto h = static_cast<GLsizei>(t.height);
    const GLenum cf = color_internal_format(t.color);
    const GLenum df = depth_internal_format(t.depth);

    auto make_fbo = [&](GLsizei samples, bool with_depth, GLuint& fbo, GLuint& color,
                        GLuint& depth) {
        glGenFramebuffers(1, &fbo);
        glGenRenderbuffers(1, &color);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glBindRenderbuffer(GL_RENDERBUFFER, color);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, cf, w, h);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
        if (with_depth) {
            glGenRenderbuffers(1, &depth);
            glBindRenderbuffer(GL_RENDERBUFFER, depth);
            glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, df, w, h);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
        }
        glBindRenderbuffer(GL_RENDERBUFFER, 0);
        const GLenum e = glGetError();
        if (e == GL_OUT_OF_MEMORY) throw Unsupported("renderbuffer allocation: out of memory");
        if (e != GL_NO_ERROR) {
            throw GlFailure(std::string("GL error ") + hex(e) + " (" + gl_error_name(e) +
                            ") creating the framebuffer");
        }
        const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE) {
            throw Unsupported("framebuffer incomplete (status " + hex(status) + ")");
        }
        // The count actually granted, which may differ from the count asked for.
        const GLint got = gl_int(GL_SAMPLES);
        const GLint want = samples > 1 ? samples : 0;
        if (got != want) {
            throw Unsupported("asked for " + std::to_string(samples) + " samples, got " +
                              std::to_string(got));
        }
    };

    try {
        target.key = t;
        if (t.samples == 4) {
            // Rendering always has depth; the resolve target only needs it to be read.
            make_fbo(4, true, target.ms_fbo, target.ms_color_rb, target.ms_depth_rb);
            make_fbo(0, t.depth != DepthFormat::None, target.fbo, target.color_rb, target.depth_rb);
        } else {
            make_fbo(0, true, target.fbo, target.color_rb, target.depth_rb);
        }
        target.valid = true;
    } catch (...) {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        target.release();
        drain_gl_errors();
        throw;
    }
}

void Renderer::Impl::set_fixed_state(bool multisample) {
    // Defaults the spec relies on; nothing below changes them, but a request must not depend
    // on what the context happened to start with.
    glDisable(GL_DITHER);
    glEnable(GL_POINT_SPRITE);
    glDisable(GL_PROGRAM_POINT_SIZE);
    glDisable(GL_POINT_SMOOTH);
    glDisable(GL_LINE_SMOOTH);
    glDisable(GL_POLYGON_SMOOTH);
    glDisable(GL_LINE_STIPPLE);
    glDisable(GL_POLYGON_STIPPLE);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_ALPHA_TEST);
    glDisable(GL_COLOR_LOGIC_OP);
    glDisable(GL_DEPTH_CLAMP);
    glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    glDisable(GL_SAMPLE_COVERAGE);
    glDisable(GL_FRAMEBUFFER_SRGB);
    glDisable(GL_RASTERIZER_DISCARD);
    glDisable(GL_PRIMITIVE_RESTART);
    glBlendEquation(GL_FUNC_ADD);
    // Float targets keep unclamped colours, as a core context would; unorm targets clamp in
    // the conversion anyway.
    glClampColor(GL_CLAMP_FRAGMENT_COLOR, GL_FIXED_ONLY);
    glClampColor(GL_CLAMP_READ_COLOR, GL_FIXED_ONLY);
    set_enabled(GL_MULTISAMPLE, multisample);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glPixelStorei(GL_PACK_SKIP_ROWS, 0);
    glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    check_gl("setting fixed state");
}

void Renderer::Impl::clear(const refraster::DrawList& list) {
    const auto& c = list.clear;
    glBindFramebuffer(GL_FRAMEBUFFER, list.target.samples == 4 ? target.ms_fbo : target.fbo);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glClearColor(c.color[0], c.color[1], c.color[2], c.color[3]);
    glClearDepth(static_cast<double>(c.depth));
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    check_gl("clear");
}

void Renderer::Impl::draw(const refraster::Target& t, const refraster::Draw& d) {
    const auto& s = d.state;
    const std::size_t count = d.element_count();
    if (count == 0) return;
    if (count > static_cast<std::size_t>(INT_MAX)) {
        throw Unsupported("draw of " + std::to_string(count) + " elements");
    }
    if (s.viewport.width > max_viewport[0] || s.viewport.height > max_viewport[1]) {
        throw Unsupported("viewport larger than GL_MAX_VIEWPORT_DIMS");
    }
    if (s.line_width > line_width_range[1] || s.point_size > point_size_range[1]) {
        throw Unsupported("line width or point size above this driver's maximum");
    }

    glViewport(s.viewport.x, s.viewport.y, s.viewport.width, s.viewport.height);
    glDepthRange(static_cast<double>(s.depth_near), static_cast<double>(s.depth_far));
    set_enabled(GL_SCISSOR_TEST, s.scissor.has_value());
    if (s.scissor) glScissor(s.scissor->x, s.scissor->y, s.scissor->width, s.scissor->height);

    set_enabled(GL_CULL_FACE, s.cull != refraster::CullMode::None);
    switch (s.cull) {
        case refraster::CullMode::Front:
            glCullFace(GL_FRONT);
            break;
        case refraster::CullMode::FrontAndBack:
            glCullFace(GL_FRONT_AND_BACK);
            break;
        case refraster::CullMode::Back:
        case refraster::CullMode::None:
            glCullFace(GL_BACK);
            break;
    }
    glFrontFace(s.front_face == refraster::FrontFace::Ccw ? GL_CCW : GL_CW);

    // The depth attachment of a depth-less target is only there to keep llvmpipe on its
    // clipping path; it must neither test nor be written.
    if (t.depth == DepthFormat::None) {
        glDisable(GL_DEPTH_TEST);
        glDepthMask(GL_FALSE);
        glDepthFunc(GL_LESS);
    } else {
        set_enabled(GL_DEPTH_TEST, s.depth_test.has_value());
        glDepthFunc(s.depth_test ? compare_func(*s.depth_test) : GL_LESS);
        glDepthMask(s.depth_write ? GL_TRUE : GL_FALSE);
    }

    glProvokingVertex(s.provoking_vertex == refraster::ProvokingVertex::Last
                          ? GL_LAST_VERTEX_CONVENTION
                          : GL_FIRST_VERTEX_CONVENTION);
    glPolygonMode(GL_FRONT_AND_BACK, polygon_mode(s.polygon_mode));
    const bool offset = s.polygon_offset.has_value();
    set_enabled(GL_POLYGON_OFFSET_FILL, offset);
    set_enabled(GL_POLYGON_OFFSET_LINE, offset);
    set_enabled(GL_POLYGON_OFFSET_POINT, offset);
    glPolygonOffset(offset ? s.polygon_offset->factor : 0.0f,
                    offset ? s.polygon_offset->units : 0.0f);
    glLineWidth(s.line_width);
    glPointSize(s.point_size);

    switch (s.blend) {
        case refraster::BlendPreset::None:
            glDisable(GL_BLEND);
            glBlendFunc(GL_ONE, GL_ZERO);
            break;
        case refraster::BlendPreset::Alpha:
            glEnable(GL_BLEND);
            glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
            break;
        case refraster::BlendPreset::Add:
            glEnable(GL_BLEND);
            glBlendFunc(GL_ONE, GL_ONE);
            break;
    }
    check_gl("setting draw state");

    glUseProgram(program(s.shade));
    if (owners) glUniform1ui(glGetUniformLocation(program(s.shade), "draw_index"), current_draw);

    const auto& va = d.vertices;
    const std::uint32_t stride_floats = va.stride();
    const auto stride_bytes = static_cast<GLsizei>(stride_floats * sizeof(float));
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(va.data.size() * sizeof(float)),
                 va.data.data(), GL_STREAM_DRAW);
    glEnableVertexAttribArray(kPositionLocation);
    glVertexAttribPointer(kPositionLocation, 4, GL_FLOAT, GL_FALSE, stride_bytes, nullptr);

    std::optional<std::size_t> color;
    for (std::size_t a = 0; a < va.attributes.size(); ++a) {
        if (va.attributes[a].name == "color") color = a;
    }
    if (color) {
        const std::uint32_t components = va.attributes[*color].components;
        if (components < 1 || components > 4) {
            throw GlFailure("color attribute with " + std::to_string(components) + " components");
        }
        const std::uintptr_t offset_bytes = va.attribute_offset(*color) * sizeof(float);
        glEnableVertexAttribArray(kColorLocation);
        glVertexAttribPointer(kColorLocation, static_cast<GLint>(components), GL_FLOAT, GL_FALSE,
                              stride_bytes, reinterpret_cast<const void*>(offset_bytes));
    } else {
        // The scene format's default colour.
        glDisableVertexAttribArray(kColorLocation);
        glVertexAttrib4f(kColorLocation, 1.0f, 1.0f, 1.0f, 1.0f);
    }
    check_gl("uploading vertices");

    const GLenum mode = primitive_mode(d.primitive);
    if (d.indices) {
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                     static_cast<GLsizeiptr>(d.indices->size() * sizeof(std::uint32_t)),
                     d.indices->data(), GL_STREAM_DRAW);
        glDrawElements(mode, static_cast<GLsizei>(count), GL_UNSIGNED_INT, nullptr);
    } else {
        glDrawArrays(mode, 0, static_cast<GLsizei>(count));
    }
    check_gl("drawing");
}

// The owner attachment: an R32UI renderbuffer at colour attachment 1 of the single-sample
// FBO, cleared to 0, written by the owner programs alongside the colour.
void Renderer::Impl::attach_owners(const refraster::Target& t) {
    if (t.samples != 1) throw Unsupported("primitive owners of a multisampled target");
    glGenRenderbuffers(1, &owner_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, owner_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_R32UI, static_cast<GLsizei>(t.width),
                          static_cast<GLsizei>(t.height));
    glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, owner_rb);
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, bufs);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        throw GlFailure("the framebuffer with the owner attachment is incomplete");
    }
    const GLuint zero[4] = {0, 0, 0, 0};
    glClearBufferuiv(GL_COLOR, 1, zero);
    check_gl("attaching the owner buffer");
}

void Renderer::Impl::detach_owners() {
    if (owner_rb == 0) return;
    glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, 0);
    const GLenum buf = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &buf);
    glDeleteRenderbuffers(1, &owner_rb);
    owner_rb = 0;
}

refraster::Framebuffer Renderer::Impl::read_back(const refraster::Target& t) {
    const auto w = static_cast<GLsizei>(t.width);
    const auto h = static_cast<GLsizei>(t.height);
    if (t.samples == 4) {
        // Blits obey the scissor test (and, in some drivers, the depth mask).
        glDisable(GL_SCISSOR_TEST);
        glDepthMask(GL_TRUE);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, target.ms_fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.fbo);
        GLbitfield mask = GL_COLOR_BUFFER_BIT;
        if (t.depth != DepthFormat::None) mask |= GL_DEPTH_BUFFER_BIT;
        glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, mask, GL_NEAREST);
        check_gl("multisample resolve");
    }

    refraster::Framebuffer fb(t.width, t.height, t.color, t.depth);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    if (t.color == ColorFormat::Rgba8) {
        glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, fb.color8.data());
    } else {
        glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, fb.color32f.data());
    }
    check_gl("reading colour");

    switch (t.depth) {
        case DepthFormat::None:
            break;
        case DepthFormat::Z16: {
            std::vector<std::uint16_t> z(fb.pixel_count());
            glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT, z.data());
            std::copy(z.begin(), z.end(), fb.depth.begin());
            break;
        }
        case DepthFormat::Z24: {
            // GL scales to 32 bits; the top 24 are the stored value.
            glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, fb.depth.data());
            for (auto& v : fb.depth) v >>= 8;
            break;
        }
        case DepthFormat::Z32f: {
            std::vector<float> z(fb.pixel_count());
            glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, z.data());
            std::transform(z.begin(), z.end(), fb.depth.begin(),
                           [](float v) { return std::bit_cast<std::uint32_t>(v); });
            break;
        }
    }
    check_gl("reading depth");
    if (owners) {
        fb.owner.assign(fb.pixel_count(), 0);
        glReadBuffer(GL_COLOR_ATTACHMENT1);
        glReadPixels(0, 0, w, h, GL_RED_INTEGER, GL_UNSIGNED_INT, fb.owner.data());
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        check_gl("reading owners");
    }
    return fb;
}

Renderer::Renderer(std::string_view backend, std::string_view mesa_package)
    : impl_(std::make_unique<Impl>()) {
    auto& p = impl_->provenance;
    p["backend"] = std::string(backend);
    p["renderer"] = gl_string(GL_RENDERER);
    p["gl_version"] = gl_string(GL_VERSION);
    p["glsl_version"] = gl_string(GL_SHADING_LANGUAGE_VERSION);
    const char* driver = std::getenv("GALLIUM_DRIVER");
    p["driver"] = driver && *driver ? driver : "llvmpipe";
    p["env"] = mesa_environment();
    p["mesa_version"] = debian_package_version(mesa_package);

    impl_->max_samples = gl_int(GL_MAX_SAMPLES);
    impl_->max_renderbuffer = gl_int(GL_MAX_RENDERBUFFER_SIZE);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, impl_->max_viewport.data());
    glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, impl_->line_width_range.data());
    glGetFloatv(GL_ALIASED_POINT_SIZE_RANGE, impl_->point_size_range.data());
    glGenVertexArrays(1, &impl_->vao);
    glGenBuffers(1, &impl_->vbo);
    glGenBuffers(1, &impl_->ibo);
    drain_gl_errors();
}

Renderer::~Renderer() {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    impl_->target.release();
    for (GLuint p : impl_->programs) {
        if (p != 0) glDeleteProgram(p);
    }
    glDeleteBuffers(1, &impl_->vbo);
    glDeleteBuffers(1, &impl_->ibo);
    glDeleteVertexArrays(1, &impl_->vao);
}

const harness::Provenance& Renderer::provenance() const {
    return impl_->provenance;
}

harness::RenderResult Renderer::render(const refraster::DrawList& list, bool owners) {
    const auto start = std::chrono::steady_clock::now();
    harness::RenderResult r;
    r.provenance = impl_->provenance;
    try {
        drain_gl_errors();
        impl_->prepare_target(list.target);
        impl_->set_fixed_state(list.target.samples == 4);
        impl_->clear(list);
        impl_->owners = owners;
        if (owners) impl_->attach_owners(list.target);
        for (std::size_t i = 0; i < list.draws.size(); ++i) {
            impl_->current_draw = static_cast<GLuint>(i);
            impl_->draw(list.target, list.draws[i]);
        }
        r.image = impl_->read_back(list.target);
        impl_->detach_owners();
        impl_->owners = false;
    } catch (const Unsupported& e) {
        r.status = harness::RenderStatus::NotSupported;
        r.message = e.what();
    } catch (const GlFailure& e) {
        r.status = harness::RenderStatus::InternalError;
        r.message = e.what();
    } catch (const std::bad_alloc&) {
        r.status = harness::RenderStatus::InternalError;
        r.message = "out of memory in the worker";
    } catch (const std::exception& e) {
        r.status = harness::RenderStatus::InternalError;
        r.message = e.what();
    }
    if (r.status != harness::RenderStatus::Ok) {
        impl_->detach_owners();
        impl_->owners = false;
        r.image = refraster::Framebuffer{};
        drain_gl_errors();
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

int run_worker(std::string_view backend, std::string_view mesa_package,
               const std::function<std::unique_ptr<ContextHolder>()>& make_context) {
    constexpr const char* kKillAtVariable = "REFRASTER_WORKER_KILL_AT";
    // The protocol gets a private copy of the original stdout; fd 1 then points at stderr,
    // so anything a library prints to stdout lands in the log instead of inside a frame.
    const int out = ::fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
    if (out < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
        std::perror("refraster worker: redirecting stdout");
        return 3;
    }
    const int in = STDIN_FILENO;
    // A harness that has gone away shows up as EPIPE, handled below.
    ::signal(SIGPIPE, SIG_IGN);
    // Test hook for whole runs through the CLI: die by SIGKILL on receiving the Nth scene,
    // as an out-of-memory kill would.
    unsigned long kill_at = 0;
    if (const char* k = std::getenv(kKillAtVariable)) kill_at = std::strtoul(k, nullptr, 10);
    // And the same for a hang: stop answering on the Nth scene, as a driver stuck in a loop would.
    unsigned long hang_at = 0;
    if (const char* k = std::getenv("REFRASTER_WORKER_HANG_AT"))
        hang_at = std::strtoul(k, nullptr, 10);
    unsigned long scenes = 0;

    try {
        std::unique_ptr<ContextHolder> context;
        harness::RenderResult hello;
        try {
            context = make_context();
        } catch (const std::exception& e) {
            hello.status = harness::RenderStatus::InternalError;
            hello.message = e.what();
            wire::write_frame(out, wire::FrameType::Hello, wire::encode_result(hello));
            return 1;
        }
        std::optional<Renderer> renderer;
        renderer.emplace(backend, mesa_package);
        hello.provenance = renderer->provenance();
        wire::write_frame(out, wire::FrameType::Hello, wire::encode_result(hello));

        while (auto frame = wire::read_frame(in)) {
            switch (static_cast<wire::FrameType>(frame->type)) {
                case wire::FrameType::Render:
                case wire::FrameType::RenderOwners: {
                    if (++scenes == kill_at) ::raise(SIGKILL);
                    if (scenes == hang_at) {
                        for (;;) ::pause();
                    }
                    harness::RenderResult reply;
                    try {
                        reply = renderer->render(wire::decode_draw_list(frame->payload),
                                                 frame->type == static_cast<std::uint32_t>(
                                                                    wire::FrameType::RenderOwners));
                    } catch (const wire::WireError& e) {
                        reply.status = harness::RenderStatus::InternalError;
                        reply.message = std::string("bad request: ") + e.what();
                        reply.provenance = renderer->provenance();
                    }
                    wire::write_frame(out, wire::FrameType::Reply, wire::encode_result(reply));
                    break;
                }
                case wire::FrameType::Crash: {
                    // A test asked for a crash; a core file would only litter the build tree.
                    const rlimit none{0, 0};
                    ::setrlimit(RLIMIT_CORE, &none);
                    std::abort();
                }
                case wire::FrameType::Hang:
                    for (;;) ::pause();
                case wire::FrameType::Hello:
                case wire::FrameType::Reply:
                default: {
                    harness::RenderResult reply;
                    reply.status = harness::RenderStatus::InternalError;
                    reply.message = "unexpected frame type " + std::to_string(frame->type);
                    wire::write_frame(out, wire::FrameType::Reply, wire::encode_result(reply));
                    break;
                }
            }
        }
        renderer.reset();
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "refraster worker (%.*s): %s\n", static_cast<int>(backend.size()),
                     backend.data(), e.what());
        return 2;
    }
}

}  // namespace harness::gl
