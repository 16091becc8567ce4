// renderer.hpp: the reference rasterizer's entry point.
//
// Implements: clearing the target and drawing every draw of a DrawList in order under a
// Profile, as Mesa 22.3 llvmpipe does in an FBO: triangles, strips and fans (in the vertex order
// Mesa's draw module emits), lines, strips and loops of any width, points of any size, polygon
// modes line and point; the draw module's clipper and float cull; llvmpipe's fixed-point
// setup, tie rule and traversal; attribute planes and per-pixel evaluation (smooth,
// noperspective, flat, with FMA where the driver fuses); z16, z24 and z32f depth with every
// compare function and polygon offset; the two blend presets; rgba8 and rgba32f targets. The
// gl-exact profile decides triangle coverage exactly instead; the softpipe-22.3 profile draws as
// Mesa 22.3 softpipe does (softpipe_model.hpp). Optionally a per-pixel trace
// (trace.hpp) and the owner of every pixel.
//
// Deliberately does not (yet), answering RenderStatus::NotSupported instead of a guess:
// anything but filled triangles under the exact profile, and multisampled targets for the
// scanline (softpipe) rules, which have none.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "refraster/draw.hpp"
#include "refraster/error.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/profile.hpp"
#include "refraster/trace.hpp"

namespace refraster {

enum class RenderStatus : std::uint8_t { Ok, NotSupported };

struct RenderOutcome {
    RenderStatus status = RenderStatus::Ok;
    std::string message;  // why, when status != Ok
    std::uint64_t fragments =
        0;  // pixels traversal found covered, counted with RenderStage::Raster
};

// Where a render may stop, for measuring what each stage costs (`refraster bench`): after
// the vertex stage (fetch, viewport transform, clip masks), after setup (assembly, clipping,
// culling, snapping, edges and attribute planes), after traversal (coverage, counted in
// RenderOutcome::fragments, nothing shaded), or never. A stopped render leaves the target
// cleared but not drawn.
enum class RenderStage : std::uint8_t { Load, Setup, Raster, Fragment };

// Which implementation of the per-pixel stage a render runs. Every path gives the same bytes:
// the same float operations in the same order, fused exactly where the profile fuses (tests
// render random scenes through each and compare them with the model); only the speed differs.
// A path this CPU cannot run falls back to the next narrower one it can
// (kernel_path_available).
enum class KernelPath : std::uint8_t {
    Model,    // the scalar model: one pixel at a time from quad packets, baseline instructions
    Scalar,   // one pixel at a time from row masks, compiled for FMA and SSE4.1 where present
    Avx2,     // 8 pixels at a time (AVX2 and FMA)
    Avx512,   // 16 pixels at a time (AVX-512 F, BW, DQ, VL and FMA)
    Fastest,  // the widest this CPU runs
};
std::string_view to_string(KernelPath p);
// Whether this CPU runs `p` itself (Model and Scalar always; Fastest always).
bool kernel_path_available(KernelPath p);
// The path a render asked for `p` runs on this CPU.
KernelPath resolve_kernel_path(KernelPath p);

struct RenderOptions {
    Profile profile;
    // When set, render() records every decision about pixel (trace->x, trace->y).
    PixelTrace* trace = nullptr;
    // Fill Framebuffer::owner: which primitive wrote each pixel last.
    bool record_owners = false;
    RenderStage stop_after = RenderStage::Fragment;
    // The per-pixel stage's implementation (a traced render always runs the model).
    KernelPath kernels = KernelPath::Fastest;
    // Threads that rasterize and shade (each owns every 64-row band of the target whose index
    // modulo the count is its own, and shades the primitives in API order there, so the bytes
    // are the same for any count); 0, the default: one per core. The model path and traced
    // renders use one.
    unsigned threads = 0;
    // When set, a render still running at this time stops and render() throws RenderStopped.
    // Neither the deadline nor the stop flag below changes a render that ends: they are read
    // between draws, between primitives of setup and traversal, and between a band's
    // primitives on every shading thread, never inside a pixel's arithmetic.
    std::optional<std::chrono::steady_clock::time_point> deadline;
    // When set, another thread may store true here to stop the render the same way.
    const std::atomic<bool>* stop = nullptr;
};

// A render that stopped before its end (RenderOptions::deadline passed, or
// RenderOptions::stop was set): the target holds a partial image, which the caller discards.
// Every thread of the render has returned when it is thrown. A backend failure (exit code 3):
// the scene was not wrong, the run was cut short.
class RenderStopped : public Error {
  public:
    explicit RenderStopped(const std::string& message)
        : Error(ExitClass::BackendFailure, message) {}
};

// Number of complete primitives a draw assembles under GL's rules (OpenGL 4.6 compatibility
// profile, section 10.1 "Primitive Types"): a leftover vertex draws nothing.
std::size_t primitive_count(PrimitiveType p, std::size_t vertex_count);

// Whether this CPU fuses as gallivm would (FMA present); FmaMode::Auto resolves to this.
bool host_has_fma();

RenderOutcome render(const DrawList& list, const RenderOptions& options, Framebuffer& out);

// The levels the reference samples a texture from: the given ones, or the base level and the
// levels glGenerateMipmap makes under `profile` (its viewport_fma decides whether the blit's
// interpolation fuses; docs/precision.md, "Generated mipmaps").
std::vector<TextureImage> texture_levels(const Texture& texture, const Profile& profile = {});
inline RenderOutcome render(const DrawList& list, Framebuffer& out) {
    return render(list, RenderOptions{}, out);
}

}  // namespace refraster
