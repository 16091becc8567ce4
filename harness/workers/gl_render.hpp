// gl_render.hpp: renders a refraster::DrawList with the current OpenGL context, and the
// request loop every GL worker process runs.
//
// Implements the rules of docs/scene-format.md, "How a GL backend draws a scene":
// a framebuffer object with the target's formats and always a depth attachment, a 4x target
// resolved with glBlitFramebuffer, a clear with scissor off and every mask on, a pass-through
// shader per interpolation qualifier, all fixed-function state set from each draw's own
// defaults, and glReadPixels into a refraster::Framebuffer (rows bottom-up). It also collects
// the provenance of the context (renderer, version, driver, environment, Mesa package).
//
// Deliberately does not: create or own a context (each worker does, with OSMesa or EGL),
// transform vertices (the front end did), or compare anything. It is compiled into each worker
// executable and never linked into the harness itself, which must not load two GL libraries.
#pragma once

#include <functional>
#include <memory>
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
    // from gl_PrimitiveID (single-sample targets only).
    harness::RenderResult render(const refraster::DrawList& list, bool owners = false);

    const harness::Provenance& provenance() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// What a worker's context factory returns: destroying it releases the context.
class ContextHolder {
  public:
    virtual ~ContextHolder() = default;
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
