// layered_scene.hpp: a scene that takes the reference many seconds, for the per-scene timeout.
#pragma once

#include <string>

namespace testutil {

// A scene of `layers` blended triangles, each covering the whole `size` x `size` target: every
// layer shades every pixel (2048 x 2048 and 400 layers: 1.7 billion fragments, below the
// loader's estimate limit, 13 s of the reference's time on two threads of the development
// machine), for the per-scene timeout.
inline std::string layered_scene(int size, int layers, const std::string& name = "layers") {
    const std::string s = std::to_string(size);
    const std::string far = std::to_string(2 * size);
    std::string text = R"({"format": "refraster-scene/1", "name": ")" + name +
                       R"(", "target": {"width": )" + s + R"(, "height": )" + s +
                       R"(, "depth": "z24"}, "clear": {"color": [0.1, 0.2, 0.3, 1]},
 "draws": [{"primitive": "triangles", "state": {"blend": "alpha"}, "vertices": [)";
    for (int k = 0; k < layers; ++k) {
        const std::string c = std::to_string(static_cast<double>(k % 17) / 17.0);
        const std::string colour = R"(, "color": [)" + c + ", 0.5, 0.75, 0.5]}";
        text += std::string(k == 0 ? "" : ",\n") + R"({"position": [0, 0])" + colour +
                R"(, {"position": [)" + far + R"(, 0])" + colour + R"(, {"position": [0, )" + far +
                "]" + colour;
    }
    return text + "]}]}";
}

}  // namespace testutil
