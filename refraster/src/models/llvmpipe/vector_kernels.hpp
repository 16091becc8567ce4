// vector_kernels.hpp: the per-pixel stage many pixels at a time, for the CPUs that have the
// instructions, chosen at run time.
//
// Implements: the choice of a vector fragment kernel (8 lanes with AVX2 and FMA, 16 with
// AVX-512) for a draw's state, the CPU checks behind that choice, and the floating-point mode
// the kernels run under. A vector kernel reads row blocks (row_block.hpp) of a single-sample or 4x
// rgba8 target and performs, lane by lane, exactly the float operations of the scalar model
// (fragment.cpp, Kernel): the same planes evaluated in the same order, fused exactly where
// the profile fuses, the same clamps, roundings and integer blending. Denormals are flushed
// by the CPU itself (MXCSR flush-to-zero and denormals-are-zero, as llvmpipe's rasterizer
// threads run, lp_rast.c util_fpstate_set_denorms_to_zero) where the profile flushes; the
// scalar model emulates the same modes operation by operation (float_ops.hpp).
//
// Textured draws have a kernel of their own (vector_texture_body.hpp) where llvmpipe samples on
// its 8-bit path.
//
// Deliberately does not: rgba32f targets, textured draws on 4x targets, or draws that turn
// multisampling off on a 4x target (the scalar kernels serve them), or
// compile anything for an instruction set at build time: every vector kernel is compiled for
// its target with a function-level target and called only when the CPU reports it.
#pragma once

#include <cstdint>

#include "common/cpu.hpp"
#include "models/llvmpipe/fragment.hpp"

namespace refraster::detail {

// The vector kernel for `path` (Avx2 or Avx512; Fastest takes the widest this CPU runs) and
// the draw's state on an rgba8 target of `samples` samples (1, or 4 for an untextured draw with
// multisampling on: the kernel then reads 4x row blocks); nullptr when the path is not a vector
// path or the CPU lacks its instructions.
FragmentKernel::ShadeRowsFn vector_shade_rows(KernelPath path, ShadeModel shade, DepthFormat depth,
                                              BlendPreset blend, unsigned samples = 1);

// The textured vector kernel (vector_texture_body.hpp) for `path` and the draw's state on an
// rgba8 single-sample target, for a texture unit the vector sampler serves
// (vector_sampler_serves); nullptr as above.
FragmentKernel::ShadeRowsFn vector_textured_shade_rows(KernelPath path, ShadeModel shade,
                                                       DepthFormat depth, BlendPreset blend);

// Whether the vector sampler reproduces the scalar sampler for this unit: the 8-bit path, the
// levels packed, exact rho, no brilinear blend, and not point sprite coordinates.
bool vector_sampler_serves(const TextureUnit& unit, bool point_coords);

// The vector row-mask builder (RowMaskFn, row_block.hpp) of `path` (as above); nullptr when
// the path is not a vector path or the CPU lacks its instructions: small_convex_rows then
// steps the rows itself.
RowMaskFn vector_row_masks(KernelPath path);

}  // namespace refraster::detail
