// egl_worker.cpp: the refraster-worker-egl executable.
//
// Implements: an EGL display on Mesa's surfaceless platform (no X, Wayland or /dev/dri
// needed), one desktop-OpenGL compatibility-profile context made current without a surface,
// then the request loop of gl_render.hpp. GALLIUM_DRIVER, set by the harness in this
// process's environment, picks llvmpipe or softpipe.
//
// Deliberately does not: create a pbuffer (every scene goes into framebuffer objects), or
// link libOSMesa: it exports the same gl* symbols as glvnd's libOpenGL.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <array>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "gl_render.hpp"

namespace {

std::string egl_error(const char* what) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%04x", static_cast<unsigned>(eglGetError()));
    return std::string(what) + " failed (EGL error " + buf + ")";
}

class EglContext : public harness::gl::ContextHolder {
  public:
    EglContext() {
        // An extension entry point: glvnd's libEGL exports only core functions.
        const auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
            eglGetProcAddress("eglGetPlatformDisplayEXT"));
        if (get_platform_display == nullptr) {
            throw std::runtime_error("eglGetPlatformDisplayEXT is not available");
        }
        display_ =
            get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display_ == EGL_NO_DISPLAY) {
            throw std::runtime_error(egl_error("eglGetPlatformDisplayEXT(surfaceless)"));
        }
        EGLint major = 0;
        EGLint minor = 0;
        if (!eglInitialize(display_, &major, &minor)) {
            throw std::runtime_error(egl_error("eglInitialize"));
        }
        try {
            if (!eglBindAPI(EGL_OPENGL_API)) throw std::runtime_error(egl_error("eglBindAPI"));
            const std::array<EGLint, 5> config_attribs = {
                EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
            EGLConfig config = nullptr;
            EGLint configs = 0;
            if (!eglChooseConfig(display_, config_attribs.data(), &config, 1, &configs) ||
                configs < 1) {
                throw std::runtime_error(egl_error("eglChooseConfig(OpenGL)"));
            }
            // No version asked for: Mesa then gives the highest compatibility version it has.
            const std::array<EGLint, 3> context_attribs = {
                EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT,
                EGL_NONE};
            context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, context_attribs.data());
            if (context_ == EGL_NO_CONTEXT) {
                throw std::runtime_error(egl_error("eglCreateContext(compatibility)"));
            }
            if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
                throw std::runtime_error(egl_error("eglMakeCurrent(no surface)"));
            }
        } catch (...) {
            if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
            eglTerminate(display_);
            throw;
        }
    }
    ~EglContext() override {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
        eglTerminate(display_);
    }
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

  private:
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace

int main() {
    return harness::gl::run_worker("egl", "libegl-mesa0",
                                   [] { return std::make_unique<EglContext>(); });
}
