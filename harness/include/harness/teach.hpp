// teach.hpp: a textbook algorithm run on a scene beside GL's rules, for `refraster teach`.
//
// Implements: taking from a scene what each textbook algorithm draws (refraster/textbook/:
// the segments of line draws for the line algorithms, the points of point draws for the
// midpoint circle, the outlines of polygon, fan and triangle draws for the polygon fills,
// ear clipping, trapezoids and flood fills, the depth-tested triangles for the painter's
// algorithm, the clip-space triangles for homogeneous rasterization), running it with its step
// trace, comparing its pixels with an image of the same scene under GL's rules (the reference
// rasterizer's, or a GL backend's), and naming for every pixel that differs why: the rounding
// of endpoints to pixel centres, a tie, GL's half-open line ends, GL_POLYGON's fan, a leak
// through an outline, a painter's order, the part of a triangle behind the eye. The result is
// the JSON that the teaching page (teach_page.hpp) draws.
//
// Deliberately does not: render the GL image (the caller does, with the owner pass, so that
// coverage is known even where a colour equals the clear colour), or write files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "harness/scene.hpp"
#include "refraster/error.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/textbook/trace.hpp"

namespace harness {

struct TeachAlgorithmInfo {
    std::string_view name;   // the --algorithm value
    std::string_view title;  // "Bresenham's line algorithm"
    std::string_view takes;  // what of a scene it draws
};
// Every algorithm `teach` knows, in the order `--help` lists them.
const std::vector<TeachAlgorithmInfo>& teach_algorithms();

// A scene that holds nothing the algorithm draws, or an unknown algorithm: bad input.
class TeachError : public refraster::Error {
  public:
    explicit TeachError(const std::string& message)
        : refraster::Error(refraster::ExitClass::BadInput, message) {}
};

// The bounds of one teaching run (docs/limits.md, "Teaching pages"): a page shows every pixel
// and every recorded step to a reader, so a run is bounded by what a page can show, and every
// algorithm's work and memory by its input. The inputs are checked before any work
// (check_teach_input, and the tool for --zoom); the steps past the step bounds are counted, not
// kept; the page's bytes are checked before anything is written.
struct TeachLimits {
    // Target width x height: the images, the comparison and every per-pixel pass cost this
    // many; each difference costs a reason of up to a few hundred bytes in the page.
    static constexpr std::uint64_t kMaxPixels = 65'536;  // 256 x 256
    // Vertices (elements: indices count) of the draws the algorithm takes, all draws together.
    // The per-pixel passes (reasons, Bresenham outlines, the seed search) cost pixels times
    // vertices.
    static constexpr std::uint64_t kMaxVertices = 4'096;
    // Vertices of the polygon draws ear clipping and the trapezoids take: ear clipping tests
    // every remaining vertex against each candidate ear (cubic in the worst case), the
    // trapezoids list every edge at every slab.
    static constexpr std::uint64_t kMaxPolygonVertices = 1'024;
    // Steps recorded, and pixel marks and overlay segments in them: the steps past any of these
    // are counted and summarised in a last step (the first steps are what a reader steps
    // through). An overlay segment costs about 100 bytes of page, a mark about 20.
    static constexpr std::size_t kMaxSteps = 10'000;
    static constexpr std::size_t kMaxStepPixels = 262'144;
    static constexpr std::size_t kMaxStepSegments = 65'536;
    // A recorded step's values: at most this many, each cut to this many characters.
    static constexpr std::size_t kMaxStepValues = 24;
    static constexpr std::size_t kMaxValueChars = 240;
    // The zoomed PNG images (width x zoom x height x zoom pixels, RGBA8 in memory, three of
    // them).
    static constexpr std::uint64_t kMaxImagePixels = 16'777'216;  // 64 MiB each
    // index.html and teach.json, each.
    static constexpr std::uint64_t kMaxPageBytes = 64ull << 20;
};

// Refuses (TeachError, bad input) a scene over a TeachLimits bound for `algorithm`: the target
// (JSON path `target`), or the vertices the algorithm takes (`draws[i]` of the draw that crosses
// the bound). Runs before any rendering; teach() runs it too.
void check_teach_input(const Scene& scene, std::string_view algorithm);

struct TeachDifference {
    int x = 0;
    int y = 0;
    double algorithm = 0.0;  // the algorithm's weight at the pixel (1: lit)
    bool gl = false;         // GL's rules light it
    std::string reason;
};

struct TeachResult {
    std::string algorithm;
    std::string title;
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> algorithm_rgba;  // width * height * 4, row 0 at the bottom
    std::vector<std::uint8_t> gl_rgba;
    std::vector<bool> gl_lit;
    std::vector<TeachDifference> differences;
    std::vector<refraster::textbook::Segment> input;
    std::vector<refraster::textbook::Step> steps;
    std::vector<std::string> pseudo_code;  // the algorithm's, each step's `line` a line of it
    std::size_t omitted_steps = 0;         // steps past TeachLimits' step bounds, not recorded
    std::vector<std::string> notes;
    std::string summary;
    // Empty, or the second algorithm's title when the GL side holds another algorithm's image
    // (teach_beside).
    std::string beside;
};

// Runs `algorithm` on `scene` and compares it with `gl_image`, the scene under GL's rules
// (with owners: Framebuffer::owner filled, single-sample). Throws TeachError when the scene
// holds nothing the algorithm draws.
TeachResult teach(const Scene& scene, std::string_view algorithm,
                  const refraster::Framebuffer& gl_image);

// Two algorithms side by side: `a` (its image, steps and pseudo-code) with `b`'s image where
// GL's would be, both runs of one scene against one GL image. The differences are where the two
// light different pixels (or colour them differently), each with both runs' reasons against GL
// ("Bresenham's line algorithm: as GL; the DDA line: the rounding of ..."), so that the page
// says why each algorithm did what it did.
TeachResult teach_beside(const TeachResult& a, const TeachResult& b);

// The page's data (docs/teaching.md, "The teaching page"): the result, the scene's name and file
// and where the GL image came from.
nlohmann::json teach_json(const TeachResult& r, const Scene& scene, const std::string& scene_file,
                          const std::string& gl_source);

}  // namespace harness
