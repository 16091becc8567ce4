// author_scene: a scene written in code (harness/authoring.hpp): a coloured square turned 35
// degrees about y, seen in perspective, saved as a scene file, loaded back and rendered
// through the reference.
//
//   author_scene OUT.json OUT.png
#include <cstdio>
#include <exception>

#include "harness/api.hpp"

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s OUT.json OUT.png\n", argv[0]);
        return 2;
    }
    try {
        harness::SceneFile file;
        file.name = "examples.authored_square";
        file.description = "A square turned 35 degrees about y, in perspective.";
        file.target = {64, 48, refraster::ColorFormat::Rgba8, refraster::DepthFormat::Z24, 1};
        file.clear.color = {0.1f, 0.1f, 0.15f, 1.0f};

        harness::SceneDraw square;
        square.state.viewport = {0, 0, 64, 48};
        square.state.depth_test = refraster::CompareFunc::Less;
        square.state.depth_write = true;
        const std::array<std::array<float, 2>, 4> corners{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
        const std::array<std::array<float, 4>, 4> colours{
            {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {1, 1, 0, 1}}};
        for (const int i : {0, 1, 2, 0, 2, 3}) {
            harness::SceneVertex v;
            v.position = {corners[static_cast<std::size_t>(i)][0],
                          corners[static_cast<std::size_t>(i)][1], 0.0f, 1.0f};
            v.position_size = 3;
            v.color = colours[static_cast<std::size_t>(i)];
            square.vertices.push_back(v);
        }
        // Model, then view, then projection: the matrix applied to each vertex is P * V * M.
        const auto model = harness::rotation_matrix(35.0f, {0.0f, 1.0f, 0.0f});
        const auto view =
            harness::look_at_matrix({0.0f, 0.5f, 3.5f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
        const auto projection = harness::perspective_matrix(45.0f, 64.0f / 48.0f, 0.5f, 10.0f);
        harness::set_clip_matrix(square,
                                 harness::multiply(projection, harness::multiply(view, model)));
        file.draws.push_back(square);

        // Written as a scene file, it loads back to the same draw list.
        const std::string text = harness::scene_to_json(file);
        std::FILE* out = std::fopen(argv[1], "wb");
        if (out == nullptr || std::fwrite(text.data(), 1, text.size(), out) != text.size() ||
            std::fclose(out) != 0) {
            std::fprintf(stderr, "%s: cannot write\n", argv[1]);
            return 3;
        }
        const harness::Scene scene = harness::load_scene_file(argv[1]);
        const harness::Scene direct = harness::load_scene_text(text, argv[1]);
        std::printf(
            "%s %s\n", argv[1],
            scene.draw_list == direct.draw_list ? "reloads identically" : "DIFFERS when reloaded");

        const auto r = harness::make_reference()->render(scene);
        if (r.status != harness::RenderStatus::Ok) {
            std::fprintf(stderr, "%s\n", r.message.c_str());
            return 3;
        }
        std::size_t drawn = 0;
        for (std::size_t i = 0; i < r.image.pixel_count(); ++i)
            drawn += r.image.depth[i] != 0xffffffu;
        harness::write_color_image(r.image, argv[2]);
        std::printf("%s: %zu of %zu pixels drawn\n", argv[2], drawn, r.image.pixel_count());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 3;
    }
}
