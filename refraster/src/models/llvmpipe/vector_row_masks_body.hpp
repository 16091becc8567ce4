// vector_row_masks_body.hpp: the row masks of a small box (RowMaskFn, row_block.hpp), a whole
// vector of a row's pixels at a time, written once over a vector type `V`.
//
// Included only by the translation units that compile it for one instruction set
// (vector_kernels_avx2.cpp, vector_kernels_avx512.cpp), after their target pragma and inside a
// namespace of their own; `V` provides lanes of int32 (I) with wrapping adds and products and
// the lanes' sign bits.
//
// Implements the test small_convex_rows applies pixel by pixel (traverse.hpp): pixel i of row
// r is covered iff q[k] + sx[k] * i + sy[k] * r >= 0 for every edge k, that is iff no edge's
// value has its sign bit set, so the OR of the edges' values tells it for a whole vector. The
// caller's int32 budget holds every value of the box exactly; lanes past the box's width
// (whose values may wrap around) are cut off by the width's mask.
//
// Deliberately does not: compute q or check the int32 budget (small_convex_rows does both).

template <class V, unsigned kEdges, std::size_t kChunks>
std::uint64_t row_masks_of(const std::int32_t* q, const std::int32_t* sx, const std::int32_t* sy,
                           int w, int h, std::uint64_t* rows) {
    using I = typename V::I;
    constexpr int kLanes = V::kLanes;
    // ramp[k][c]: sx * i for the pixels i of chunk c; value[k]: q + sy * r, in every lane.
    I ramp[kEdges][kChunks];
    I value[kEdges];
    I step[kEdges];
    for (unsigned k = 0; k < kEdges; ++k) {
        ramp[k][0] = V::mullo32(V::splati(sx[k]), V::lane_index_i());
        const I chunk = V::splati(
            static_cast<std::int32_t>(static_cast<std::uint32_t>(sx[k]) * std::uint32_t{kLanes}));
        for (std::size_t c = 1; c < kChunks; ++c) ramp[k][c] = V::add32(ramp[k][c - 1], chunk);
        value[k] = V::splati(q[k]);
        step[k] = V::splati(sy[k]);
    }
    const std::uint64_t full = w == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << w) - 1;
    std::uint64_t any = 0;
    for (int r = 0; r < h; ++r) {
        std::uint64_t outside = 0;
        for (std::size_t c = 0; c < kChunks; ++c) {
            I v = V::add32(value[0], ramp[0][c]);
            for (unsigned k = 1; k < kEdges; ++k) v = V::or_i(v, V::add32(value[k], ramp[k][c]));
            outside |= std::uint64_t{V::sign_bits(v)} << (c * std::size_t{kLanes});
        }
        const std::uint64_t m = ~outside & full;
        rows[r] = m;
        any |= m;
        for (unsigned k = 0; k < kEdges; ++k) value[k] = V::add32(value[k], step[k]);
    }
    return any;
}

// The instance for the box's number of vectors a row.
template <class V, unsigned kEdges, std::size_t kChunks = 1>
std::uint64_t row_masks_by_width(const std::int32_t* q, const std::int32_t* sx,
                                 const std::int32_t* sy, int w, int h, std::uint64_t* rows) {
    if constexpr (kChunks * V::kLanes < 64) {
        if (static_cast<std::size_t>(w) > kChunks * V::kLanes)
            return row_masks_by_width<V, kEdges, kChunks + 1>(q, sx, sy, w, h, rows);
    }
    return row_masks_of<V, kEdges, kChunks>(q, sx, sy, w, h, rows);
}

template <class V>
std::uint64_t vector_row_masks(const std::int32_t* q, const std::int32_t* sx,
                               const std::int32_t* sy, unsigned edges, int w, int h,
                               std::uint64_t* rows) {
    if (edges == 3) return row_masks_by_width<V, 3>(q, sx, sy, w, h, rows);
    return row_masks_by_width<V, 4>(q, sx, sy, w, h, rows);
}
