// vector_kernels.cpp: which vector kernel runs (the CPU checks behind it: common/cpu.cpp).
#include "models/llvmpipe/vector_kernels.hpp"

namespace refraster::detail {

FragmentKernel::ShadeRowsFn avx2_shade_rows(ShadeModel s, DepthFormat d, BlendPreset b,
                                            unsigned samples);
FragmentKernel::ShadeRowsFn avx512_shade_rows(ShadeModel s, DepthFormat d, BlendPreset b,
                                              unsigned samples);
FragmentKernel::ShadeRowsFn avx2_textured_shade_rows(ShadeModel s, DepthFormat d, BlendPreset b);
FragmentKernel::ShadeRowsFn avx512_textured_shade_rows(ShadeModel s, DepthFormat d, BlendPreset b);
RowMaskFn avx2_row_masks();
RowMaskFn avx512_row_masks();

#if !REFRASTER_VECTOR_KERNELS
// No vector kernels in this build: resolve_kernel_path never picks them.
FragmentKernel::ShadeRowsFn avx2_shade_rows(ShadeModel, DepthFormat, BlendPreset, unsigned) {
    return nullptr;
}
FragmentKernel::ShadeRowsFn avx512_shade_rows(ShadeModel, DepthFormat, BlendPreset, unsigned) {
    return nullptr;
}
FragmentKernel::ShadeRowsFn avx2_textured_shade_rows(ShadeModel, DepthFormat, BlendPreset) {
    return nullptr;
}
FragmentKernel::ShadeRowsFn avx512_textured_shade_rows(ShadeModel, DepthFormat, BlendPreset) {
    return nullptr;
}
RowMaskFn avx2_row_masks() {
    return nullptr;
}
RowMaskFn avx512_row_masks() {
    return nullptr;
}
#endif

FragmentKernel::ShadeRowsFn vector_shade_rows(KernelPath path, ShadeModel shade, DepthFormat depth,
                                              BlendPreset blend, unsigned samples) {
    switch (resolve_kernel_path(path)) {
        case KernelPath::Avx512:
            return avx512_shade_rows(shade, depth, blend, samples);
        case KernelPath::Avx2:
            return avx2_shade_rows(shade, depth, blend, samples);
        default:
            return nullptr;
    }
}

FragmentKernel::ShadeRowsFn vector_textured_shade_rows(KernelPath path, ShadeModel shade,
                                                       DepthFormat depth, BlendPreset blend) {
    switch (resolve_kernel_path(path)) {
        case KernelPath::Avx512:
            return avx512_textured_shade_rows(shade, depth, blend);
        case KernelPath::Avx2:
            return avx2_textured_shade_rows(shade, depth, blend);
        default:
            return nullptr;
    }
}

bool vector_sampler_serves(const TextureUnit& unit, bool point_coords) {
    return unit.aos && unit.packed != nullptr && !unit.rho_approx && !unit.brilinear &&
           !point_coords;
}

RowMaskFn vector_row_masks(KernelPath path) {
    switch (resolve_kernel_path(path)) {
        case KernelPath::Avx512:
            return avx512_row_masks();
        case KernelPath::Avx2:
            return avx2_row_masks();
        default:
            return nullptr;
    }
}

}  // namespace refraster::detail
