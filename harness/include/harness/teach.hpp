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
    std::vector<std::string> notes;
    std::string summary;
};

// Runs `algorithm` on `scene` and compares it with `gl_image`, the scene under GL's rules
// (with owners: Framebuffer::owner filled, single-sample). Throws TeachError when the scene
// holds nothing the algorithm draws.
TeachResult teach(const Scene& scene, std::string_view algorithm,
                  const refraster::Framebuffer& gl_image);

// The page's data (docs/teaching.md, "The teaching page"): the result, the scene's name and file
// and where the GL image came from.
nlohmann::json teach_json(const TeachResult& r, const Scene& scene, const std::string& scene_file,
                          const std::string& gl_source);

}  // namespace harness
