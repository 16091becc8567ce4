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
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <vector>

#include "backends/driver_env.hpp"
#include "backends/wire.hpp"
#include "gl_enums.hpp"
#include "gl_provenance.hpp"
#include "refraster/framebuffer.hpp"

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
constexpr GLuint kTexcoordLocation = 2;

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

// Compiles and links a program; `before_link` binds locations first. Throws GlFailure with
// the driver's log when either step fails.
GLuint link_program(const std::string& vs_source, const std::string& fs_source,
                    const std::function<void(GLuint)>& before_link = {}) {
    const GLuint v = compile_shader(GL_VERTEX_SHADER, vs_source);
    GLuint f = 0;
    try {
        f = compile_shader(GL_FRAGMENT_SHADER, fs_source);
    } catch (...) {
        glDeleteShader(v);
        throw;
    }
    const GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    if (before_link) before_link(p);
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
    return p;
}

// The owner pass needs gl_PrimitiveID in the fragment shader (GLSL 1.50) and an unsigned
// integer output; everything else is the colour program's.
constexpr const char* kGlslOwnerVersion = "#version 150 compatibility\n";

struct ProgramSources {
    std::string vertex;
    std::string fragment;
};

// The pass-through program of one shade model, with or without the owner output, and with a
// texture (env given) or without. Without a texture the sources are exactly those the colour
// and owner programs always had. With one, the texture coordinate is interpolated with the
// colour's qualifier and the texel of unit 0 sampled with textureProj at (s, t, q); with
// `point_sprite` it is sampled with texture at gl_PointCoord (GL_POINT_SPRITE is always on,
// so the rasterizer replaces it for points) and the vertex's coordinate is not read.
ProgramSources program_sources(refraster::ShadeModel shade, bool owners,
                               std::optional<refraster::TextureEnv> env, bool point_sprite) {
    const std::string q = qualifier(shade);
    const std::string version = owners ? kGlslOwnerVersion : kGlslVersion;
    const bool textured = env.has_value();
    const bool coords = textured && !point_sprite;
    const std::string color_out = !textured ? "    frag_color = v_color;\n"
                                  : *env == refraster::TextureEnv::Modulate
                                      ? "    frag_color = v_color * t;\n"
                                      : "    frag_color = t;\n";
    ProgramSources src;
    src.vertex = version +
                 "in vec4 position;\n"
                 "in vec4 color;\n" +
                 (coords ? "in vec4 texcoord;\n" : "") + q + " out vec4 v_color;\n" +
                 (coords ? q + " out vec4 v_texcoord;\n" : "") +
                 "void main() {\n"
                 "    gl_Position = position;\n"
                 "    v_color = color;\n" +
                 (coords ? "    v_texcoord = texcoord;\n" : "") + "}\n";
    const std::string sample =
        !textured ? ""
        : point_sprite
            ? "    vec4 t = texture(tex, gl_PointCoord);\n"
            : "    vec4 t = textureProj(tex, vec3(v_texcoord.s, v_texcoord.t, v_texcoord.q));\n";
    src.fragment = version + q + " in vec4 v_color;\n" +
                   (coords ? q + " in vec4 v_texcoord;\n" : "") + "out vec4 frag_color;\n" +
                   (owners ? "out uint frag_owner;\n"
                             "uniform uint draw_index;\n"
                             "uniform uint one_primitive;\n"
                           : "") +
                   (textured ? "uniform sampler2D tex;\n" : "") + "void main() {\n" + sample +
                   color_out +
                   (owners ? "    frag_owner = (draw_index << 24) | (one_primitive != 0u ? 1u : "
                             "(uint(gl_PrimitiveID + 1) & 0xffffffu));\n"
                           : "") +
                   "}\n";
    return src;
}

GLuint build_program(refraster::ShadeModel shade, bool owners,
                     std::optional<refraster::TextureEnv> env, bool point_sprite) {
    const ProgramSources src = program_sources(shade, owners, env, point_sprite);
    const bool coords = env.has_value() && !point_sprite;
    const GLuint p = link_program(src.vertex, src.fragment, [owners, coords](GLuint program) {
        glBindAttribLocation(program, kPositionLocation, "position");
        glBindAttribLocation(program, kColorLocation, "color");
        if (coords) glBindAttribLocation(program, kTexcoordLocation, "texcoord");
        glBindFragDataLocation(program, 0, "frag_color");
        if (owners) glBindFragDataLocation(program, 1, "frag_owner");
    });
    if (env) {
        glUseProgram(p);
        glUniform1i(glGetUniformLocation(p, "tex"), 0);  // texture unit 0
    }
    check_gl("building the shader program");
    return p;
}

struct TargetObjects {
    refraster::Target key;
    // The depth buffer has stencil bits too: the draw list has a draw with a fill rule.
    bool stencil = false;
    bool valid = false;
    // Single-sample renderbuffers: rendered into and read (1x), or the blit's colour (4x).
    GLuint fbo = 0;
    GLuint color_rb = 0;
    GLuint depth_rb = 0;
    GLuint stencil_rb = 0;  // a stencil of its own beside z16, which has no combined format
    // 4x only: multisample textures, so that every sample can be fetched.
    GLuint ms_fbo = 0;
    GLuint ms_color_tex = 0;
    GLuint ms_depth_tex = 0;
    GLuint ms_stencil_rb = 0;

    void release() {
        const GLuint fbos[] = {fbo, ms_fbo};
        const GLuint rbs[] = {color_rb, depth_rb, stencil_rb, ms_stencil_rb};
        const GLuint texs[] = {ms_color_tex, ms_depth_tex};
        glDeleteFramebuffers(2, fbos);
        glDeleteRenderbuffers(4, rbs);
        glDeleteTextures(2, texs);
        *this = TargetObjects{};
    }
};

// Whether a draw list needs a stencil buffer: a polygon drawn with a fill rule counts its
// coverage there (docs/scene-format.md, "How a GL backend draws a fill rule").
bool needs_stencil(const refraster::DrawList& list) {
    for (const auto& d : list.draws) {
        if (d.state.fill_rule) return true;
    }
    return false;
}

// After an allocation: GL_OUT_OF_MEMORY is Unsupported (the scene asks for more than this
// driver can hold), any other error a GlFailure.
void check_allocation(const char* what) {
    const GLenum e = glGetError();
    if (e == GL_OUT_OF_MEMORY) throw Unsupported(std::string(what) + ": out of memory");
    if (e != GL_NO_ERROR) {
        throw GlFailure(std::string("GL error ") + hex(e) + " (" + gl_error_name(e) + ") at " +
                        what);
    }
}

// A full-screen triangle from gl_VertexID: (-1,-1), (3,-1), (-1,3). Every pixel centre and
// every sample position of the viewport lies strictly inside it.
constexpr const char* kFullScreenVertexShader =
    "#version 330\n"
    "void main() {\n"
    "    vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID & 2) * 2 - 1));\n"
    "    gl_Position = vec4(p, 0.0, 1.0);\n"
    "}\n";

}  // namespace

std::optional<std::uint32_t> depth_from_fetch(refraster::DepthFormat format,
                                              std::uint32_t fetched) {
    const std::uint32_t bits = refraster::depth_bits(format);
    if (bits != 16 && bits != 24) return std::nullopt;
    const std::uint32_t max = (1u << bits) - 1;
    // The constant llvmpipe multiplies by: 1 / (2^n - 1) in double, then made a float.
    const auto scale = static_cast<float>(1.0 / static_cast<double>(max));
    const float d = std::bit_cast<float>(fetched);
    if (!(d >= 0.0f && d <= 1.0f)) return std::nullopt;
    const std::int64_t estimate = std::llround(static_cast<double>(d) * max);
    // Downwards, so that 1.0, the fetch of both 2^24 - 2 and 2^24 - 1, gives the larger.
    for (std::int64_t z = std::min<std::int64_t>(estimate + 2, max);
         z >= std::max<std::int64_t>(estimate - 2, 0); --z) {
        const float back = static_cast<float>(z) * scale;
        if (std::bit_cast<std::uint32_t>(back) == fetched) return static_cast<std::uint32_t>(z);
    }
    return std::nullopt;
}

namespace {

// What the z24 fetch pass writes for a sample that fetched as 1.0 but failed the depth test
// GL_GREATER against 1.0 in the marking pass, that is, a stored 2^24 - 2 (a NaN's bits: no
// fetch of a depth in [0, 1] gives it).
constexpr std::uint32_t kZ24BelowOne = 0x7fc0fffeu;
constexpr std::uint32_t kZ24Max = (1u << 24) - 1;

}  // namespace

struct SampleReader::Impl {
    GLuint vao = 0;
    GLuint fbo = 0;
    // Attachment 0: colour (RGBA8 or RGBA32UI), 1: depth bits (R32UI), 2: owners (R32UI).
    std::array<GLuint, 3> rbs{};
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    refraster::ColorFormat color_format = refraster::ColorFormat::Rgba8;
    std::map<std::uint32_t, GLuint> programs;  // by program_key
    // The z24 marking pass: an R32UI texture of the source's shape, and the framebuffer that
    // pairs it with the source's depth.
    GLuint mark_fbo = 0;
    GLuint mark_tex = 0;
    std::array<std::uint32_t, 3> mark_shape{};  // width, height, samples
    GLuint mark_program = 0;

    static bool marks(const SampleSources& s) {
        return s.depth_format == refraster::DepthFormat::Z24 && s.depth_texture != 0 &&
               !s.raw_depth;
    }
    static std::uint32_t program_key(const SampleSources& s) {
        return (s.samples == 4 ? 1u : 0u) | (s.color_texture ? 2u : 0u) |
               (s.color_format == refraster::ColorFormat::Rgba32f ? 4u : 0u) |
               (s.depth_texture ? 8u : 0u) | (s.owner_texture ? 16u : 0u) | (marks(s) ? 32u : 0u);
    }
    GLuint program(const SampleSources& s);
    void prepare_targets(const SampleSources& s);
    void mark_below_one(const SampleSources& s);
    void release_targets() {
        glDeleteFramebuffers(1, &fbo);
        glDeleteRenderbuffers(3, rbs.data());
        fbo = 0;
        rbs = {};
        width = height = 0;
    }
    void release_marks() {
        glDeleteFramebuffers(1, &mark_fbo);
        glDeleteTextures(1, &mark_tex);
        mark_fbo = mark_tex = 0;
        mark_shape = {};
    }
};

// llvmpipe fetches both 2^24 - 2 and 2^24 - 1 of a z24 texture as 1.0. They differ in the
// depth test, which compares the stored integers: a fragment at depth 1.0 (stored as
// 2^24 - 1) passes GL_GREATER exactly where the stored value is below 2^24 - 1. This pass
// draws such a fragment over every sample, writing 1 into the mark texture where it passes;
// the fetch pass then tells the two apart.
void SampleReader::Impl::mark_below_one(const SampleSources& s) {
    const GLenum tex_target = s.samples == 4 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D;
    const std::array<std::uint32_t, 3> shape{s.width, s.height, s.samples};
    const auto w = static_cast<GLsizei>(s.width);
    const auto h = static_cast<GLsizei>(s.height);
    if (mark_fbo == 0 || mark_shape != shape) {
        release_marks();
        glGenTextures(1, &mark_tex);
        glBindTexture(tex_target, mark_tex);
        if (s.samples == 4) {
            glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, 4, GL_R32UI, w, h, GL_TRUE);
        } else {
            glTexImage2D(GL_TEXTURE_2D, 0, GL_R32UI, w, h, 0, GL_RED_INTEGER, GL_UNSIGNED_INT,
                         nullptr);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
        }
        glBindTexture(tex_target, 0);
        check_allocation("allocating the z24 marks");
        glGenFramebuffers(1, &mark_fbo);
        mark_shape = shape;
    }
    if (mark_program == 0) {
        mark_program = link_program(kFullScreenVertexShader,
                                    "#version 330\n"
                                    "layout(location = 0) out uint mark;\n"
                                    "void main() {\n"
                                    "    mark = 1u;\n"
                                    "    gl_FragDepth = 1.0;\n"
                                    "}\n");
    }
    glBindFramebuffer(GL_FRAMEBUFFER, mark_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, tex_target, mark_tex, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, tex_target, s.depth_texture, 0);
    const GLenum buf = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &buf);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        throw GlFailure("the z24 marking framebuffer is incomplete");
    }
    const GLuint zero[4] = {0, 0, 0, 0};
    glClearBufferuiv(GL_COLOR, 0, zero);
    // Every sample tested on its own, nothing written but the marks.
    set_enabled(GL_MULTISAMPLE, s.samples == 4);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    glDepthRange(0.0, 1.0);
    glDisable(GL_DEPTH_CLAMP);
    glUseProgram(mark_program);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDisable(GL_MULTISAMPLE);
    // The depth texture is read next: it must not stay attached to a framebuffer.
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, tex_target, 0, 0);
    check_gl("marking z24 samples below 1.0");
}

// The fetch program of one combination of sources. With one sample a pixel the samplers are
// sampler2D, read at level 0; the conversions from the stored formats are the same.
GLuint SampleReader::Impl::program(const SampleSources& s) {
    const std::uint32_t key = program_key(s);
    if (auto it = programs.find(key); it != programs.end()) return it->second;
    const bool ms = s.samples == 4;
    const std::string dim = ms ? "2DMS" : "2D";
    const std::string at = ms ? "sample_index" : "0";
    const bool float_color = s.color_format == refraster::ColorFormat::Rgba32f;
    std::string fs = "#version 330\nuniform int sample_index;\n";
    std::string body = "    ivec2 p = ivec2(gl_FragCoord.xy);\n";
    if (s.color_texture) {
        fs += "uniform sampler" + dim + " color_in;\n";
        if (float_color) {
            fs += "layout(location = 0) out uvec4 color_out;\n";
            body += "    color_out = floatBitsToUint(texelFetch(color_in, p, " + at + "));\n";
        } else {
            fs += "layout(location = 0) out vec4 color_out;\n";
            body += "    color_out = texelFetch(color_in, p, " + at + ");\n";
        }
    }
    if (s.depth_texture) {
        fs += "uniform sampler" + dim + " depth_in;\nlayout(location = 1) out uint depth_out;\n";
        body += "    float d = texelFetch(depth_in, p, " + at + ").r;\n";
        body += "    depth_out = floatBitsToUint(d);\n";
        if (marks(s)) {
            fs += "uniform usampler" + dim + " mark_in;\n";
            body += "    if (d == 1.0 && texelFetch(mark_in, p, " + at + ").r != 0u) {\n";
            body += "        depth_out = " + std::to_string(kZ24BelowOne) + "u;\n    }\n";
        }
    }
    if (s.owner_texture) {
        fs += "uniform usampler" + dim + " owner_in;\nlayout(location = 2) out uint owner_out;\n";
        body += "    owner_out = texelFetch(owner_in, p, " + at + ").r;\n";
    }
    fs += "void main() {\n" + body + "}\n";
    const GLuint p = link_program(kFullScreenVertexShader, fs);
    glUseProgram(p);
    glUniform1i(glGetUniformLocation(p, "color_in"), 0);
    glUniform1i(glGetUniformLocation(p, "depth_in"), 1);
    glUniform1i(glGetUniformLocation(p, "owner_in"), 2);
    glUniform1i(glGetUniformLocation(p, "mark_in"), 3);
    check_gl("building a sample fetch program");
    programs.emplace(key, p);
    return p;
}

void SampleReader::Impl::prepare_targets(const SampleSources& s) {
    if (fbo != 0 && width == s.width && height == s.height && color_format == s.color_format) {
        return;
    }
    release_targets();
    const auto w = static_cast<GLsizei>(s.width);
    const auto h = static_cast<GLsizei>(s.height);
    const GLenum color = s.color_format == refraster::ColorFormat::Rgba32f ? GL_RGBA32UI : GL_RGBA8;
    const GLenum formats[3] = {color, GL_R32UI, GL_R32UI};
    glGenFramebuffers(1, &fbo);
    glGenRenderbuffers(3, rbs.data());
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    for (GLuint i = 0; i < 3; ++i) {
        glBindRenderbuffer(GL_RENDERBUFFER, rbs[i]);
        glRenderbufferStorage(GL_RENDERBUFFER, formats[i], w, h);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + i, GL_RENDERBUFFER,
                                  rbs[i]);
    }
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    check_allocation("allocating the sample read-back targets");
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        throw GlFailure("the sample read-back framebuffer is incomplete");
    }
    width = s.width;
    height = s.height;
    color_format = s.color_format;
}

SampleReader::SampleReader() : impl_(std::make_unique<Impl>()) {
    glGenVertexArrays(1, &impl_->vao);
}

SampleReader::~SampleReader() {
    impl_->release_targets();
    impl_->release_marks();
    if (impl_->mark_program != 0) glDeleteProgram(impl_->mark_program);
    for (const auto& [key, p] : impl_->programs) glDeleteProgram(p);
    glDeleteVertexArrays(1, &impl_->vao);
}

refraster::Framebuffer SampleReader::read(const SampleSources& src) {
    if (src.samples != 1 && src.samples != 4) throw GlFailure("samples other than 1 or 4");
    if ((src.depth_texture != 0) != (src.depth_format != refraster::DepthFormat::None)) {
        throw GlFailure("a depth texture without a depth format, or the reverse");
    }
    auto& m = *impl_;
    const auto w = static_cast<GLsizei>(src.width);
    const auto h = static_cast<GLsizei>(src.height);
    const std::size_t n = std::size_t{src.width} * src.height;
    refraster::Framebuffer fb(src.width, src.height, src.color_format, src.depth_format,
                              src.samples);
    if (src.owner_texture) fb.owner.assign(n * src.samples, 0);
    if (n == 0) return fb;

    m.prepare_targets(src);
    const GLuint program = m.program(src);
    glBindVertexArray(m.vao);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_CULL_FACE);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_RASTERIZER_DISCARD);
    glDisable(GL_SAMPLE_MASK);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glViewport(0, 0, w, h);
    if (Impl::marks(src)) m.mark_below_one(src);

    // Nothing may stand between the fetched value and the target.
    glBindFramebuffer(GL_FRAMEBUFFER, m.fbo);
    const GLenum bufs[3] = {src.color_texture ? GLenum{GL_COLOR_ATTACHMENT0} : GLenum{GL_NONE},
                            src.depth_texture ? GLenum{GL_COLOR_ATTACHMENT1} : GLenum{GL_NONE},
                            src.owner_texture ? GLenum{GL_COLOR_ATTACHMENT2} : GLenum{GL_NONE}};
    glDrawBuffers(3, bufs);
    glViewport(0, 0, w, h);
    constexpr std::array<GLenum, 15> kOff = {GL_SCISSOR_TEST,
                                             GL_DEPTH_TEST,
                                             GL_STENCIL_TEST,
                                             GL_BLEND,
                                             GL_CULL_FACE,
                                             GL_POLYGON_OFFSET_FILL,
                                             GL_SAMPLE_MASK,
                                             GL_ALPHA_TEST,
                                             GL_COLOR_LOGIC_OP,
                                             GL_DITHER,
                                             GL_RASTERIZER_DISCARD,
                                             GL_MULTISAMPLE,
                                             GL_SAMPLE_ALPHA_TO_COVERAGE,
                                             GL_SAMPLE_COVERAGE,
                                             GL_FRAMEBUFFER_SRGB};
    for (GLenum cap : kOff) glDisable(cap);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glClampColor(GL_CLAMP_FRAGMENT_COLOR, GL_FALSE);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glPixelStorei(GL_PACK_SKIP_ROWS, 0);
    glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);

    const GLenum tex_target = src.samples == 4 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D;
    const GLuint textures[4] = {src.color_texture, src.depth_texture, src.owner_texture,
                                Impl::marks(src) ? m.mark_tex : 0};
    for (GLuint unit = 0; unit < 4; ++unit) {
        glActiveTexture(GL_TEXTURE0 + unit);
        glBindTexture(tex_target, textures[unit]);
        if (src.samples == 1 && textures[unit] != 0) {
            // texelFetch of level 0 needs a complete texture, whatever its mipmaps.
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
        }
    }
    glActiveTexture(GL_TEXTURE0);
    glUseProgram(program);
    glBindVertexArray(m.vao);
    check_gl("setting up the sample fetch");

    const GLint sample_location = glGetUniformLocation(program, "sample_index");
    std::vector<std::uint8_t> bytes(src.color_texture && !fb.color8.empty() ? n * 4 : 0);
    std::vector<std::uint32_t> words(n * 4);
    const std::size_t k = src.samples;
    for (std::uint32_t s = 0; s < src.samples; ++s) {
        glUniform1i(sample_location, static_cast<GLint>(s));
        glDrawArrays(GL_TRIANGLES, 0, 3);
        check_gl("fetching samples");
        if (src.color_texture) {
            glReadBuffer(GL_COLOR_ATTACHMENT0);
            if (src.color_format == refraster::ColorFormat::Rgba8) {
                glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
                for (std::size_t i = 0; i < n; ++i) {
                    std::memcpy(&fb.color8[(i * k + s) * 4], &bytes[i * 4], 4);
                }
            } else {
                glReadPixels(0, 0, w, h, GL_RGBA_INTEGER, GL_UNSIGNED_INT, words.data());
                for (std::size_t i = 0; i < n; ++i) {
                    std::memcpy(&fb.color32f[(i * k + s) * 4], &words[i * 4], 16);
                }
            }
            check_gl("reading colour samples");
        }
        if (src.depth_texture) {
            glReadBuffer(GL_COLOR_ATTACHMENT1);
            glReadPixels(0, 0, w, h, GL_RED_INTEGER, GL_UNSIGNED_INT, words.data());
            check_gl("reading depth samples");
            const bool unorm = src.depth_format == refraster::DepthFormat::Z16 ||
                               src.depth_format == refraster::DepthFormat::Z24;
            for (std::size_t i = 0; i < n; ++i) {
                std::uint32_t v = words[i];
                if (v == kZ24BelowOne && Impl::marks(src)) {
                    fb.depth[i * k + s] = kZ24Max - 1;
                    continue;
                }
                if (unorm && !src.raw_depth) {
                    const auto z = depth_from_fetch(src.depth_format, v);
                    if (!z) {
                        throw GlFailure("a " + std::string(refraster::to_string(src.depth_format)) +
                                        " depth sample fetched as float bits " + hex(v) +
                                        " is no value of its format");
                    }
                    v = *z;
                }
                fb.depth[i * k + s] = v;
            }
        }
        if (src.owner_texture) {
            glReadBuffer(GL_COLOR_ATTACHMENT2);
            glReadPixels(0, 0, w, h, GL_RED_INTEGER, GL_UNSIGNED_INT, words.data());
            check_gl("reading owner samples");
            for (std::size_t i = 0; i < n; ++i) fb.owner[i * k + s] = words[i];
        }
    }
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    return fb;
}

struct Renderer::Impl {
    harness::Provenance provenance;
    // By ShadeModel, then with owners, then untextured, modulate, replace; 0 until first use.
    // By shade model (3), owners (2) and variant (5): untextured, then each env with the
    // vertex's coordinates and with point sprite coordinates.
    std::array<GLuint, 30> programs{};
    // The GL textures of the DrawList being rendered, by index; made at the start of each
    // render and deleted at its end.
    std::vector<GLuint> textures;
    bool owners = false;                        // this render writes the owner attachment
    GLuint owner_rb = 0;                        // 1x
    GLuint owner_tex = 0;                       // 4x: a multisample texture
    std::optional<SampleReader> sample_reader;  // made at the first 4x target
    GLuint current_draw = 0;
    GLuint vao = 0;
    GLuint vbo = 0;
    GLuint ibo = 0;
    TargetObjects target;
    GLint max_samples = 0;
    GLint max_texture_samples = 0;  // the least of colour, depth and integer textures
    GLint max_texture_size = 0;
    GLint max_renderbuffer = 0;
    std::array<GLint, 2> max_viewport{};
    std::array<GLfloat, 2> line_width_range{};
    std::array<GLfloat, 2> point_size_range{};

    GLuint program(refraster::ShadeModel shade, std::optional<refraster::TextureEnv> env,
                   bool point_sprite) {
        const std::size_t variant =
            env ? 1 + static_cast<std::size_t>(*env) + (point_sprite ? 2 : 0) : 0;
        GLuint& p = programs[static_cast<std::size_t>(shade) + (owners ? 3 : 0) + 6 * variant];
        if (p == 0) p = build_program(shade, owners, env, point_sprite);
        return p;
    }
    void upload_textures(const refraster::DrawList& list);
    void release_textures() {
        if (!textures.empty()) {
            glDeleteTextures(static_cast<GLsizei>(textures.size()), textures.data());
        }
        textures.clear();
    }
    void bind_texture(const refraster::TextureState& ts);
    void attach_owners(const refraster::Target& t);
    void detach_owners();

    void prepare_target(const refraster::Target& t, bool stencil);
    void set_fixed_state();
    void clear(const refraster::DrawList& list);
    void draw(const refraster::Target& t, const refraster::Draw& d);
    void read_back(const refraster::Target& t, harness::RenderResult& r);
    refraster::Framebuffer read_single(const refraster::Target& t);
};

void Renderer::Impl::prepare_target(const refraster::Target& t, bool stencil) {
    if (t.samples != 1 && t.samples != 4) {
        throw Unsupported("samples " + std::to_string(t.samples) + " (only 1 and 4 exist)");
    }
    if (t.samples == 4 && max_samples < 4) {
        throw Unsupported("4x multisampling: this driver reports GL_MAX_SAMPLES " +
                          std::to_string(max_samples));
    }
    if (t.samples == 4 && max_texture_samples < 4) {
        throw Unsupported("4x multisample textures: this driver allows " +
                          std::to_string(max_texture_samples) + " samples");
    }
    if (t.samples == 4 && (t.width > static_cast<GLuint>(max_texture_size) ||
                           t.height > static_cast<GLuint>(max_texture_size))) {
        throw Unsupported("4x target " + std::to_string(t.width) + "x" + std::to_string(t.height) +
                          " (GL_MAX_TEXTURE_SIZE " + std::to_string(max_texture_size) + ")");
    }
    if (t.width == 0 || t.height == 0 || t.width > static_cast<GLuint>(max_renderbuffer) ||
        t.height > static_cast<GLuint>(max_renderbuffer)) {
        throw Unsupported("target " + std::to_string(t.width) + "x" + std::to_string(t.height) +
                          " (GL_MAX_RENDERBUFFER_SIZE " + std::to_string(max_renderbuffer) + ")");
    }
    if (target.valid && target.key == t && target.stencil == stencil) return;
    target.release();

    const auto w = static_cast<GLsizei>(t.width);
    const auto h = static_cast<GLsizei>(t.height);
    const GLenum cf = color_internal_format(t.color);
    const GLenum df = depth_internal_format(t.depth, stencil);
    // Where the depth buffer attaches: a combined format holds the stencil too; z16 gets a
    // stencil renderbuffer of its own.
    const bool combined = stencil && t.depth != DepthFormat::Z16;
    const GLenum depth_attachment = combined ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT;
    const bool separate_stencil = stencil && !combined;

    // The count actually granted, which may differ from the count asked for.
    auto check_samples = [](GLsizei samples) {
        const GLint got = gl_int(GL_SAMPLES);
        const GLint want = samples > 1 ? samples : 0;
        if (got != want) {
            throw Unsupported("asked for " + std::to_string(samples) + " samples, got " +
                              std::to_string(got));
        }
    };
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
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, depth_attachment, GL_RENDERBUFFER, depth);
            if (separate_stencil) {
                glGenRenderbuffers(1, &target.stencil_rb);
                glBindRenderbuffer(GL_RENDERBUFFER, target.stencil_rb);
                glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_STENCIL_INDEX8, w, h);
                glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                          target.stencil_rb);
            }
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
            throw Unsupported(std::string("framebuffer") +
                              (separate_stencil ? " of z16 depth and a separate stencil" : "") +
                              " incomplete (status " + hex(status) + ")");
        }
        check_samples(samples);
    };
    // 4x: colour and depth are multisample textures with fixed sample locations, which the
    // sample reader fetches from.
    auto make_ms_fbo = [&]() {
        glGenFramebuffers(1, &target.ms_fbo);
        glGenTextures(1, &target.ms_color_tex);
        glGenTextures(1, &target.ms_depth_tex);
        glBindFramebuffer(GL_FRAMEBUFFER, target.ms_fbo);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, target.ms_color_tex);
        glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, 4, cf, w, h, GL_TRUE);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D_MULTISAMPLE,
                               target.ms_color_tex, 0);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, target.ms_depth_tex);
        glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, 4, df, w, h, GL_TRUE);
        glFramebufferTexture2D(GL_FRAMEBUFFER, depth_attachment, GL_TEXTURE_2D_MULTISAMPLE,
                               target.ms_depth_tex, 0);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
        if (separate_stencil) {
            glGenRenderbuffers(1, &target.ms_stencil_rb);
            glBindRenderbuffer(GL_RENDERBUFFER, target.ms_stencil_rb);
            glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_STENCIL_INDEX8, w, h);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                      target.ms_stencil_rb);
            glBindRenderbuffer(GL_RENDERBUFFER, 0);
        }
        check_allocation("creating the multisample framebuffer");
        const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE) {
            throw Unsupported("multisample framebuffer incomplete (status " + hex(status) + ")");
        }
        check_samples(4);
    };

    try {
        target.key = t;
        target.stencil = stencil;
        if (t.samples == 4) {
            // Rendering always has depth; the blit resolves colour only (the image's depth
            // is sample 0's, read with the samples).
            make_ms_fbo();
            make_fbo(0, false, target.fbo, target.color_rb, target.depth_rb);
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

void Renderer::Impl::set_fixed_state() {
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
    glStencilMask(0xff);
    glClearStencil(0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT |
            (target.stencil ? GL_STENCIL_BUFFER_BIT : 0u));
    check_gl("clear");
}

namespace {

// A polygon with a fill rule, by the stencil method (docs/scene-format.md, "How a GL backend
// draws a fill rule"): the polygon's triangles first count their coverage in the stencil
// buffer with colour, depth and culling off (INVERT for even-odd; INCR_WRAP on front faces and
// DECR_WRAP on back faces for non-zero), then draw again where the stencil is not zero, each
// fragment zeroing it, so that the first triangle to reach a pixel draws it and no other.
template <class Submit>
void draw_fill_rule(const refraster::Target& t, const refraster::Draw& d, Submit&& submit) {
    const auto& s = d.state;
    // Every pixel starts at zero (a fill draw leaves it so, but a draw must not depend on
    // that): the whole buffer, as a clear ignores nothing but the scissor.
    glDisable(GL_SCISSOR_TEST);
    glStencilMask(0xff);
    glClearStencil(0);
    glClear(GL_STENCIL_BUFFER_BIT);
    set_enabled(GL_SCISSOR_TEST, s.scissor.has_value());

    glEnable(GL_STENCIL_TEST);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glStencilFunc(GL_ALWAYS, 0, 0xff);
    if (*s.fill_rule == refraster::FillRule::EvenOdd) {
        glStencilOp(GL_KEEP, GL_KEEP, GL_INVERT);
    } else {
        glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_KEEP, GL_INCR_WRAP);
        glStencilOpSeparate(GL_BACK, GL_KEEP, GL_KEEP, GL_DECR_WRAP);
    }
    submit();
    check_gl("counting a fill rule's coverage");

    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (t.depth != DepthFormat::None) {
        set_enabled(GL_DEPTH_TEST, s.depth_test.has_value());
        glDepthMask(s.depth_write ? GL_TRUE : GL_FALSE);
    }
    glStencilFunc(GL_NOTEQUAL, 0, 0xff);
    glStencilOp(GL_KEEP, GL_ZERO, GL_ZERO);
    submit();
    glDisable(GL_STENCIL_TEST);
}

}  // namespace

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

    // GL_MULTISAMPLE has no effect on a single-sample target; it stays off there, as it
    // always was.
    set_enabled(GL_MULTISAMPLE, t.samples == 4 && s.multisample);
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

    const std::optional<refraster::TextureEnv> env =
        s.texture ? std::optional(s.texture->env) : std::nullopt;
    if (s.texture) bind_texture(*s.texture);
    const bool point_sprite = d.samples_point_coords();
    glPointParameteri(
        GL_POINT_SPRITE_COORD_ORIGIN,
        s.texture && s.texture->point_coord_origin == refraster::PointCoordOrigin::LowerLeft
            ? GL_LOWER_LEFT
            : GL_UPPER_LEFT);
    const GLuint prog = program(s.shade, env, point_sprite);
    glUseProgram(prog);
    if (owners) {
        glUniform1ui(glGetUniformLocation(prog, "draw_index"), current_draw);
        // A polygon is one primitive, number 0. llvmpipe's gl_PrimitiveID is not defined for
        // GL_POLYGON's triangles (measured: values such as 50 and 64 that change from render to
        // render), so the shader writes 0 itself; it still reads gl_PrimitiveID, so that the
        // pass rasterizes as the owner pass of any other draw.
        glUniform1ui(glGetUniformLocation(prog, "one_primitive"),
                     d.primitive == refraster::PrimitiveType::Polygon ? 1u : 0u);
    }

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
    std::optional<std::size_t> texcoord;
    for (std::size_t a = 0; a < va.attributes.size(); ++a) {
        if (va.attributes[a].name == "color") color = a;
        if (va.attributes[a].name == "texcoord") texcoord = a;
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
    if (s.texture && texcoord && !point_sprite) {
        const std::uint32_t components = va.attributes[*texcoord].components;
        if (components < 1 || components > 4) {
            throw GlFailure("texcoord attribute with " + std::to_string(components) +
                            " components");
        }
        const std::uintptr_t offset_bytes = va.attribute_offset(*texcoord) * sizeof(float);
        glEnableVertexAttribArray(kTexcoordLocation);
        glVertexAttribPointer(kTexcoordLocation, static_cast<GLint>(components), GL_FLOAT, GL_FALSE,
                              stride_bytes, reinterpret_cast<const void*>(offset_bytes));
    } else {
        // Untextured programs have no texcoord input; the array must not stay enabled with an
        // earlier draw's layout all the same. A textured draw without coordinates samples at
        // GL's current-attribute default.
        glDisableVertexAttribArray(kTexcoordLocation);
        glVertexAttrib4f(kTexcoordLocation, 0.0f, 0.0f, 0.0f, 1.0f);
    }
    check_gl("uploading vertices");

    const GLenum mode = primitive_mode(d.primitive);
    if (d.indices) {
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                     static_cast<GLsizeiptr>(d.indices->size() * sizeof(std::uint32_t)),
                     d.indices->data(), GL_STREAM_DRAW);
    }
    const auto submit = [&] {
        if (d.indices) {
            glDrawElements(mode, static_cast<GLsizei>(count), GL_UNSIGNED_INT, nullptr);
        } else {
            glDrawArrays(mode, 0, static_cast<GLsizei>(count));
        }
    };
    if (s.fill_rule) {
        draw_fill_rule(t, d, submit);
    } else {
        submit();
    }
    check_gl("drawing");
}

namespace {

// After a texture allocation: any error, GL_OUT_OF_MEMORY included, is a GlFailure naming
// the texture and level.
void check_texture(const char* step, std::size_t texture, std::size_t level) {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        throw GlFailure(std::string("GL error ") + hex(e) + " (" + gl_error_name(e) + ") " + step +
                        " texture " + std::to_string(texture) + " level " + std::to_string(level));
    }
}

}  // namespace

// Every texture of the list on texture unit 0, RGBA8 from the given rows (bottom to top, as
// glTexImage2D takes them): each given level, GL_TEXTURE_MAX_LEVEL the last of them; or, with
// generate_mipmaps, the base and glGenerateMipmap, GL_TEXTURE_MAX_LEVEL left at 1000. Sampling
// state is set per draw (bind_texture).
void Renderer::Impl::upload_textures(const refraster::DrawList& list) {
    release_textures();
    if (list.textures.empty()) return;
    for (std::size_t i = 0; i < list.draws.size(); ++i) {
        const auto& ts = list.draws[i].state.texture;
        if (ts && ts->texture >= list.textures.size()) {
            throw GlFailure("draw " + std::to_string(i) + " names texture " +
                            std::to_string(ts->texture) + " of " +
                            std::to_string(list.textures.size()));
        }
    }
    glActiveTexture(GL_TEXTURE0);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_IMAGE_HEIGHT, 0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    glPixelStorei(GL_UNPACK_SKIP_IMAGES, 0);
    glPixelStorei(GL_UNPACK_SWAP_BYTES, GL_FALSE);
    glPixelStorei(GL_UNPACK_LSB_FIRST, GL_FALSE);
    check_gl("setting the unpack state");

    textures.assign(list.textures.size(), 0);
    glGenTextures(static_cast<GLsizei>(textures.size()), textures.data());
    check_gl("creating textures");
    for (std::size_t i = 0; i < list.textures.size(); ++i) {
        const auto& tex = list.textures[i];
        if (tex.levels.empty()) throw GlFailure("texture " + std::to_string(i) + " has no levels");
        const std::size_t given = tex.generate_mipmaps ? 1 : tex.levels.size();
        if (given > 1000) {
            throw GlFailure("texture " + std::to_string(i) + " has " + std::to_string(given) +
                            " levels");
        }
        glBindTexture(GL_TEXTURE_2D, textures[i]);
        for (std::size_t level = 0; level < given; ++level) {
            const auto& img = tex.levels[level];
            if (img.width > static_cast<std::uint32_t>(max_texture_size) ||
                img.height > static_cast<std::uint32_t>(max_texture_size)) {
                throw Unsupported("texture " + std::to_string(i) + " level " +
                                  std::to_string(level) + " of " + std::to_string(img.width) + "x" +
                                  std::to_string(img.height) + " (GL_MAX_TEXTURE_SIZE " +
                                  std::to_string(max_texture_size) + ")");
            }
            if (img.rgba.size() != std::size_t{img.width} * img.height * 4) {
                throw GlFailure("texture " + std::to_string(i) + " level " + std::to_string(level) +
                                ": " + std::to_string(img.rgba.size()) + " bytes for " +
                                std::to_string(img.width) + "x" + std::to_string(img.height) +
                                " texels");
            }
            glTexImage2D(GL_TEXTURE_2D, static_cast<GLint>(level), GL_RGBA8,
                         static_cast<GLsizei>(img.width), static_cast<GLsizei>(img.height), 0,
                         GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.empty() ? nullptr : img.rgba.data());
            check_texture("uploading", i, level);
        }
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
        if (tex.generate_mipmaps) {
            glGenerateMipmap(GL_TEXTURE_2D);
            check_texture("generating the mipmaps of", i, 0);
        } else {
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, static_cast<GLint>(given - 1));
        }
        check_gl("setting texture levels");
    }
    glBindTexture(GL_TEXTURE_2D, 0);
}

// The draw's texture on unit 0 with its sampling state. LOD bias, the LOD range and
// anisotropy stay at GL's defaults.
void Renderer::Impl::bind_texture(const refraster::TextureState& ts) {
    if (ts.texture >= textures.size()) {
        throw GlFailure("a draw names texture " + std::to_string(ts.texture) + " of " +
                        std::to_string(textures.size()));
    }
    if (refraster::uses_mipmaps(ts.mag_filter)) {
        throw GlFailure("magnification filter other than nearest or linear");
    }
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, textures[ts.texture]);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, texture_filter(ts.min_filter));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, texture_filter(ts.mag_filter));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, texture_wrap(ts.wrap_s));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, texture_wrap(ts.wrap_t));
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, ts.border_color.data());
    check_gl("setting texture state");
}

// The owner attachment at colour attachment 1 of the framebuffer drawn into, cleared to 0,
// written by the owner programs alongside the colour: an R32UI renderbuffer (1x) or an R32UI
// multisample texture (4x, fetched per sample).
void Renderer::Impl::attach_owners(const refraster::Target& t) {
    const auto w = static_cast<GLsizei>(t.width);
    const auto h = static_cast<GLsizei>(t.height);
    if (t.samples == 4) {
        glGenTextures(1, &owner_tex);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, owner_tex);
        glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, 4, GL_R32UI, w, h, GL_TRUE);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
        check_allocation("creating the owner samples");
        glBindFramebuffer(GL_FRAMEBUFFER, target.ms_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D_MULTISAMPLE,
                               owner_tex, 0);
    } else {
        glGenRenderbuffers(1, &owner_rb);
        glBindRenderbuffer(GL_RENDERBUFFER, owner_rb);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_R32UI, w, h);
        glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, owner_rb);
    }
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
    const GLenum buf = GL_COLOR_ATTACHMENT0;
    if (owner_rb != 0) {
        glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, 0);
        glDrawBuffers(1, &buf);
        glDeleteRenderbuffers(1, &owner_rb);
        owner_rb = 0;
    }
    if (owner_tex != 0) {
        if (target.ms_fbo != 0) {
            glBindFramebuffer(GL_FRAMEBUFFER, target.ms_fbo);
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D_MULTISAMPLE,
                                   0, 0);
            glDrawBuffers(1, &buf);
        }
        glDeleteTextures(1, &owner_tex);
        owner_tex = 0;
    }
}

void Renderer::Impl::read_back(const refraster::Target& t, harness::RenderResult& r) {
    if (t.samples == 1) {
        r.image = read_single(t);
        return;
    }
    const auto w = static_cast<GLsizei>(t.width);
    const auto h = static_cast<GLsizei>(t.height);
    // The resolve is the blit's, colour only. Blits obey the scissor test.
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.ms_fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.fbo);
    glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    check_gl("multisample resolve");

    refraster::Framebuffer image(t.width, t.height, t.color, t.depth);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    if (t.color == ColorFormat::Rgba8) {
        glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, image.color8.data());
    } else {
        glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, image.color32f.data());
    }
    check_gl("reading the resolved colour");

    if (!sample_reader) sample_reader.emplace();
    SampleSources src;
    src.width = t.width;
    src.height = t.height;
    src.samples = 4;
    src.color_format = t.color;
    src.color_texture = target.ms_color_tex;
    // A depth-less target's depth attachment is never written: not read either.
    src.depth_format = t.depth;
    src.depth_texture = t.depth != DepthFormat::None ? target.ms_depth_tex : 0;
    src.owner_texture = owners ? owner_tex : 0;
    r.samples = sample_reader->read(src);

    // The image's depth and owners are sample 0's.
    const std::size_t n = image.pixel_count();
    for (std::size_t i = 0; i < image.depth.size(); ++i) image.depth[i] = r.samples.depth[i * 4];
    if (owners) {
        image.owner.resize(n);
        for (std::size_t i = 0; i < n; ++i) image.owner[i] = r.samples.owner[i * 4];
    }
    r.image = std::move(image);
}

refraster::Framebuffer Renderer::Impl::read_single(const refraster::Target& t) {
    const auto w = static_cast<GLsizei>(t.width);
    const auto h = static_cast<GLsizei>(t.height);
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
    p["gl_vendor"] = gl_string(GL_VENDOR);
    p["gl_version"] = gl_string(GL_VERSION);
    p["glsl_version"] = gl_string(GL_SHADING_LANGUAGE_VERSION);
    p["env"] = mesa_environment();
    p["mesa_version"] = debian_package_version(mesa_package);
    p["libraries"] = loaded_gl_libraries();
    // The driver that really runs, whatever the environment asked for: the harness refuses a
    // worker whose driver is not the one --driver names.
    p["driver"] = driver_env::loaded_driver(p["renderer"], p["libraries"]);
    if (auto vk = driver_env::vulkan_driver(p["renderer"]); !vk.empty()) {
        p["vulkan_driver"] = std::move(vk);
    }
    // A Mesa build of one's own (--mesa-prefix): its version is the one GL reports, not the
    // system package's.
    if (const char* prefix = std::getenv("REFRASTER_MESA_PREFIX"); prefix && *prefix) {
        p["mesa_prefix"] = prefix;
        p["mesa_version"] = mesa_version_of(p["gl_version"]);
    }

    impl_->max_samples = gl_int(GL_MAX_SAMPLES);
    impl_->max_texture_samples =
        std::min({gl_int(GL_MAX_COLOR_TEXTURE_SAMPLES), gl_int(GL_MAX_DEPTH_TEXTURE_SAMPLES),
                  gl_int(GL_MAX_INTEGER_SAMPLES)});
    impl_->max_texture_size = gl_int(GL_MAX_TEXTURE_SIZE);
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
    impl_->detach_owners();
    impl_->target.release();
    impl_->sample_reader.reset();
    impl_->release_textures();
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

void Renderer::add_provenance(const std::string& key, const std::string& value) {
    impl_->provenance[key] = value;
}

// Targets of this many samples or more are released after their scene (16,777,216: a
// 4096 x 4096 single-sample target, 256 MiB of rgba32f).
constexpr std::uint64_t kKeepTargetSamples = std::uint64_t{1} << 24;

harness::RenderResult Renderer::render(const refraster::DrawList& list, bool owners) {
    const auto start = std::chrono::steady_clock::now();
    harness::RenderResult r;
    r.provenance = impl_->provenance;
    try {
        drain_gl_errors();
        impl_->prepare_target(list.target, needs_stencil(list));
        impl_->set_fixed_state();
        impl_->clear(list);
        impl_->owners = owners;
        if (owners) impl_->attach_owners(list.target);
        impl_->upload_textures(list);
        for (std::size_t i = 0; i < list.draws.size(); ++i) {
            impl_->current_draw = static_cast<GLuint>(i);
            impl_->draw(list.target, list.draws[i]);
        }
        impl_->read_back(list.target, r);
        impl_->release_textures();
        impl_->detach_owners();
        impl_->owners = false;
        // A large target is not kept for the next scene: its GL storage (and the sample
        // read-back targets of its size) would stay beside the images being encoded, over a
        // gigabyte more at the target limit (docs/limits.md, "Memory at the target limit").
        const auto& t = list.target;
        if (std::uint64_t{t.width} * t.height * t.samples >= kKeepTargetSamples) {
            impl_->target.release();
            impl_->sample_reader.reset();
        }
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
        impl_->release_textures();
        impl_->detach_owners();
        impl_->owners = false;
        r.image = refraster::Framebuffer{};
        r.samples = refraster::Framebuffer{};
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
    // And for order dependence: answer the Nth scene with its first pixel's first channel
    // changed, as a driver whose state an earlier scene left stale would draw it.
    unsigned long stale_at = 0;
    if (const char* k = std::getenv("REFRASTER_WORKER_STALE_AT"))
        stale_at = std::strtoul(k, nullptr, 10);
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
        for (const auto& [k, v] : context->provenance()) renderer->add_provenance(k, v);
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
                    if (scenes == stale_at && reply.status == harness::RenderStatus::Ok) {
                        auto& img = reply.image;
                        if (!img.color8.empty()) img.color8[0] ^= 0xFF;
                        if (!img.color32f.empty()) img.color32f[0] = 0.5f - img.color32f[0];
                    }
                    // The images are given up as they are encoded.
                    wire::write_frame(out, wire::FrameType::Reply,
                                      wire::encode_result(std::move(reply)));
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
