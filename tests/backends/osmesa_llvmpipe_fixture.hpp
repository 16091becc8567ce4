// osmesa_llvmpipe_fixture.hpp: the fixture of the probe tests that call GL in this process: one
// OSMesa llvmpipe context (compatibility profile, RGBA, no depth or stencil of its own, a 1x1
// buffer: the probes render to their own framebuffer objects) made current for the whole test
// suite, a check that the renderer is llvmpipe before each test and that no GL error is left
// after it.
//
// Deliberately does not: choose another driver (GALLIUM_DRIVER is set only when the
// environment has not set it, and the renderer check then fails the tests).
#pragma once

#include <GL/gl.h>
#include <GL/osmesa.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <string>

class OsmesaLlvmpipeTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        ::setenv("GALLIUM_DRIVER", "llvmpipe", 0);
        const int attribs[] = {OSMESA_FORMAT,
                               OSMESA_RGBA,
                               OSMESA_DEPTH_BITS,
                               0,
                               OSMESA_STENCIL_BITS,
                               0,
                               OSMESA_PROFILE,
                               OSMESA_COMPAT_PROFILE,
                               0};
        context_ = OSMesaCreateContextAttribs(attribs, nullptr);
        ASSERT_NE(context_, nullptr);
        ASSERT_TRUE(OSMesaMakeCurrent(context_, pixel_.data(), GL_UNSIGNED_BYTE, 1, 1));
    }
    static void TearDownTestSuite() {
        if (context_) OSMesaDestroyContext(context_);
        context_ = nullptr;
    }
    void SetUp() override {
        const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        ASSERT_NE(renderer.find("llvmpipe"), std::string::npos) << renderer;
        while (glGetError() != GL_NO_ERROR) {
        }
    }
    void TearDown() override { EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR)); }

  private:
    static inline OSMesaContext context_ = nullptr;
    static inline std::array<unsigned char, 4> pixel_{};
};
