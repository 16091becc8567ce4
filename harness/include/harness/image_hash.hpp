// image_hash.hpp: a stable digest of a render's decoded pixels (colour and depth), for golden
// hashes that catch any change of the reference's output without a GL driver.
//
// Implements: 64-bit FNV-1a over the format, size, colour values (bytes, or float bit patterns)
// and depth values, written as 16 hex digits.
//
// Deliberately does not: hash files (image files carry metadata; pixels are what counts).
#pragma once

#include <string>

#include "refraster/framebuffer.hpp"

namespace harness {

std::string image_hash(const refraster::Framebuffer& fb);

// A render's digest: of every sample for a 4x target (the resolve follows from them), of the
// image otherwise, so that single-sample digests are those of image_hash.
std::string render_hash(const refraster::Framebuffer& image, const refraster::Framebuffer& samples);

}  // namespace harness
