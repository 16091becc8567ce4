// explain_pixel: every decision the reference made about one pixel of a scene, as
// `refraster explain` prints it (without a GL backend to compare with).
//
//   explain_pixel SCENE.json X Y
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "harness/api.hpp"

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: %s SCENE.json X Y\n", argv[0]);
        return 2;
    }
    try {
        const harness::Scene scene = harness::load_scene_file(argv[1]);
        const int x = std::atoi(argv[2]);
        const int y = std::atoi(argv[3]);
        const harness::Explanation e = harness::explain_pixel(
            scene, harness::load_profile("llvmpipe-22.3"), x, y, /*backend=*/nullptr);
        std::fputs(harness::explanation_text(e).c_str(), stdout);
        return 0;
    } catch (const harness::SceneError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 3;
    }
}
