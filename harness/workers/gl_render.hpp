// gl_render.hpp: renders a refraster::DrawList with the current OpenGL context, and the
// request loop every GL worker process runs.
//
// Implements the rules of docs/scene-format.md, "How a GL backend draws a scene":
// a framebuffer object with the target's formats and always a depth attachment, a 4x target
// (multisample textures) resolved with glBlitFramebuffer and every sample read back exactly
// (SampleReader), GL_MULTISAMPLE per draw, a clear with scissor off and every mask on, a
// pass-through shader per interpolation qualifier, all fixed-function state set from each draw's
// own defaults, and glReadPixels into a refraster::Framebuffer (rows bottom-up). Textures: every
// texture of the DrawList is made (RGBA8, the given levels or glGenerateMipmap's) at the start of
// a render and deleted at its end; a textured draw binds its texture on unit 0 with its filters,
// wraps and border colour, and its program (per interpolation qualifier and env) samples it with
// textureProj at the "texcoord" attribute, interpolated like the colour. It also collects the
// provenance of the context (renderer, version, driver, environment, Mesa package).
//
// Deliberately does not: create or own a context (each worker does, with OSMesa or EGL),
// transform vertices (the front end did), or compare anything. It is compiled into each worker
// executable and never linked into the harness itself, which must not load two GL libraries.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "harness/backend.hpp"
#include "refraster/draw.hpp"

namespace harness::gl {

class Renderer {
  public:
    // Needs a current compatibility-profile context; it must stay current while the Renderer
    // lives. `backend` ("osmesa", "egl") and `mesa_package` (the Debian package whose version
    // is recorded) only feed the provenance.
    Renderer(std::string_view backend, std::string_view mesa_package);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Never throws for a GL-side problem: the status says what went wrong.
    // With `owners`, also fills Framebuffer::owner from a second colour attachment written
    // from gl_PrimitiveID. A 4x target also fills RenderResult::samples; the image is then
    // the blit's colour with sample 0's depth and owners.
    harness::RenderResult render(const refraster::DrawList& list, bool owners = false);

    const harness::Provenance& provenance() const;
    void add_provenance(const std::string& key, const std::string& value);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Reads every sample of multisample textures exactly, one full-screen texelFetch pass per
// sample into single-sample integer or unorm8 targets read with glReadPixels:
// - rgba8 colour: the fetched float, written to an RGBA8 target, gives the byte back;
// - rgba32f colour: floatBitsToUint of the fetched value into RGBA32UI;
// - depth: floatBitsToUint of the fetched depth into R32UI; z32f keeps those bits (denormals
//   too), z16 and z24 recover the stored integer with depth_from_fetch; for z24 a marking
//   pass first runs a depth test GL_GREATER against 1.0 over every sample, which separates
//   2^24 - 2 from 2^24 - 1 (both fetched as 1.0);
// - owners (R32UI): the fetched integer into R32UI.
// The textures are GL_TEXTURE_2D_MULTISAMPLE when `samples` is 4; with `samples` 1 they are
// plain GL_TEXTURE_2D read at level 0 by the same shaders with sampler2D, which is how the
// probe tests check every possible depth value. Needs a current context of GL 3.3 or later;
// changes the bound framebuffers, program, vertex array, texture units 0-3, viewport and the
// fixed-function state a full-screen pass depends on, and leaves them changed.
struct SampleSources {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::uint32_t samples = 4;  // 4: multisample textures; 1: single-sample textures
    refraster::ColorFormat color_format = refraster::ColorFormat::Rgba8;
    unsigned color_texture = 0;  // GL names; 0: none (the colour stays zero)
    refraster::DepthFormat depth_format = refraster::DepthFormat::None;
    unsigned depth_texture = 0;  // 0 when depth_format is None
    unsigned owner_texture = 0;  // R32UI; 0: no owners
    // Probes only: Framebuffer::depth holds the fetched float's bits, not the stored value.
    bool raw_depth = false;
};

class SampleReader {
  public:
    SampleReader();
    ~SampleReader();
    SampleReader(const SampleReader&) = delete;
    SampleReader& operator=(const SampleReader&) = delete;

    // A Framebuffer with `samples` values a pixel (pixel-major); owners filled when an owner
    // texture is given. Throws std::runtime_error (one line) on a GL error or on a fetched
    // depth that is no value of its format.
    refraster::Framebuffer read(const SampleSources& src);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// The stored z16 or z24 integer whose texel fetch returns the float with bits `fetched`, or
// nullopt when none does. llvmpipe fetches a unorm depth of n bits as
// fl(float(z) * fl(1 / (2^n - 1))) (lp_bld_conv.c: lp_build_unsigned_norm_to_float, n <= 24;
// measured for all 2^16 and 2^24 values). Rounding d * (2^n - 1) does not invert that for z24
// (it is wrong for 6,291,455 values: in [2^23, 2^24) the product lands one or two steps
// high), so the estimate is searched +-2 for the z whose fetch gives d back. The fetch is
// injective but for one pair: z24's 2^24 - 2 and 2^24 - 1 both give 1.0, here 2^24 - 1;
// SampleReader tells them apart with a depth test.
std::optional<std::uint32_t> depth_from_fetch(refraster::DepthFormat format, std::uint32_t fetched);

// What a worker's context factory returns: destroying it releases the context.
class ContextHolder {
  public:
    virtual ~ContextHolder() = default;
    // What the context knows of where it renders (the EGL device), for every result's
    // provenance.
    virtual harness::Provenance provenance() const { return {}; }
};

// The whole life of a worker process. Moves the protocol off fd 1 (which then points at
// stderr, so a stray print cannot corrupt a frame), calls `make_context` (which throws
// std::runtime_error with a one-line reason on failure), announces itself with a Hello frame,
// then answers requests from stdin until end of stream. Returns the process exit code.
// Test hooks: a Crash frame makes it abort(), a Hang frame makes it sleep forever, and with
// REFRASTER_WORKER_KILL_AT=N in its environment it SIGKILLs itself on receiving its Nth scene
// (REFRASTER_WORKER_HANG_AT=N: it stops answering instead).
int run_worker(std::string_view backend, std::string_view mesa_package,
               const std::function<std::unique_ptr<ContextHolder>()>& make_context);

}  // namespace harness::gl
