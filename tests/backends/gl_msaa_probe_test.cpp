// gl_msaa_probe_test.cpp: measures, in an OSMesa llvmpipe context of this process, the facts
// the 4x read-back rests on (harness/workers/gl_render.hpp, SampleReader):
// - every z16 and z24 value (all 2^16 and 2^24), uploaded into a single-sample depth texture,
//   comes back through the fetch shaders and depth_from_fetch, and the fetched float is
//   exactly fl(z * fl(1 / (2^n - 1)));
// - z32f depths, every positive denormal among them, keep their bits;
// - every rgba8 byte and rgba32f bit pattern (negatives, infinities, NaNs, denormals) keeps
//   its value;
// - depth written per sample (glSampleMaski, gl_FragDepth) reads back as the same values
//   written to a single-sample target read with glReadPixels;
// - colour written per sample reads back exactly, and glBlitFramebuffer's resolve equals
//   refraster::resolve_samples of those samples byte for byte (rgba8) and bit for bit
//   (rgba32f).
// The workers' GL code (gl_render.cpp) is compiled in; OSMesa is the only GL library in the
// process.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "gl_render.hpp"
#include "osmesa_llvmpipe_fixture.hpp"
#include "refraster/framebuffer.hpp"

namespace {

using refraster::ColorFormat;
using refraster::DepthFormat;

std::uint32_t u32(std::mt19937& rng) {
    return static_cast<std::uint32_t>(rng());
}

std::string hex32(std::uint32_t v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%08x", v);
    return buf;
}

GLuint compile(GLenum type, const std::string& source) {
    const GLuint sh = glCreateShader(type);
    const char* text = source.c_str();
    glShaderSource(sh, 1, &text, nullptr);
    glCompileShader(sh);
    GLint ok = GL_FALSE;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        std::array<char, 2048> log{};
        glGetShaderInfoLog(sh, static_cast<GLsizei>(log.size()), nullptr, log.data());
        ADD_FAILURE() << "shader: " << log.data();
    }
    return sh;
}

// A full-screen triangle whose fragments write the values of `values` (a usampler2D on
// unit 3) at their pixel: as colour bits (uintBitsToFloat) or as gl_FragDepth.
GLuint writer_program(bool depth) {
    const std::string vs =
        "#version 330\n"
        "void main() {\n"
        "    vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID & 2) * 2 - 1));\n"
        "    gl_Position = vec4(p, 0.0, 1.0);\n"
        "}\n";
    const std::string fs =
        std::string("#version 330\nuniform usampler2D values;\n") +
        (depth ? "out vec4 color;\n" : "layout(location = 0) out vec4 color;\n") +
        "void main() {\n"
        "    uvec4 v = texelFetch(values, ivec2(gl_FragCoord.xy), 0);\n" +
        (depth ? "    color = vec4(0.0);\n    gl_FragDepth = uintBitsToFloat(v.r);\n"
               : "    color = uintBitsToFloat(v);\n") +
        "}\n";
    const GLuint p = glCreateProgram();
    const GLuint v = compile(GL_VERTEX_SHADER, vs);
    const GLuint f = compile(GL_FRAGMENT_SHADER, fs);
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok = GL_FALSE;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    EXPECT_EQ(ok, GL_TRUE) << "writer program link";
    glUseProgram(p);
    glUniform1i(glGetUniformLocation(p, "values"), 3);
    return p;
}

// An RGBA32UI texture on unit 3 holding `words` (4 a pixel), for the writer program.
GLuint value_texture(std::uint32_t w, std::uint32_t h, const std::vector<std::uint32_t>& words) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32UI, static_cast<GLsizei>(w), static_cast<GLsizei>(h), 0,
                 GL_RGBA_INTEGER, GL_UNSIGNED_INT, words.data());
    glActiveTexture(GL_TEXTURE0);
    return t;
}

// Draws the writer program over the bound framebuffer, into sample `s` only when s >= 0.
void write_values(GLuint program, GLuint values, std::uint32_t w, std::uint32_t h, int s,
                  bool depth) {
    glUseProgram(program);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_2D, values);
    glActiveTexture(GL_TEXTURE0);
    glViewport(0, 0, static_cast<GLsizei>(w), static_cast<GLsizei>(h));
    constexpr std::array<GLenum, 5> kOff = {GL_SCISSOR_TEST, GL_BLEND, GL_CULL_FACE, GL_DITHER,
                                            GL_STENCIL_TEST};
    for (GLenum cap : kOff) glDisable(cap);
    glClampColor(GL_CLAMP_FRAGMENT_COLOR, GL_FALSE);
    // Depth is written only with the test on.
    if (depth) {
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_ALWAYS);
        glDepthMask(GL_TRUE);
    } else {
        glDisable(GL_DEPTH_TEST);
    }
    if (s >= 0) {
        glEnable(GL_MULTISAMPLE);
        glEnable(GL_SAMPLE_MASK);
        glSampleMaski(0, 1u << s);
    } else {
        glDisable(GL_SAMPLE_MASK);
    }
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisable(GL_SAMPLE_MASK);
    glSampleMaski(0, ~0u);
}

GLenum depth_format_enum(DepthFormat f) {
    switch (f) {
        case DepthFormat::Z16:
            return GL_DEPTH_COMPONENT16;
        case DepthFormat::Z32f:
            return GL_DEPTH_COMPONENT32F;
        default:
            return GL_DEPTH_COMPONENT24;
    }
}

// The stored depth of the bound read framebuffer as the 1x backend reads it.
std::vector<std::uint32_t> read_depth_pixels(DepthFormat f, std::uint32_t w, std::uint32_t h) {
    const std::size_t n = std::size_t{w} * h;
    std::vector<std::uint32_t> out(n);
    const auto gw = static_cast<GLsizei>(w);
    const auto gh = static_cast<GLsizei>(h);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (f == DepthFormat::Z16) {
        std::vector<std::uint16_t> z(n);
        glReadPixels(0, 0, gw, gh, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT, z.data());
        std::copy(z.begin(), z.end(), out.begin());
    } else if (f == DepthFormat::Z24) {
        glReadPixels(0, 0, gw, gh, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, out.data());
        for (auto& v : out) v >>= 8;
    } else {
        std::vector<float> z(n);
        glReadPixels(0, 0, gw, gh, GL_DEPTH_COMPONENT, GL_FLOAT, z.data());
        for (std::size_t i = 0; i < n; ++i) out[i] = std::bit_cast<std::uint32_t>(z[i]);
    }
    return out;
}

class MsaaProbe : public OsmesaLlvmpipeTest {
  protected:
    static void SetUpTestSuite() {
        OsmesaLlvmpipeTest::SetUpTestSuite();
        reader_ = new harness::gl::SampleReader();
    }
    static void TearDownTestSuite() {
        delete reader_;
        reader_ = nullptr;
        OsmesaLlvmpipeTest::TearDownTestSuite();
    }

    static harness::gl::SampleReader& reader() { return *reader_; }

    // A single-sample depth texture of format `f`, filled from `data` of GL type `type`,
    // whose stored values (read back through an FBO) must equal `want`.
    static GLuint depth_texture(DepthFormat f, std::uint32_t w, std::uint32_t h, GLenum type,
                                const void* data, const std::vector<std::uint32_t>& want) {
        GLuint t = 0;
        glGenTextures(1, &t);
        glBindTexture(GL_TEXTURE_2D, t);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(depth_format_enum(f)),
                     static_cast<GLsizei>(w), static_cast<GLsizei>(h), 0, GL_DEPTH_COMPONENT, type,
                     data);
        glBindTexture(GL_TEXTURE_2D, 0);
        GLuint fbo = 0;
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, t, 0);
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
        EXPECT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER),
                  static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE));
        const auto stored = read_depth_pixels(f, w, h);
        std::size_t bad = 0;
        for (std::size_t i = 0; i < want.size(); ++i) bad += stored[i] != want[i] ? 1u : 0u;
        EXPECT_EQ(bad, 0u) << "values not stored as uploaded";
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glDeleteFramebuffers(1, &fbo);
        return t;
    }

    static inline harness::gl::SampleReader* reader_ = nullptr;
};

// Every z16 or z24 value through the fetch path: the fetched float is fl(z * K) for every z,
// the only two values it cannot tell apart are z24's 2^24 - 2 and 2^24 - 1 (both 1.0), and
// the reader (which marks those two apart with a depth test) gives every z back.
void check_every_unorm_depth(harness::gl::SampleReader& reader, DepthFormat f, std::uint32_t w,
                             std::uint32_t h, GLuint texture) {
    harness::gl::SampleSources src;
    src.width = w;
    src.height = h;
    src.samples = 1;
    src.depth_format = f;
    src.depth_texture = texture;
    src.raw_depth = true;
    const auto raw = reader.read(src);
    const std::uint32_t bits = refraster::depth_bits(f);
    const std::uint32_t count = 1u << bits;
    const auto scale = static_cast<float>(1.0 / static_cast<double>(count - 1));
    std::size_t not_product = 0;
    std::size_t not_recovered = 0;
    std::size_t not_rounded = 0;            // how often round(d * (2^n - 1)) would have been wrong
    std::vector<std::uint32_t> collisions;  // z whose fetch equals that of z + 1
    for (std::uint32_t z = 0; z < count; ++z) {
        const std::uint32_t d = raw.depth[z];
        const float product = static_cast<float>(z) * scale;
        if (std::bit_cast<std::uint32_t>(product) != d && not_product++ < 5) {
            ADD_FAILURE() << "z " << z << " fetched as " << hex32(d) << ", fl(z*K) is "
                          << hex32(std::bit_cast<std::uint32_t>(product));
        }
        if (z + 1 < count && raw.depth[z + 1] == d) collisions.push_back(z);
        const auto back = harness::gl::depth_from_fetch(f, d);
        const bool ambiguous = bits == 24 && z == count - 2;
        if ((!back || *back != z) && !ambiguous && not_recovered++ < 5) {
            ADD_FAILURE() << "z " << z << " fetched as " << hex32(d) << " recovered as "
                          << (back ? std::to_string(*back) : "nothing");
        }
        const double scaled = static_cast<double>(std::bit_cast<float>(d)) * (count - 1);
        not_rounded += std::llround(scaled) != z ? 1u : 0u;
    }
    EXPECT_EQ(not_product, 0u);
    EXPECT_EQ(not_recovered, 0u);
    EXPECT_EQ(collisions,
              bits == 24 ? std::vector<std::uint32_t>{count - 2} : std::vector<std::uint32_t>{});

    src.raw_depth = false;
    const auto got = reader.read(src);
    std::size_t wrong = 0;
    for (std::uint32_t z = 0; z < count; ++z) {
        if (got.depth[z] != z && wrong++ < 5) {
            ADD_FAILURE() << "z " << z << " read back as " << got.depth[z];
        }
    }
    EXPECT_EQ(wrong, 0u);
    std::printf(
        "%s: %u values checked, every fetch == fl(z*K), %zu colliding pair(s), all read "
        "back; round(d*(2^n-1)) would be wrong for %zu\n",
        std::string(refraster::to_string(f)).c_str(), count, collisions.size(), not_rounded);
}

TEST_F(MsaaProbe, EveryZ24ValueRoundTripsThroughTheFetch) {
    constexpr std::uint32_t kW = 4096;
    constexpr std::uint32_t kH = 4096;
    std::vector<std::uint32_t> upload(std::size_t{kW} * kH);
    std::vector<std::uint32_t> want(upload.size());
    // Mesa scales a GL_UNSIGNED_INT depth to 24 bits (z * (2^24-1) / (2^32-1)): z << 8 alone
    // would store z - 1. Half a step above lands on z whichever way it rounds.
    for (std::uint32_t z = 0; z < upload.size(); ++z) {
        upload[z] = (z << 8) | 0x80u;
        want[z] = z;
    }
    const GLuint t = depth_texture(DepthFormat::Z24, kW, kH, GL_UNSIGNED_INT, upload.data(), want);
    check_every_unorm_depth(reader(), DepthFormat::Z24, kW, kH, t);
    glDeleteTextures(1, &t);
}

TEST_F(MsaaProbe, EveryZ16ValueRoundTripsThroughTheFetch) {
    constexpr std::uint32_t kW = 256;
    constexpr std::uint32_t kH = 256;
    std::vector<std::uint16_t> upload(std::size_t{kW} * kH);
    std::vector<std::uint32_t> want(upload.size());
    for (std::uint32_t z = 0; z < upload.size(); ++z) {
        upload[z] = static_cast<std::uint16_t>(z);
        want[z] = z;
    }
    const GLuint t =
        depth_texture(DepthFormat::Z16, kW, kH, GL_UNSIGNED_SHORT, upload.data(), want);
    check_every_unorm_depth(reader(), DepthFormat::Z16, kW, kH, t);
    glDeleteTextures(1, &t);
}

// Every positive denormal, zero, one, the smallest normal, and random floats in [0, 1].
TEST_F(MsaaProbe, Z32fDepthKeepsItsBitsDenormalsIncluded) {
    constexpr std::uint32_t kW = 4096;
    constexpr std::uint32_t kH = 4096;
    std::vector<float> upload(std::size_t{kW} * kH);
    std::vector<std::uint32_t> want(upload.size());
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::uint32_t> in_unit(0, 0x3f800000u);
    for (std::size_t i = 0; i < upload.size(); ++i) {
        std::uint32_t b = 0;
        if (i < (1u << 23)) {
            b = static_cast<std::uint32_t>(i);  // 0 and every denormal
        } else if (i == (1u << 23)) {
            b = 0x3f800000u;  // 1.0
        } else {
            b = in_unit(rng);
        }
        upload[i] = std::bit_cast<float>(b);
        want[i] = b;
    }
    const GLuint t = depth_texture(DepthFormat::Z32f, kW, kH, GL_FLOAT, upload.data(), want);
    harness::gl::SampleSources src;
    src.width = kW;
    src.height = kH;
    src.samples = 1;
    src.depth_format = DepthFormat::Z32f;
    src.depth_texture = t;
    const auto got = reader().read(src);
    std::size_t bad = 0;
    std::size_t bad_denormals = 0;
    for (std::size_t i = 0; i < want.size(); ++i) {
        if (got.depth[i] != want[i]) {
            ++bad;
            bad_denormals += i < (1u << 23) ? 1 : 0;
            if (bad <= 5) {
                ADD_FAILURE() << "z32f " << hex32(want[i]) << " fetched as " << hex32(got.depth[i]);
            }
        }
    }
    EXPECT_EQ(bad, 0u) << bad_denormals << " of them denormal";
    std::printf("z32f: %zu values checked (%u denormal), %zu changed\n", want.size(),
                (1u << 23) - 1, bad);
    glDeleteTextures(1, &t);
}

TEST_F(MsaaProbe, EveryColourValueKeepsItsBits) {
    {
        // rgba8: every byte in every channel.
        constexpr std::uint32_t kW = 256;
        constexpr std::uint32_t kH = 256;
        std::vector<std::uint8_t> bytes(std::size_t{kW} * kH * 4);
        for (std::uint32_t y = 0; y < kH; ++y) {
            for (std::uint32_t x = 0; x < kW; ++x) {
                const std::size_t i = (std::size_t{y} * kW + x) * 4;
                bytes[i] = static_cast<std::uint8_t>(x);
                bytes[i + 1] = static_cast<std::uint8_t>(y);
                bytes[i + 2] = static_cast<std::uint8_t>(x ^ y);
                bytes[i + 3] = static_cast<std::uint8_t>(x + 3 * y);
            }
        }
        GLuint t = 0;
        glGenTextures(1, &t);
        glBindTexture(GL_TEXTURE_2D, t);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, kW, kH, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                     bytes.data());
        harness::gl::SampleSources src;
        src.width = kW;
        src.height = kH;
        src.samples = 1;
        src.color_texture = t;
        EXPECT_TRUE(std::ranges::equal(reader().read(src).color8, bytes));
        glDeleteTextures(1, &t);
    }
    {
        // rgba32f: specials, every kind of denormal, random bit patterns (NaNs included).
        constexpr std::uint32_t kW = 1024;
        constexpr std::uint32_t kH = 1024;
        std::vector<std::uint32_t> words(std::size_t{kW} * kH * 4);
        std::mt19937 rng(11);
        const std::uint32_t specials[] = {0x00000000u, 0x80000000u, 0x00000001u, 0x807fffffu,
                                          0x00400000u, 0x7f800000u, 0xff800000u, 0x7fc00000u,
                                          0xffc00001u, 0x7f800001u, 0x7f7fffffu, 0x00800000u};
        for (std::size_t i = 0; i < words.size(); ++i) {
            if (i < std::size(specials)) {
                words[i] = specials[i];
            } else if (i % 3 == 0) {
                words[i] = u32(rng) & 0x807fffffu;  // a denormal of either sign
            } else {
                words[i] = u32(rng);
            }
        }
        GLuint t = 0;
        glGenTextures(1, &t);
        glBindTexture(GL_TEXTURE_2D, t);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, kW, kH, 0, GL_RGBA, GL_FLOAT, words.data());
        harness::gl::SampleSources src;
        src.width = kW;
        src.height = kH;
        src.samples = 1;
        src.color_format = ColorFormat::Rgba32f;
        src.color_texture = t;
        const auto got = reader().read(src);
        std::size_t bad = 0;
        for (std::size_t i = 0; i < words.size(); ++i) {
            const auto b = std::bit_cast<std::uint32_t>(got.color32f[i]);
            if (b != words[i] && bad++ < 5) {
                ADD_FAILURE() << "rgba32f " << hex32(words[i]) << " fetched as " << hex32(b);
            }
        }
        EXPECT_EQ(bad, 0u);
        std::printf("rgba32f fetch: %zu floats checked, %zu changed\n", words.size(), bad);
        glDeleteTextures(1, &t);
    }
}

// A 4x framebuffer with colour and depth multisample textures.
struct MsTarget {
    GLuint fbo = 0;
    GLuint color = 0;
    GLuint depth = 0;
    MsTarget(std::uint32_t w, std::uint32_t h, GLenum color_format, GLenum depth_format) {
        glGenFramebuffers(1, &fbo);
        glGenTextures(1, &color);
        glGenTextures(1, &depth);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, color);
        glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, 4, color_format, static_cast<GLsizei>(w),
                                static_cast<GLsizei>(h), GL_TRUE);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D_MULTISAMPLE,
                               color, 0);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, depth);
        glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, 4, depth_format, static_cast<GLsizei>(w),
                                static_cast<GLsizei>(h), GL_TRUE);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D_MULTISAMPLE,
                               depth, 0);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
        EXPECT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER),
                  static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE));
        GLint samples = 0;
        glGetIntegerv(GL_SAMPLES, &samples);
        EXPECT_EQ(samples, 4);
    }
    ~MsTarget() {
        glDeleteFramebuffers(1, &fbo);
        glDeleteTextures(1, &color);
        glDeleteTextures(1, &depth);
    }
};

// Depth values for the per-sample tests: random in [0, 1], the exact steps k / (2^n - 1) near
// 0 and 1, and 0, 1 themselves.
std::vector<std::uint32_t> depth_values(std::size_t n, std::uint32_t seed, DepthFormat f) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::uint32_t> in_unit(0, 0x3f800000u);
    const std::uint32_t bits = refraster::depth_bits(f);
    const double steps = bits == 32 ? 16777215.0 : static_cast<double>((1u << bits) - 1);
    std::vector<std::uint32_t> v(n * 4, 0);
    for (std::size_t i = 0; i < n; ++i) {
        float d = std::bit_cast<float>(in_unit(rng));
        switch (i % 4) {
            case 0:
                break;
            case 1:
                d = static_cast<float>(static_cast<double>(u32(rng) % 4096) / steps);
                break;
            case 2:
                d = static_cast<float>(1.0 - static_cast<double>(u32(rng) % 4096) / steps);
                break;
            default:
                d = static_cast<float>(u32(rng) % 2);
                break;
        }
        v[i * 4] = std::bit_cast<std::uint32_t>(d);
    }
    return v;
}

TEST_F(MsaaProbe, DepthWrittenPerSampleReadsBackAsAtOneSample) {
    constexpr std::uint32_t kW = 64;
    constexpr std::uint32_t kH = 64;
    constexpr std::size_t kN = std::size_t{kW} * kH;
    const GLuint program = writer_program(true);
    std::size_t checked = 0;
    for (const auto f : {DepthFormat::Z16, DepthFormat::Z24, DepthFormat::Z32f}) {
        MsTarget ms(kW, kH, GL_RGBA8, depth_format_enum(f));
        // The single-sample reference: the same values written to a 1x target.
        GLuint ss_fbo = 0;
        GLuint ss_rb[2] = {0, 0};
        glGenFramebuffers(1, &ss_fbo);
        glGenRenderbuffers(2, ss_rb);
        glBindFramebuffer(GL_FRAMEBUFFER, ss_fbo);
        glBindRenderbuffer(GL_RENDERBUFFER, ss_rb[0]);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, kW, kH);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, ss_rb[0]);
        glBindRenderbuffer(GL_RENDERBUFFER, ss_rb[1]);
        glRenderbufferStorage(GL_RENDERBUFFER, depth_format_enum(f), kW, kH);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, ss_rb[1]);

        std::array<std::vector<std::uint32_t>, 4> want;
        for (std::uint32_t s = 0; s < 4; ++s) {
            const auto values = depth_values(kN, 100 + s, f);
            const GLuint vt = value_texture(kW, kH, values);
            glBindFramebuffer(GL_FRAMEBUFFER, ss_fbo);
            write_values(program, vt, kW, kH, -1, true);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, ss_fbo);
            want[s] = read_depth_pixels(f, kW, kH);
            glBindFramebuffer(GL_FRAMEBUFFER, ms.fbo);
            write_values(program, vt, kW, kH, static_cast<int>(s), true);
            glDeleteTextures(1, &vt);
        }
        glDeleteFramebuffers(1, &ss_fbo);
        glDeleteRenderbuffers(2, ss_rb);

        harness::gl::SampleSources src;
        src.width = kW;
        src.height = kH;
        src.samples = 4;
        src.depth_format = f;
        src.depth_texture = ms.depth;
        const auto got = reader().read(src);
        ASSERT_EQ(got.samples, 4u);
        std::size_t bad = 0;
        for (std::size_t i = 0; i < kN; ++i) {
            for (std::uint32_t s = 0; s < 4; ++s) {
                if (got.depth[i * 4 + s] != want[s][i] && bad++ < 5) {
                    ADD_FAILURE() << to_string(f) << " pixel " << i << " sample " << s << ": got "
                                  << got.depth[i * 4 + s] << ", 1x gives " << want[s][i];
                }
            }
        }
        EXPECT_EQ(bad, 0u) << to_string(f);
        checked += kN * 4;
    }
    glDeleteProgram(program);
    std::printf("per-sample depth: %zu values checked\n", checked);
}

// Random colour values written into each sample under glSampleMaski read back exactly, and the
// blit's resolve of them is refraster::resolve_samples's.
struct ResolveOutcome {
    std::size_t values = 0;
    std::size_t mismatches = 0;        // blit != resolve_samples
    std::size_t negative_zeros = 0;    // of those: every sample (flushed) -0, blit +0
    std::size_t model_mismatches = 0;  // blit != blit_model
};

// A float as llvmpipe's rasterizer threads see it: denormals are zero (DAZ, FTZ).
float flushed(float v) {
    return std::fpclassify(v) == FP_SUBNORMAL ? std::copysign(0.0f, v) : v;
}

// The resolve shader as Mesa 22.3 writes it (u_simple_shaders.c, util_make_fs_msaa_resolve):
// the sum starts as the immediate +0.0 and adds the samples in order, then is scaled by
// 1 / samples; inputs and results flushed.
float blit_model(const std::array<float, 4>& f) {
    float sum = 0.0f;
    for (float v : f) sum = flushed(flushed(sum) + flushed(v));
    return flushed(sum * 0.25f);
}

ResolveOutcome check_resolve(harness::gl::SampleReader& reader, ColorFormat cf,
                             const std::array<std::vector<std::uint32_t>, 4>& values,
                             std::uint32_t w, std::uint32_t h) {
    const std::size_t n = std::size_t{w} * h;
    const bool f32 = cf == ColorFormat::Rgba32f;
    MsTarget ms(w, h, f32 ? GL_RGBA32F : GL_RGBA8, GL_DEPTH_COMPONENT24);
    const GLuint program = writer_program(false);
    for (std::uint32_t s = 0; s < 4; ++s) {
        const GLuint vt = value_texture(w, h, values[s]);
        glBindFramebuffer(GL_FRAMEBUFFER, ms.fbo);
        write_values(program, vt, w, h, static_cast<int>(s), false);
        glDeleteTextures(1, &vt);
    }
    glDeleteProgram(program);

    harness::gl::SampleSources src;
    src.width = w;
    src.height = h;
    src.samples = 4;
    src.color_format = cf;
    src.color_texture = ms.color;
    const auto samples = reader.read(src);
    // What was written is what is read back: bytes for rgba8 (the values are the bytes'
    // fetched floats), bits for rgba32f.
    std::size_t bad_samples = 0;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::uint32_t s = 0; s < 4; ++s) {
            for (std::size_t c = 0; c < 4; ++c) {
                const std::uint32_t written = values[s][i * 4 + c];
                const std::size_t k = (i * 4 + s) * 4 + c;
                const std::uint32_t got =
                    f32 ? std::bit_cast<std::uint32_t>(samples.color32f[k])
                        : std::bit_cast<std::uint32_t>(static_cast<float>(samples.color8[k]) *
                                                       (1.0f / 255.0f));
                if (got != written && bad_samples++ < 5) {
                    ADD_FAILURE() << "sample " << s << " of pixel " << i << " channel " << c
                                  << " written " << hex32(written) << " read " << hex32(got);
                }
            }
        }
    }
    EXPECT_EQ(bad_samples, 0u);

    // The blit into a single-sample renderbuffer, read with glReadPixels.
    GLuint fbo = 0;
    GLuint rb = 0;
    glGenFramebuffers(1, &fbo);
    glGenRenderbuffers(1, &rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    glRenderbufferStorage(GL_RENDERBUFFER, f32 ? GL_RGBA32F : GL_RGBA8, static_cast<GLsizei>(w),
                          static_cast<GLsizei>(h));
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, ms.fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glDisable(GL_SCISSOR_TEST);
    glBlitFramebuffer(0, 0, static_cast<GLint>(w), static_cast<GLint>(h), 0, 0,
                      static_cast<GLint>(w), static_cast<GLint>(h), GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glClampColor(GL_CLAMP_READ_COLOR, GL_FALSE);
    refraster::Framebuffer blit(w, h, cf, DepthFormat::None);
    if (f32) {
        glReadPixels(0, 0, static_cast<GLsizei>(w), static_cast<GLsizei>(h), GL_RGBA, GL_FLOAT,
                     blit.color32f.data());
    } else {
        glReadPixels(0, 0, static_cast<GLsizei>(w), static_cast<GLsizei>(h), GL_RGBA,
                     GL_UNSIGNED_BYTE, blit.color8.data());
    }
    glDeleteFramebuffers(1, &fbo);
    glDeleteRenderbuffers(1, &rb);

    refraster::Framebuffer ms_fb = samples;
    ms_fb.depth_format = DepthFormat::None;
    ms_fb.depth.clear();
    const auto resolved = refraster::resolve_samples(ms_fb);
    ResolveOutcome out;
    out.values = n * 4;
    for (std::size_t i = 0; i < n * 4; ++i) {
        const std::uint32_t got =
            f32 ? std::bit_cast<std::uint32_t>(blit.color32f[i]) : blit.color8[i];
        const std::uint32_t want =
            f32 ? std::bit_cast<std::uint32_t>(resolved.color32f[i]) : resolved.color8[i];
        if (f32) {
            std::array<float, 4> in{};
            bool all_negative_zero = true;
            for (std::uint32_t s = 0; s < 4; ++s) {
                in[s] = samples.color32f[((i / 4) * 4 + s) * 4 + i % 4];
                all_negative_zero &= flushed(in[s]) == 0.0f && std::signbit(in[s]);
            }
            const std::uint32_t model = std::bit_cast<std::uint32_t>(blit_model(in));
            if (model != got && out.model_mismatches++ < 5) {
                ADD_FAILURE() << "pixel " << i / 4 << " channel " << i % 4 << ": blit "
                              << hex32(got) << ", model " << hex32(model);
            }
            if (got != want && all_negative_zero && got == 0u && want == 0x80000000u) {
                ++out.mismatches;
                ++out.negative_zeros;
                continue;
            }
        }
        if (got != want && out.mismatches++ < 8) {
            std::string inputs;
            for (std::uint32_t s = 0; s < 4; ++s) {
                const std::size_t k = ((i / 4) * 4 + s) * 4 + i % 4;
                inputs += " " + (f32 ? hex32(std::bit_cast<std::uint32_t>(samples.color32f[k]))
                                     : std::to_string(samples.color8[k]));
            }
            ADD_FAILURE() << to_string(cf) << " pixel " << i / 4 << " channel " << i % 4
                          << ": samples" << inputs << ", blit " << hex32(got)
                          << ", resolve_samples " << hex32(want);
        }
    }
    return out;
}

TEST_F(MsaaProbe, BlitResolveOfRandomRgba8SamplesIsResolveSamples) {
    constexpr std::uint32_t kW = 128;
    constexpr std::uint32_t kH = 128;
    std::mt19937 rng(21);
    std::array<std::vector<std::uint32_t>, 4> values;
    for (auto& v : values) {
        v.resize(std::size_t{kW} * kH * 4);
        // The float an rgba8 fetch gives for a random byte, which the target stores back.
        for (auto& x : v) {
            x = std::bit_cast<std::uint32_t>(static_cast<float>(u32(rng) % 256) * (1.0f / 255.0f));
        }
    }
    // Pixel 0: the extremes, and sums that end on a half step.
    const std::uint32_t bytes[4][4] = {
        {0, 255, 1, 254}, {0, 255, 0, 255}, {0, 255, 1, 0}, {0, 255, 0, 1}};
    for (std::uint32_t s = 0; s < 4; ++s) {
        for (std::size_t c = 0; c < 4; ++c) {
            values[s][c] =
                std::bit_cast<std::uint32_t>(static_cast<float>(bytes[s][c]) * (1.0f / 255.0f));
        }
    }
    const auto r = check_resolve(reader(), ColorFormat::Rgba8, values, kW, kH);
    EXPECT_EQ(r.mismatches, 0u);
    std::printf("rgba8 resolve: %zu channels checked, %zu differ\n", r.values, r.mismatches);
}

TEST_F(MsaaProbe, BlitResolveOfRandomRgba32fSamplesFollowsTheMeasuredRule) {
    constexpr std::uint32_t kW = 128;
    constexpr std::uint32_t kH = 128;
    std::mt19937 rng(22);
    std::uniform_real_distribution<float> moderate(-1000.0f, 1000.0f);
    std::array<std::vector<std::uint32_t>, 4> values;
    for (auto& v : values) {
        v.resize(std::size_t{kW} * kH * 4);
        for (std::size_t i = 0; i < v.size(); ++i) {
            std::uint32_t b = 0;
            switch (u32(rng) % 6) {
                case 0:
                case 1:
                    b = std::bit_cast<std::uint32_t>(moderate(rng));
                    break;
                case 2:  // large: sums overflow to infinity
                    b = (u32(rng) & 0x80000000u) | (0x7e800000u + (u32(rng) % 0x01000000u));
                    break;
                case 3:  // denormal, either sign
                    b = u32(rng) & 0x807fffffu;
                    break;
                case 4:  // tiny normals, whose sum or quarter may be denormal
                    b = (u32(rng) & 0x80000000u) | (0x00800000u + (u32(rng) % 0x02000000u));
                    break;
                default:  // any finite float
                    b = u32(rng);
                    if ((b & 0x7f800000u) == 0x7f800000u) b &= 0xbfffffffu;
                    break;
            }
            v[i] = b;
        }
    }
    // Pixel 0: every sample -0 (channel 0), negative denormals (1), -0 then +0 (2), and
    // +0 then -0 (3); pixel 1: sums that overflow, cancel exactly, and end denormal.
    const std::uint32_t cases[4][8] = {
        {0x80000000u, 0x80000001u, 0x80000000u, 0x00000000u, 0x7f7fffffu, 0x3f800000u, 0x00800000u,
         0x00c00000u},
        {0x80000000u, 0x807fffffu, 0x00000000u, 0x80000000u, 0x7f7fffffu, 0xbf800000u, 0x80800000u,
         0x00800000u},
        {0x80000000u, 0x80400000u, 0x80000000u, 0x80000000u, 0x7f000000u, 0x3f800000u, 0x00000000u,
         0x00000000u},
        {0x80000000u, 0x80000010u, 0x80000000u, 0x80000000u, 0x7f000000u, 0xbf800000u, 0x00000000u,
         0x00000000u},
    };
    for (std::uint32_t s = 0; s < 4; ++s) {
        for (std::size_t c = 0; c < 8; ++c) values[s][c] = cases[s][c];
    }
    const auto r = check_resolve(reader(), ColorFormat::Rgba32f, values, kW, kH);
    // Measured: the blit is blit_model's everywhere, the sum starting from +0, so that where
    // every sample is (or flushes to) -0 the resolve is +0; resolve_samples follows it.
    EXPECT_EQ(r.model_mismatches, 0u);
    EXPECT_EQ(r.mismatches, 0u) << "resolve_samples differs from the blit";
    std::printf("rgba32f resolve: %zu channels checked, blit == model == resolve_samples\n",
                r.values);
}

}  // namespace
