// osmesa_worker.cpp: the refraster-worker-osmesa executable.
//
// Implements: one OSMesa compatibility-profile context for the life of the process, then the
// request loop of gl_render.hpp. GALLIUM_DRIVER, set by the harness in this process's
// environment, picks llvmpipe or softpipe.
//
// Deliberately does not: render into the OSMesa buffer. That buffer is a window-system
// framebuffer whose y flip changes llvmpipe's setup order; it exists only because
// OSMesaMakeCurrent needs one, and every scene goes into framebuffer objects.
#include <GL/osmesa.h>

#include <array>
#include <memory>
#include <stdexcept>

#include "gl_render.hpp"

namespace {

class OsmesaContext : public harness::gl::ContextHolder {
  public:
    OsmesaContext() {
        // No version asked for: Mesa then gives the highest compatibility version it has.
        const std::array<int, 9> attribs = {
            OSMESA_FORMAT,
            OSMESA_RGBA,
            OSMESA_DEPTH_BITS,
            0,
            OSMESA_STENCIL_BITS,
            0,
            OSMESA_PROFILE,
            OSMESA_COMPAT_PROFILE,
            0,
        };
        context_ = OSMesaCreateContextAttribs(attribs.data(), nullptr);
        if (context_ == nullptr) {
            throw std::runtime_error("OSMesaCreateContextAttribs failed (compatibility profile)");
        }
        if (!OSMesaMakeCurrent(context_, pixel_.data(), GL_UNSIGNED_BYTE, 1, 1)) {
            OSMesaDestroyContext(context_);
            throw std::runtime_error("OSMesaMakeCurrent failed");
        }
    }
    ~OsmesaContext() override { OSMesaDestroyContext(context_); }
    OsmesaContext(const OsmesaContext&) = delete;
    OsmesaContext& operator=(const OsmesaContext&) = delete;

  private:
    OSMesaContext context_ = nullptr;
    std::array<unsigned char, 4> pixel_{};  // the 1x1 buffer MakeCurrent insists on
};

}  // namespace

int main() {
    return harness::gl::run_worker("osmesa", "libosmesa6",
                                   [] { return std::make_unique<OsmesaContext>(); });
}
