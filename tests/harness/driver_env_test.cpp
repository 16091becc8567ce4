// Choosing a GL driver: the worker's environment, the driver the environment names, and naming
// the driver a context really runs (harness/backend.hpp, backends/driver_env.hpp).
#include "backends/driver_env.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "harness/backend.hpp"

namespace {

using harness::BackendKind;
using harness::Driver;
using Env = std::vector<std::string>;

bool has(const Env& env, const std::string& kv) {
    return std::find(env.begin(), env.end(), kv) != env.end();
}

bool names(const Env& env, const std::string& name) {
    return std::any_of(env.begin(), env.end(),
                       [&](const std::string& kv) { return kv.starts_with(name + "="); });
}

// --driver llvmpipe wins over a loader override in the environment: the label must be true.
TEST(DriverEnvironment, AGalliumDriverReplacesEveryDriverChoice) {
    const Env base{"PATH=/bin", "GALLIUM_DRIVER=softpipe", "MESA_LOADER_DRIVER_OVERRIDE=zink",
                   "GALLIVM_PERF=nopt"};
    const Env env = harness::gl_worker_environment(Driver::Llvmpipe, base, {"LP_NUM_THREADS=0"});
    EXPECT_TRUE(has(env, "GALLIUM_DRIVER=llvmpipe"));
    EXPECT_FALSE(has(env, "GALLIUM_DRIVER=softpipe"));
    EXPECT_FALSE(names(env, "MESA_LOADER_DRIVER_OVERRIDE"));
    EXPECT_TRUE(has(env, "LIBGL_ALWAYS_SOFTWARE=1"));
    EXPECT_TRUE(has(env, "GALLIVM_PERF=nopt"));
    EXPECT_TRUE(has(env, "LP_NUM_THREADS=0"));
    EXPECT_TRUE(has(env, "PATH=/bin"));
}

TEST(DriverEnvironment, ZinkIsChosenByTheLoaderOnLavapipeUnlessTheUserSaysOtherwise) {
    const Env env = harness::gl_worker_environment(Driver::Zink, {"GALLIUM_DRIVER=llvmpipe"}, {});
    EXPECT_TRUE(has(env, "MESA_LOADER_DRIVER_OVERRIDE=zink"));
    EXPECT_FALSE(names(env, "GALLIUM_DRIVER"));
    EXPECT_TRUE(has(env, "LIBGL_ALWAYS_SOFTWARE=1"));
    const Env gpu = harness::gl_worker_environment(Driver::Zink, {"LIBGL_ALWAYS_SOFTWARE=0"}, {});
    EXPECT_TRUE(has(gpu, "LIBGL_ALWAYS_SOFTWARE=0"));
    EXPECT_FALSE(has(gpu, "LIBGL_ALWAYS_SOFTWARE=1"));
    // The options' own variables replace the environment's.
    const Env extra =
        harness::gl_worker_environment(Driver::Zink, {"ZINK_DEBUG=a"}, {"ZINK_DEBUG=b"});
    EXPECT_TRUE(has(extra, "ZINK_DEBUG=b"));
    EXPECT_FALSE(has(extra, "ZINK_DEBUG=a"));
}

TEST(DriverEnvironment, TheEnvironmentChoosesTheDriverWhenNoneIsNamed) {
    EXPECT_EQ(harness::driver_from_environment(BackendKind::Egl, {}), Driver(Driver::Llvmpipe));
    EXPECT_EQ(harness::driver_from_environment(BackendKind::Egl, {"GALLIUM_DRIVER=softpipe"}),
              Driver(Driver::Softpipe));
    EXPECT_EQ(
        harness::driver_from_environment(
            BackendKind::Egl, {"GALLIUM_DRIVER=softpipe", "MESA_LOADER_DRIVER_OVERRIDE=zink"}),
        Driver(Driver::Zink));
    // The swrast loader hosts the Gallium drivers; OSMesa has no loader.
    EXPECT_EQ(
        harness::driver_from_environment(BackendKind::Egl, {"MESA_LOADER_DRIVER_OVERRIDE=swrast"}),
        Driver(Driver::Llvmpipe));
    EXPECT_EQ(
        harness::driver_from_environment(BackendKind::OSMesa, {"MESA_LOADER_DRIVER_OVERRIDE=zink"}),
        Driver(Driver::Llvmpipe));
    EXPECT_EQ(harness::driver_from_environment(BackendKind::Egl, {"GALLIUM_DRIVER="}),
              Driver(Driver::Llvmpipe));
}

TEST(DriverEnvironment, TheRecordedVariablesAreThoseThatChooseOrChangeTheDriver) {
    const Env vars = harness::driver_env::driver_variables(
        {"PATH=/bin", "ZINK_DEBUG=x", "GALLIVM_PERF=no_filter_hacks", "VK_ICD_FILENAMES=/a.json",
         "HOME=/root", "MESA_LOADER_DRIVER_OVERRIDE=zink", "LIBGL_ALWAYS_SOFTWARE=1",
         "__EGL_VENDOR_LIBRARY_FILENAMES=/v.json", "LP_NUM_THREADS=2", "GALLIUM_DRIVER=x"});
    EXPECT_EQ(vars, (Env{"GALLIUM_DRIVER=x", "GALLIVM_PERF=no_filter_hacks",
                         "LIBGL_ALWAYS_SOFTWARE=1", "LP_NUM_THREADS=2",
                         "MESA_LOADER_DRIVER_OVERRIDE=zink", "VK_ICD_FILENAMES=/a.json",
                         "ZINK_DEBUG=x", "__EGL_VENDOR_LIBRARY_FILENAMES=/v.json"}));
}

TEST(DriverEnvironment, TheLoadedDriverIsNamedFromTheLibrariesThenTheRenderer) {
    using harness::driver_env::loaded_driver;
    using harness::driver_env::vulkan_driver;
    const std::string zink_libs =
        "/usr/lib/x86_64-linux-gnu/dri/zink_dri.so;/usr/lib/x86_64-linux-gnu/libEGL.so.1;"
        "/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so";
    EXPECT_EQ(loaded_driver("zink (llvmpipe (LLVM 15.0.6, 256 bits))", zink_libs), "zink");
    EXPECT_EQ(vulkan_driver("zink (llvmpipe (LLVM 15.0.6, 256 bits))"),
              "lavapipe: llvmpipe (LLVM 15.0.6, 256 bits)");
    EXPECT_EQ(vulkan_driver("zink (AMD RADV NAVI10)"), "radv: AMD RADV NAVI10");
    const std::string swrast = "/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so";
    EXPECT_EQ(loaded_driver("llvmpipe (LLVM 15.0.6, 256 bits)", swrast), "llvmpipe");
    EXPECT_EQ(loaded_driver("softpipe", swrast), "softpipe");
    EXPECT_EQ(loaded_driver("Mesa Intel(R) UHD Graphics 620 (KBL GT2)", "/usr/lib/dri/iris_dri.so"),
              "iris");
    EXPECT_EQ(vulkan_driver("llvmpipe (LLVM 15.0.6, 256 bits)"), "");
}

}  // namespace
