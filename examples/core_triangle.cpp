// core_triangle: the core library alone (refraster::refraster, no harness): one triangle drawn
// into an 8x8 target and printed, '#' for a covered pixel.
//
// The triangle's corners are the window points (0, 0), (8, 0) and (0, 8). A pixel centre
// (x + 0.5, y + 0.5) lies inside when x + y < 7; the centres with x + y = 7 lie exactly on the
// long edge, which the GL tie rule llvmpipe follows gives to the triangle only for left and
// bottom edges (docs/precision.md, "Edge functions and the tie rule"): 28 pixels.
#include <cstdio>

#include "refraster/renderer.hpp"

int main() {
    refraster::DrawList list;
    list.target = {8, 8, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    list.clear.color = {0.0f, 0.0f, 0.0f, 1.0f};

    refraster::Draw draw;
    draw.primitive = refraster::PrimitiveType::Triangles;
    draw.state.viewport = {0, 0, 8, 8};
    draw.state.shade = refraster::ShadeModel::Flat;
    // Clip-space positions (x, y, z, w) and colours (r, g, b, a): window = (clip + 1) * 4.
    draw.vertices.attributes = {{"color", 4}};
    draw.vertices.data = {-1, -1, 0, 1, 1, 1, 1, 1,  //
                          1,  -1, 0, 1, 1, 1, 1, 1,  //
                          -1, 1,  0, 1, 1, 1, 1, 1};
    list.draws.push_back(draw);

    refraster::Framebuffer fb;
    const refraster::RenderOutcome r = refraster::render(list, fb);
    if (r.status != refraster::RenderStatus::Ok) {
        std::fprintf(stderr, "render failed: %s\n", r.message.c_str());
        return 1;
    }
    int covered = 0;
    for (int y = 7; y >= 0; --y) {  // rows bottom to top in memory; print the top first
        for (int x = 0; x < 8; ++x) {
            const bool lit = fb.color8[4 * static_cast<std::size_t>(y * 8 + x)] == 255;
            covered += lit ? 1 : 0;
            std::putchar(lit ? '#' : '.');
        }
        std::putchar('\n');
    }
    std::printf("%d pixels covered\n", covered);
    return 0;
}
