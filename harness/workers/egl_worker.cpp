// egl_worker.cpp: the refraster-worker-egl executable.
//
// Implements: an EGL display on Mesa's surfaceless platform (no X, Wayland or /dev/dri
// needed), or, with REFRASTER_EGL_DEVICE=N in the environment, on device N of
// EGL_EXT_device_enumeration (EGL_PLATFORM_DEVICE_EXT: the software device, or a GPU), one
// desktop-OpenGL compatibility-profile context made current without a surface, then the
// request loop of gl_render.hpp. GALLIUM_DRIVER, set by the harness in this process's
// environment, picks llvmpipe or softpipe for the software paths. `--list-devices` prints the
// devices, one line each ("N: extensions; DRM node"), and exits.
//
// Deliberately does not: create a pbuffer (every scene goes into framebuffer objects), or
// link libOSMesa: it exports the same gl* symbols as glvnd's libOpenGL.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "gl_render.hpp"

namespace {

std::string egl_error(const char* what) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%04x", static_cast<unsigned>(eglGetError()));
    return std::string(what) + " failed (EGL error " + buf + ")";
}

// The devices of EGL_EXT_device_enumeration (extension entry points: glvnd's libEGL exports
// only core functions).
std::vector<EGLDeviceEXT> egl_devices() {
    const auto query =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (query == nullptr) throw std::runtime_error("eglQueryDevicesEXT is not available");
    EGLint n = 0;
    if (!query(0, nullptr, &n)) throw std::runtime_error(egl_error("eglQueryDevicesEXT"));
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(n));
    if (n > 0 && !query(n, devices.data(), &n))
        throw std::runtime_error(egl_error("eglQueryDevicesEXT"));
    devices.resize(static_cast<std::size_t>(n));
    return devices;
}

std::string device_string(EGLDeviceEXT d, EGLint name) {
    const auto query = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
        eglGetProcAddress("eglQueryDeviceStringEXT"));
    if (query == nullptr) return {};
    const char* s = query(d, name);
    return s ? s : "";
}

class EglContext : public harness::gl::ContextHolder {
  public:
    EglContext() {
        const auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
            eglGetProcAddress("eglGetPlatformDisplayEXT"));
        if (get_platform_display == nullptr) {
            throw std::runtime_error("eglGetPlatformDisplayEXT is not available");
        }
        const char* device = std::getenv("REFRASTER_EGL_DEVICE");
        if (device != nullptr && *device != '\0') {
            const auto devices = egl_devices();
            const long index = std::strtol(device, nullptr, 10);
            if (index < 0 || static_cast<std::size_t>(index) >= devices.size()) {
                throw std::runtime_error("EGL device " + std::string(device) + " does not exist (" +
                                         std::to_string(devices.size()) +
                                         " devices: --egl-device list shows them)");
            }
            const EGLDeviceEXT d = devices[static_cast<std::size_t>(index)];
            provenance_["egl_platform"] = "device";
            provenance_["egl_device"] = std::to_string(index);
            provenance_["egl_device_extensions"] = device_string(d, EGL_EXTENSIONS);
            provenance_["egl_device_drm"] = device_string(d, EGL_DRM_DEVICE_FILE_EXT);
            display_ = get_platform_display(EGL_PLATFORM_DEVICE_EXT, d, nullptr);
            if (display_ == EGL_NO_DISPLAY) {
                throw std::runtime_error(egl_error("eglGetPlatformDisplayEXT(device)"));
            }
        } else {
            provenance_["egl_platform"] = "surfaceless";
            display_ =
                get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
            if (display_ == EGL_NO_DISPLAY) {
                throw std::runtime_error(egl_error("eglGetPlatformDisplayEXT(surfaceless)"));
            }
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

    harness::Provenance provenance() const override { return provenance_; }

  private:
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
    harness::Provenance provenance_;
};

int list_devices() {
    try {
        const auto devices = egl_devices();
        for (std::size_t i = 0; i < devices.size(); ++i) {
            const std::string drm = device_string(devices[i], EGL_DRM_DEVICE_FILE_EXT);
            std::printf("%zu: %s%s%s\n", i, device_string(devices[i], EGL_EXTENSIONS).c_str(),
                        drm.empty() ? "" : "; ", drm.c_str());
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc > 1 && std::string(argv[1]) == "--list-devices") return list_devices();
    return harness::gl::run_worker("egl", "libegl-mesa0",
                                   [] { return std::make_unique<EglContext>(); });
}
