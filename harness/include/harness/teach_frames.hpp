// teach_frames.hpp: a `refraster teach` run's steps as pictures for a lecture.
//
// Implements: the frame of a step, as the teaching page draws the algorithm's image in step
// mode (teach_page.hpp): every pixel as the steps up to this one have decided it (undecided dark,
// decided as bright as its weight, considered and rejected dark red), the pixel grid at a zoom
// of 4 and more, the input geometry (one colour per role, in the page's order), the step's own
// pixels outlined (yellow; dashed red when rejected) and its construction (pink). Each frame is
// an SVG (with the step's number and title under the picture, for a slide) and an RGBA8 image
// (the picture alone, for an animation or a slide that takes bitmaps).
//
// Deliberately does not: write files (the tool does), draw GL's image or the difference mask
// (the page and the PNGs of `teach` hold them), or antialias the raster frames' lines.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "harness/teach.hpp"
#include "refraster/framebuffer.hpp"

namespace harness {

// The most frames one run writes: a lecture's animation or handout, and a bound on the files
// and the time (each frame costs its zoomed picture's pixels).
inline constexpr std::size_t kMaxTeachFrames = 500;

class TeachFrames {
  public:
    // Frames of `r`'s steps at `zoom` screen pixels a pixel (1 to 64).
    TeachFrames(const TeachResult& r, int zoom);

    std::size_t steps() const { return steps_.size(); }
    // Moves to step k (0-based; any order, replaying from the start when going back).
    void seek(std::size_t k);
    // The current step's frame.
    std::string svg() const;
    refraster::Framebuffer image() const;

  private:
    const TeachResult& r_;
    const std::vector<refraster::textbook::Step>& steps_;
    int zoom_;
    std::vector<std::string> roles_;  // input roles in order of first appearance
    std::vector<double> state_;       // per pixel: -1 undecided, else the weight
    std::size_t at_ = 0;
    bool started_ = false;
    refraster::Framebuffer underlay_;  // grid and input geometry, drawn once (alpha 0 elsewhere)
};

}  // namespace harness
