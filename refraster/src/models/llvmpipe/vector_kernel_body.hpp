// vector_kernel_body.hpp: the vector fragment kernel, written once over a vector type `V`.
//
// Included only by the translation units that compile it for one instruction set
// (vector_kernels_avx2.cpp, vector_kernels_avx512.cpp), after their target pragma and inside a
// namespace of their own; `V` provides lanes of float (F), of int32 (I) and a lane mask (M).
//
// Implements, for every lane, the scalar model's pixel (fragment.cpp, Kernel::shade_pixel):
//   z = clamp(plane_z(px, py) + offset)  [lp_bld_interp.c attribs_update_simple: fmuladd(dady,
//        py, fmuladd(dadx, px, a0)), fused iff the profile fuses; lp_build_depth_clamp: min
//        with 1 then max with 0, minps/maxps semantics]
//   depth value: RNE(z * (2^n - 1)) for z16/z24, z's bits for z32f; test by the draw's mask of
//        passing outcomes, then the write
//   colour: flat (converted once), noperspective (the plane), smooth (the plane times
//        1 / plane_w, a true division); rgba8 by clamp and RNE(c * 255) (lp_build_conv)
//   blending: none, alpha as (x*y + ((x*y) >> 8) + 128) >> 8 per channel with a saturating
//        add (lp_build_mul_norm), add as a saturating add
// Pixels in the same lanes never depend on each other, so evaluating a whole vector when some
// lanes are not covered or fail the depth test writes the same bytes: only covered lanes that
// pass are stored.
//
// 4x targets with multisampling on (shade_rows_4x, the scalar Kernel::shade_4x): the colour
// once a pixel at its centre, then per sample the depth at the sample's position, the test,
// blending and stores. A pixel's four samples lie side by side in memory (framebuffer.hpp), so
// each vector of the sample stages holds kLanes / 4 pixels' samples, lane l sample l % 4 of
// pixel l / 4, and the pixels' colours are permuted into it.
//
// Blocks of thin primitives, whose rows hold a pixel or two (shade_packed): the covered pixels
// packed across rows, kLanes a vector, each lane at its own pixel's px and py, the buffers read
// by gathers and written by scatters (AVX2: lane by lane).
//
// Deliberately does not: rgba32f targets, or draws that turn multisampling off on a 4x target
// (the scalar kernels serve both).

template <class V, ShadeModel S, DepthFormat D, BlendPreset B>
struct VectorKernel {
    using F = typename V::F;
    using I = typename V::I;
    using M = typename V::M;
    static constexpr int kLanes = V::kLanes;
    static_assert(64 % kLanes == 0, "a row mask splits into whole vectors");

    struct PlaneV {
        F a0, dx, dy;
    };
    static PlaneV splat(const Plane& p) {
        return {V::splat(p.a0), V::splat(p.dadx), V::splat(p.dady)};
    }
    [[gnu::always_inline]] static F at(const PlaneV& p, F px, F py, bool fma) {
        return with_row(p, column_part(p, px, fma), py, fma);
    }
    // `at` in two steps: the part that depends on x alone, the same for every row of a block
    // (dadx * px + a0), then the row's (dady * py added to it); the same operations in the
    // same order, so the same bits.
    [[gnu::always_inline]] static F column_part(const PlaneV& p, F px, bool fma) {
        return fma ? V::fma(p.dx, px, p.a0) : V::add(V::mul(p.dx, px), p.a0);
    }
    [[gnu::always_inline]] static F with_row(const PlaneV& p, F column, F py, bool fma) {
        return fma ? V::fma(p.dy, py, column) : V::add(V::mul(p.dy, py), column);
    }
    // A float's bits as an int32 that orders as the float does (for non-NaN values): the
    // magnitude, negated for negative values, so that -0 and +0 are both 0.
    [[gnu::always_inline]] static I ordered_key(I bits) {
        const I magnitude = V::and_i(bits, V::splati(0x7fffffff));
        return V::select(V::lt_i(bits, V::splati(0)), magnitude, V::sub32(V::splati(0), magnitude));
    }
    // The same key for a value read under the CPU's denormals-are-zero mode: a denormal is 0.
    [[gnu::always_inline]] static I ordered_key_daz(I bits) {
        const I magnitude = V::and_i(bits, V::splati(0x7fffffff));
        return V::select(V::lt_i(magnitude, V::splati(0x00800000)), ordered_key(bits),
                         V::splati(0));
    }
    // color_to_unorm8: 0 unless c > 0 (NaN too), 255 from 1 on, RNE(c * 255) between.
    [[gnu::always_inline]] static I unorm8(F c) {
        const I v = V::to_int_rne(V::mul(c, V::splat(255.0f)));
        const I zero_below = V::select(V::gt_f(c, V::splat(0.0f)), V::splati(0), v);
        return V::select(V::ge_f(c, V::splat(1.0f)), zero_below, V::splati(255));
    }
    // unorm8_mul on 16-bit lanes holding one channel each.
    [[gnu::always_inline]] static I mul_norm16(I x, I y) {
        const I p = V::mullo16(x, y);
        return V::srl16(V::add16(V::add16(p, V::srl16(p, 8)), V::splat16(128)), 8);
    }
    [[gnu::always_inline]] static I blend(I s, I d) {
        if constexpr (B == BlendPreset::None) {
            (void)d;
            return s;
        } else if constexpr (B == BlendPreset::Add) {
            return V::adds_u8(s, d);
        } else {
            const I low_bytes = V::splati(0x00ff00ff);
            const I a = V::srl32(s, 24);
            const I a16 = V::or_i(a, V::sll32(a, 16));
            const I inv = V::sub16(V::splat16(255), a16);
            const I lo = V::min_u16(V::add16(mul_norm16(V::and_i(s, low_bytes), a16),
                                             mul_norm16(V::and_i(d, low_bytes), inv)),
                                    V::splat16(255));
            const I hi = V::min_u16(
                V::add16(mul_norm16(V::srl16(s, 8), a16), mul_norm16(V::srl16(d, 8), inv)),
                V::splat16(255));
            return V::or_i(lo, V::sll16(hi, 8));
        }
    }

    // The draw's depth test as the lanes read it.
    struct DepthTest {
        PlaneV zp;
        F z_offset;
        M want_lt, want_eq, want_gt;
        bool write;
        bool daz;  // compare z32f values as the CPU's denormals-are-zero mode reads them
    };
    static DepthTest depth_test_of(const KernelState& k, const Plane* planes,
                                   const SetupPrimitive& prim) {
        return {splat(planes[kZPlane]),
                V::splat(prim.z_offset),
                V::mask_if((k.depth_pass & 1u) != 0),
                V::mask_if((k.depth_pass & 2u) != 0),
                V::mask_if((k.depth_pass & 4u) != 0),
                k.depth_write,
                k.options.flush_denormals};
    }

    // The depth test of the lanes at (px, py) against dp[0..kLanes) (`inside`: every lane lies
    // in the row, else only `live` lanes are read and written): the live lanes that pass, their
    // depths written when the draw writes depth.
    [[gnu::always_inline]] static M depth_stage(const DepthTest& t, F px, F py, bool fma,
                                                std::uint32_t* dp, bool inside, M live) {
        return depth_stage_of(t, at(t.zp, px, py, fma), dp, inside, live);
    }
    // The same from the z plane's value at the lanes.
    [[gnu::always_inline]] static M depth_stage_of(const DepthTest& t, F z_plane, std::uint32_t* dp,
                                                   bool inside, M live) {
        const I value = depth_value(t, z_plane);
        const I stored = inside ? V::load(dp) : V::load_masked(dp, live);
        live = depth_passes(t, value, stored, live);
        if (t.write && !V::none(live)) {
            if (inside) {
                V::store(dp, V::select(live, stored, value));
            } else {
                V::store_masked(dp, live, value);
            }
        }
        return live;
    }
    // The depth value of the lanes from the z plane's value there.
    [[gnu::always_inline]] static I depth_value(const DepthTest& t, F z_plane) {
        F z = V::add(z_plane, t.z_offset);
        z = V::max(V::min(z, V::splat(1.0f)), V::splat(0.0f));
        if constexpr (D == DepthFormat::Z32f) {
            return V::as_int(z);
        } else {
            return V::to_int_rne(V::mul(z, V::splat(static_cast<float>(depth_unorm_max(D)))));
        }
    }
    // The live lanes whose depth value passes the test against the depth stored there.
    [[gnu::always_inline]] static M depth_passes(const DepthTest& t, I value, I stored, M live) {
        M lt, eq;
        if constexpr (D == DepthFormat::Z32f) {
            // Compared as integers ordered as the floats are (neither side is NaN; -0 equals
            // +0), a stored denormal (a cleared depth may be one) as 0 where the profile
            // flushes: llvmpipe compares under the rasterizer's denormals-are-zero mode
            // (fragment.cpp, depth_outcome).
            const I kz = t.daz ? ordered_key_daz(value) : ordered_key(value);
            const I ks = t.daz ? ordered_key_daz(stored) : ordered_key(stored);
            lt = V::lt_i(kz, ks);
            eq = V::eq_i(kz, ks);
        } else {
            // Values below 2^24: signed compares order them as unsigned ones.
            lt = V::lt_i(value, stored);
            eq = V::eq_i(value, stored);
        }
        const M pass = V::m_or(V::m_or(V::m_and(lt, t.want_lt), V::m_and(eq, t.want_eq)),
                               V::m_andnot(V::m_or(lt, eq), t.want_gt));
        return V::m_and(live, pass);
    }

    // The source colour `src` (packed rgba8) blended into cp[0..kLanes) in the live lanes, and
    // the owner written beside it (op, when the target records owners).
    [[gnu::always_inline]] static void color_stage(I src, std::uint32_t* cp, std::uint32_t* op,
                                                   I owner, bool inside, M live) {
        if constexpr (B == BlendPreset::None && V::kCheapMaskedStore) {
            // Replacing needs no destination: the store waits on no load of the line (measured
            // on medium triangles: a quarter of the kernel's samples were on that load).
            V::store_masked(cp, live, src);
            if (op != nullptr) V::store_masked(op, live, owner);
        } else if (inside) {
            const I dst = V::load(cp);
            V::store(cp, V::select(live, dst, blend(src, dst)));
            if (op != nullptr) V::store(op, V::select(live, V::load(op), owner));
        } else {
            if constexpr (B == BlendPreset::None) {
                V::store_masked(cp, live, src);
            } else {
                V::store_masked(cp, live, blend(src, V::load_masked(cp, live)));
            }
            if (op != nullptr) V::store_masked(op, live, owner);
        }
    }

    // A primitive's rows lie a framebuffer row apart in the depth and colour buffers (a page
    // apart at 1024 pixels), a stride the hardware prefetchers do not follow: the lines a row
    // covers are asked for kAhead rows ahead (measured on medium triangles on a loaded machine:
    // about 5% fewer profile samples in the kernel, 8 rows ahead slightly better than 4). A
    // prefetch changes no value.
    static constexpr int kAhead = 8;
    [[gnu::always_inline]] static void prefetch_row(const RowBlock& b, int r, Framebuffer& fb) {
        std::uint64_t pm = b.mask[r];
        for (int s = 1; s < b.samples; ++s) pm |= b.sample_rows(s)[r];
        if (pm == 0) return;
        const auto n = static_cast<std::size_t>(b.samples);
        const std::size_t row =
            static_cast<std::size_t>(b.y0 + r) * fb.width + static_cast<std::size_t>(b.x0);
        const std::size_t first = (row + static_cast<std::size_t>(std::countr_zero(pm))) * n;
        const std::size_t last =
            (row + static_cast<std::size_t>(63 - std::countl_zero(pm))) * n + (n - 1);
        if constexpr (D != DepthFormat::None) prefetch_pixels<1, 3>(fb.depth.data(), first, last);
        prefetch_pixels<1, 3>(reinterpret_cast<const std::uint32_t*>(fb.color8.data()), first,
                              last);
    }

    // Blocks of at least this many rows evaluate the planes' column parts once a block
    // (a full-screen primitive's 64-row tiles: 3 to 4% less time on all-pass full-screen
    // layers); shorter ones once a row, which measured faster on medium triangles, whose
    // blocks are a few runs by a few dozen rows.
    static constexpr int kColumnRows = 48;

    static void shade_rows(const KernelState& k, const SetupList& list, const SetupPrimitive& prim,
                           const RowBlock& b, Framebuffer& fb) {
        if (b.rows >= kColumnRows) {
            shade_block<true>(k, list, prim, b, fb);
            return;
        }
        if (b.rows <= kPackedCost) {  // one vector of pixels at least: never packed
            shade_block<false>(k, list, prim, b, fb);
            return;
        }
        int rows = 0;
        int pixels = 0;
        for (int r = 0; r < b.rows; ++r) {
            rows += b.mask[r] != 0 ? 1 : 0;
            pixels += bit_count(b.mask[r]);
        }
        if (pixels <= kPackedMax && (pixels + kLanes - 1) / kLanes * kPackedCost < rows &&
            fb.width * fb.height <= kPackedPixelsMax) {
            shade_packed(k, list, prim, b, fb);
        } else {
            shade_block<false>(k, list, prim, b, fb);
        }
    }

    // Thin primitives (lines one pixel wide, small points, tiny triangles) cover a pixel or two
    // a row, and a run a row evaluates a whole vector for each. A block whose covered pixels
    // fill fewer than 1 / kPackedCost as many vectors as it has covered rows packs its pixels
    // into the lanes, row after row, reads depths and colours by gathers and writes them by
    // scatters. A lane's px and py are its pixel's, so every value is the one the runs compute;
    // a primitive's pixels are distinct, so the order of their reads and writes changes
    // nothing.
    static constexpr int kPackedMax = 256;
    static constexpr int kPackedCost = 4;
    // Gathers and scatters index pixels with int32 lanes.
    static constexpr std::size_t kPackedPixelsMax = 0x7fffffff;

    static void shade_packed(const KernelState& k, const SetupList& list,
                             const SetupPrimitive& prim, const RowBlock& b, Framebuffer& fb) {
        alignas(64) std::int32_t xs[static_cast<std::size_t>(kPackedMax + kLanes)];
        alignas(64) std::int32_t ys[static_cast<std::size_t>(kPackedMax + kLanes)];
        int n = 0;
        for (int r = 0; r < b.rows; ++r) {
            prefetch_row(b, r, fb);
            for (std::uint64_t m = b.mask[r]; m != 0; m &= m - 1) {
                xs[n] = b.x0 + std::countr_zero(m);
                ys[n] = b.y0 + r;
                ++n;
            }
        }
        for (int i = n; i < n + kLanes; ++i) xs[i] = ys[i] = 0;  // lanes no mask selects

        const Plane* planes = list.planes.data() + prim.planes;
        const bool fma = k.options.fma;
        const DepthTest depth = depth_test_of(k, planes, prim);
        const Source source = source_of(planes, list.flat.data() + prim.flat);
        const I width = V::splati(static_cast<std::int32_t>(fb.width));
        auto* color = reinterpret_cast<std::uint32_t*>(fb.color8.data());
        for (int i = 0; i < n; i += kLanes) {
            const int count = std::min(kLanes, n - i);
            M live = V::from_bits(static_cast<unsigned>((std::uint64_t{1} << count) - 1));
            const I xi = V::load(reinterpret_cast<const std::uint32_t*>(xs + i));
            const I yi = V::load(reinterpret_cast<const std::uint32_t*>(ys + i));
            const F px = V::to_float(xi);
            const F py = V::to_float(yi);
            const I at = V::add32(V::mullo32(yi, width), xi);
            if constexpr (D != DepthFormat::None) {
                const I value = depth_value(depth, VectorKernel::at(depth.zp, px, py, fma));
                live = depth_passes(depth, value, V::gather(fb.depth.data(), at, live), live);
                if (V::none(live)) continue;
                if (depth.write) V::scatter(fb.depth.data(), at, live, value);
            }
            const I src = source_color(source, px, py, fma);
            if constexpr (B == BlendPreset::None) {
                V::scatter(color, at, live, src);
            } else {
                V::scatter(color, at, live, blend(src, V::gather(color, at, live)));
            }
            if (!fb.owner.empty())
                V::scatter(fb.owner.data(), at, live,
                           V::splati(static_cast<std::int32_t>(prim.owner)));
        }
    }

    template <bool kColumns>
    [[gnu::always_inline]] static void shade_block(const KernelState& k, const SetupList& list,
                                                   const SetupPrimitive& prim, const RowBlock& b,
                                                   Framebuffer& fb) {
        const Plane* planes = list.planes.data() + prim.planes;
        const float* flat = list.flat.data() + prim.flat;
        const bool fma = k.options.fma;
        const bool owners = !fb.owner.empty();
        const auto width = static_cast<std::int32_t>(fb.width);
        const DepthTest depth = depth_test_of(k, planes, prim);
        const Source source = source_of(planes, flat);
        const I owner = V::splati(static_cast<std::int32_t>(prim.owner));
        const F lanes = V::lane_index();
        constexpr std::uint64_t kLaneBits = (std::uint64_t{1} << kLanes) - 1;

        // The planes' column parts (column_part) of each run of kLanes pixels some row of the
        // block covers, once a block instead of once a row.
        Columns columns[kColumns ? kRuns : 1];  // only the covered runs are written and read
        if constexpr (kColumns) {
            std::uint64_t covered = 0;
            for (int r = 0; r < b.rows; ++r) covered |= b.mask[r];
            for (std::size_t run = 0; run < kRuns; ++run) {
                const int first = static_cast<int>(run) * kLanes;
                if (((covered >> first) & kLaneBits) == 0) continue;
                const F px = V::add(V::splat(static_cast<float>(b.x0 + first)), lanes);
                if constexpr (D != DepthFormat::None)
                    columns[run].z = column_part(depth.zp, px, fma);
                source_columns(source, px, fma, columns[run]);
            }
        }

        for (int r = 0; r < kAhead && r < b.rows; ++r) prefetch_row(b, r, fb);
        for (int r = 0; r < b.rows; ++r) {
            if (r + kAhead < b.rows) prefetch_row(b, r + kAhead, fb);
            std::uint64_t m = b.mask[r];
            if (m == 0) continue;
            const std::int32_t y = b.y0 + r;
            const F py = V::splat(static_cast<float>(y));
            const std::size_t row = static_cast<std::size_t>(y) * fb.width;
            std::uint32_t* depth_row = fb.depth.empty() ? nullptr : fb.depth.data() + row;
            auto* color_row = reinterpret_cast<std::uint32_t*>(fb.color8.data()) + row;
            std::uint32_t* owner_row = owners ? fb.owner.data() + row : nullptr;
            while (m != 0) {
                const int base = std::countr_zero(m) & ~(kLanes - 1);
                const auto bits = static_cast<unsigned>((m >> base) & kLaneBits);
                m &= ~(kLaneBits << base);
                const std::int32_t x = b.x0 + base;
                // Lanes past the row's end are never covered; their memory is not touched.
                const bool inside = x + kLanes <= width;
                M live = V::from_bits(bits);
                I src;
                if constexpr (kColumns) {
                    const Columns& column = columns[static_cast<std::size_t>(base / kLanes)];
                    if constexpr (D != DepthFormat::None) {
                        live = depth_stage_of(depth, with_row(depth.zp, column.z, py, fma),
                                              depth_row + x, inside, live);
                        if (V::none(live)) continue;
                    }
                    src = source_color_of(source, column, py, fma);
                } else {
                    const F px = V::add(V::splat(static_cast<float>(x)), lanes);
                    if constexpr (D != DepthFormat::None) {
                        live = depth_stage(depth, px, py, fma, depth_row + x, inside, live);
                        if (V::none(live)) continue;
                    }
                    src = source_color(source, px, py, fma);
                }
                color_stage(src, color_row + x, owners ? owner_row + x : nullptr, owner, inside,
                            live);
            }
        }
    }

    // The source colours of the pixels (x .. x + kLanes - 1, y) as packed rgba8, evaluated at
    // (px, py) (flat: the primitive's, converted once).
    struct PlanesSource {
        PlaneV wp;
        PlaneV cp[4];
    };
    struct FlatSource {
        I flat_color;
    };
    using Source = std::conditional_t<S == ShadeModel::Flat, FlatSource, PlanesSource>;
    // Each member set by vector moves (a value-initialized Source is cleared by a string
    // store first, which small primitives noticed).
    [[gnu::always_inline]] static Source source_of(const Plane* planes, const float* flat) {
        Source src;
        if constexpr (S != ShadeModel::Flat) {
            src.wp = splat(planes[kWPlane]);
            for (std::size_t j = 0; j < 4; ++j) src.cp[j] = splat(planes[kFirstAttributePlane + j]);
        } else {
            // Converted once per primitive, as the scalar model does (with the same results
            // under the CPU's denormal modes: a denormal channel becomes 0 either way).
            std::uint32_t packed = 0;
            for (std::size_t j = 0; j < 4; ++j)
                packed |= std::uint32_t{color_to_unorm8(flat[j])} << (8 * j);
            src.flat_color = V::splati(static_cast<std::int32_t>(packed));
        }
        return src;
    }
    // A run's column parts (column_part): z, then 1 / w's and the colours' planes as
    // source_color reads them.
    static constexpr std::size_t kRuns = 64 / kLanes;
    static constexpr std::size_t kColourPlanes = S == ShadeModel::Smooth ? 5 : 4;
    struct Columns {
        F z;
        F c[kColourPlanes];  // smooth: w, r, g, b, a; noperspective: r, g, b, a; flat: unused
    };
    [[gnu::always_inline]] static void source_columns(const Source& src, F px, bool fma,
                                                      Columns& out) {
        if constexpr (S == ShadeModel::Smooth) {
            out.c[0] = column_part(src.wp, px, fma);
            for (int j = 0; j < 4; ++j) out.c[1 + j] = column_part(src.cp[j], px, fma);
        } else if constexpr (S == ShadeModel::NoPerspective) {
            for (int j = 0; j < 4; ++j) out.c[j] = column_part(src.cp[j], px, fma);
        }
    }
    // source_color from a run's column parts at row py.
    [[gnu::always_inline]] static I source_color_of(const Source& src, const Columns& col, F py,
                                                    bool fma) {
        if constexpr (S == ShadeModel::Flat) {
            return src.flat_color;
        } else {
            F c[4];
            if constexpr (S == ShadeModel::Smooth) {
                const F w = V::div(V::splat(1.0f), with_row(src.wp, col.c[0], py, fma));
                for (int j = 0; j < 4; ++j)
                    c[j] = V::mul(with_row(src.cp[j], col.c[1 + j], py, fma), w);
            } else {
                for (int j = 0; j < 4; ++j) c[j] = with_row(src.cp[j], col.c[j], py, fma);
            }
            return pack_unorm8(c);
        }
    }
    [[gnu::always_inline]] static I source_color(const Source& src, F px, F py, bool fma) {
        if constexpr (S == ShadeModel::Flat) {
            return src.flat_color;
        } else {
            F c[4];
            if constexpr (S == ShadeModel::Smooth) {
                const F w = V::div(V::splat(1.0f), at(src.wp, px, py, fma));
                for (int j = 0; j < 4; ++j) c[j] = V::mul(at(src.cp[j], px, py, fma), w);
            } else {
                for (int j = 0; j < 4; ++j) c[j] = at(src.cp[j], px, py, fma);
            }
            return pack_unorm8(c);
        }
    }

    // A 4x target, multisampling on: kLanes pixels of a row at a time, their samples in
    // kGroups vectors of kGroupPixels pixels each.
    static constexpr int kGroupPixels = kLanes / static_cast<int>(kMsaaSamples);
    static constexpr std::size_t kGroups = kMsaaSamples;
    static constexpr auto kN = static_cast<std::size_t>(kLanes);
    // Lane l of a sample vector: bit l of its mask is sample l % 4 of pixel l / 4; sample 0 of
    // each of a run's kLanes pixels, four bits apart.
    static constexpr std::uint64_t kSample0Bits = kLanes == 16 ? 0x1111111111111111u : 0x11111111u;
    static_assert(kLanes == 8 || kLanes == 16, "two or four pixels' samples a vector");

    static void shade_rows_4x(const KernelState& k, const SetupList& list,
                              const SetupPrimitive& prim, const RowBlock& b, Framebuffer& fb) {
        const Plane* planes = list.planes.data() + prim.planes;
        const float* flat = list.flat.data() + prim.flat;
        const bool fma = k.options.fma;
        const bool owners = !fb.owner.empty();
        const auto width = static_cast<std::int32_t>(fb.width);
        const DepthTest depth = depth_test_of(k, planes, prim);
        const Source source = source_of(planes, flat);
        const I owner = V::splati(static_cast<std::int32_t>(prim.owner));
        // Colour at the pixel centre: px + 0.5 (planes set up without the pixel offset, as the
        // scalar model evaluates them: fragment.cpp shade_4x); every value here is exact.
        const F centre_x = V::add(V::lane_index(), V::splat(0.5f));
        // Depth at the sample: px + sx, py + sy (samples.hpp: multiples of 1/8, exact).
        alignas(64) float sample_x[kN];
        alignas(64) float sample_y[kN];
        alignas(64) std::uint32_t pick[kGroups][kN];
        for (std::size_t l = 0; l < kN; ++l) {
            const auto& pos = kSamplePositions4x[l % kMsaaSamples];
            const std::size_t pixel = l / kMsaaSamples;  // the lane's pixel in its group
            sample_x[l] = static_cast<float>(pixel) + pos.x;
            sample_y[l] = pos.y;
            for (std::size_t g = 0; g < kGroups; ++g)
                pick[g][l] = static_cast<std::uint32_t>(g * (kN / kMsaaSamples) + l / kMsaaSamples);
        }
        const F sample_dx = V::load_f(sample_x);
        const F sample_dy = V::load_f(sample_y);
        I group_pick[kGroups];
        for (std::size_t g = 0; g < kGroups; ++g) group_pick[g] = V::load(pick[g]);
        constexpr std::uint64_t kLaneBits = (std::uint64_t{1} << kLanes) - 1;
        const std::uint64_t* sample_rows[kMsaaSamples];
        for (int s = 0; s < static_cast<int>(kMsaaSamples); ++s) sample_rows[s] = b.sample_rows(s);

        for (int r = 0; r < kAhead && r < b.rows; ++r) prefetch_row(b, r, fb);
        for (int r = 0; r < b.rows; ++r) {
            if (r + kAhead < b.rows) prefetch_row(b, r + kAhead, fb);
            const std::uint64_t m[kMsaaSamples] = {sample_rows[0][r], sample_rows[1][r],
                                                   sample_rows[2][r], sample_rows[3][r]};
            std::uint64_t u = m[0] | m[1] | m[2] | m[3];
            if (u == 0) continue;
            const std::int32_t y = b.y0 + r;
            const float fy = static_cast<float>(y);
            const F py_centre = V::splat(fy + 0.5f);
            const F py_sample = V::add(V::splat(fy), sample_dy);
            const std::size_t row = static_cast<std::size_t>(y) * fb.width * kMsaaSamples;
            std::uint32_t* depth_row = fb.depth.empty() ? nullptr : fb.depth.data() + row;
            auto* color_row = reinterpret_cast<std::uint32_t*>(fb.color8.data()) + row;
            std::uint32_t* owner_row = owners ? fb.owner.data() + row : nullptr;
            while (u != 0) {
                const int base = std::countr_zero(u) & ~(kLanes - 1);
                u &= ~(kLaneBits << base);
                const std::int32_t x = b.x0 + base;
                M live[kGroups];
                bool any = false;
                // Bit 4i + s: sample s of pixel x + i; group g's lanes are its bits from
                // g * kLanes on.
                std::uint64_t samples = 0;
                for (unsigned s = 0; s < kMsaaSamples; ++s)
                    samples |= _pdep_u64((m[s] >> base) & kLaneBits, kSample0Bits) << s;
                for (std::size_t g = 0; g < kGroups; ++g) {
                    const auto bits = static_cast<unsigned>((samples >> (g * kLanes)) & kLaneBits);
                    live[g] = V::from_bits(bits);
                    if (bits == 0) continue;
                    if constexpr (D != DepthFormat::None) {
                        const std::int32_t xg = x + static_cast<int>(g) * kGroupPixels;
                        const F px = V::add(V::splat(static_cast<float>(xg)), sample_dx);
                        live[g] = depth_stage(depth, px, py_sample, fma,
                                              depth_row + static_cast<std::size_t>(xg) * 4,
                                              xg + kGroupPixels <= width, live[g]);
                        if (V::none(live[g])) continue;
                    }
                    any = true;
                }
                if (!any) continue;
                const F px_centre = V::add(V::splat(static_cast<float>(x)), centre_x);
                const I src = source_color(source, px_centre, py_centre, fma);
                for (std::size_t g = 0; g < kGroups; ++g) {
                    if (V::none(live[g])) continue;
                    const std::int32_t xg = x + static_cast<int>(g) * kGroupPixels;
                    const std::size_t at_sample = static_cast<std::size_t>(xg) * 4;
                    color_stage(V::permute(src, group_pick[g]), color_row + at_sample,
                                owners ? owner_row + at_sample : nullptr, owner,
                                xg + kGroupPixels <= width, live[g]);
                }
            }
        }
    }

    // Four channels as packed rgba8 (color_to_unorm8 of each).
    [[gnu::always_inline]] static I pack_unorm8(const F* c) {
        return V::or_i(V::or_i(unorm8(c[0]), V::sll32(unorm8(c[1]), 8)),
                       V::or_i(V::sll32(unorm8(c[2]), 16), V::sll32(unorm8(c[3]), 24)));
    }
};

// The kernel for a draw's state, as a function pointer.
// `samples`: 1, or 4 (shade_rows_4x).
template <class V>
FragmentKernel::ShadeRowsFn pick_vector_kernel(ShadeModel s, DepthFormat d, BlendPreset b,
                                               unsigned samples) {
    const auto by_blend = [&]<ShadeModel kS, DepthFormat kD>() -> FragmentKernel::ShadeRowsFn {
        const auto of = [&]<BlendPreset kB>() -> FragmentKernel::ShadeRowsFn {
            using K = VectorKernel<V, kS, kD, kB>;
            return samples == kMsaaSamples ? &K::shade_rows_4x : &K::shade_rows;
        };
        switch (b) {
            case BlendPreset::None:
                return of.template operator()<BlendPreset::None>();
            case BlendPreset::Alpha:
                return of.template operator()<BlendPreset::Alpha>();
            case BlendPreset::Add:
                return of.template operator()<BlendPreset::Add>();
        }
        return nullptr;
    };
    const auto by_depth = [&]<ShadeModel kS>() -> FragmentKernel::ShadeRowsFn {
        switch (d) {
            case DepthFormat::None:
                return by_blend.template operator()<kS, DepthFormat::None>();
            case DepthFormat::Z16:
                return by_blend.template operator()<kS, DepthFormat::Z16>();
            case DepthFormat::Z24:
                return by_blend.template operator()<kS, DepthFormat::Z24>();
            case DepthFormat::Z32f:
                return by_blend.template operator()<kS, DepthFormat::Z32f>();
        }
        return nullptr;
    };
    switch (s) {
        case ShadeModel::Flat:
            return by_depth.template operator()<ShadeModel::Flat>();
        case ShadeModel::Smooth:
            return by_depth.template operator()<ShadeModel::Smooth>();
        case ShadeModel::NoPerspective:
            return by_depth.template operator()<ShadeModel::NoPerspective>();
    }
    return nullptr;
}
