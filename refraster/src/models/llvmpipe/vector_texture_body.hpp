// vector_texture_body.hpp: the textured vector fragment kernel, written once over a vector type
// `V`, for draws that llvmpipe samples on its 8-bit path.
//
// Included only by the translation units that compile it for one instruction set
// (vector_kernels_avx2.cpp, vector_kernels_avx512.cpp), after vector_kernel_body.hpp, whose
// depth test, blending and stores it shares.
//
// Implements, for every lane, the scalar model's textured pixel (fragment.cpp,
// Kernel::textured_quad and shade_pixel_colored; texture.cpp, the 8-bit path):
//   coordinates: s = a4 * (1 / a7), t = a5 * (1 / a7) (textureProj; lp_build_rcp, a true
//        division), the attributes evaluated as the colour's are (flat, noperspective, or the
//        plane times 1 / plane_w)
//   level of detail: the quad's, from its pixels 0, 1 and 2 (lp_build_rho, rho squared exact;
//        lp_build_lod_selector): every lane evaluates the coordinates of its own quad's pixels,
//        at (x & ~1, y & ~1), (x | 1, y & ~1) and (x & ~1, y | 1). A helper pixel's coordinates
//        are the planes' values at its position whatever the coverage, so a lane computes
//        exactly what the quad shares. Lanes are laid out from an even x, so that the pixels of
//        a quad's row sit in lanes 2k and 2k + 1: the row of y & ~1 and the row of y | 1 are
//        each evaluated once, and each lane reads its quad's values from them.
//   min or mag filter per quad, nearest mip level from the exponent of rho squared, or two
//        levels and their weight from lp_build_fast_log2, clamped (split_levels)
//   per axis: nearest texel floor(u * n) wrapped, or 8.8 fixed point cvtps2dq(u * 256n) - 128
//        with repeat (power of two or not) or clamp to edge; texels gathered from the packed
//        levels (PackedLevels), the lerps a + ((w * (b - a) + 128) >> 8) computed as llvmpipe's
//        pmulhrsw computes them on 16-bit lanes, along s, then t, then between the levels
//   colour: the texel bytes times 1/255 in float, times the interpolated colour (modulate),
//        converted to rgba8, blended and stored as the untextured kernel does
// The depth test runs first: a vector whose lanes all fail samples nothing. Lanes never depend
// on one another, so the stored bytes are the model's.
//
// Deliberately does not: the float sampling path (wraps other than repeat and clamp to edge,
// or texture_filtering=float), the profile's approximate rho or brilinear blend, point sprite
// coordinates, or 4x and rgba32f targets: choose_fragment_kernel keeps those on the scalar
// kernels.

template <class V, ShadeModel S, DepthFormat D, BlendPreset B>
struct VectorTexturedKernel {
    using Base = VectorKernel<V, S, D, B>;
    using F = typename V::F;
    using I = typename V::I;
    using M = typename V::M;
    using PlaneV = typename Base::PlaneV;
    static constexpr int kLanes = V::kLanes;

    // The draw's texture unit as the lanes read it.
    struct Unit {
        const std::uint32_t* texels;
        const std::int32_t* offset;
        const std::int32_t* width;
        const std::int32_t* height;
        bool single_level;  // only level 0 is ever read
        I width0, height0;
        bool pot_s, pot_t;
        TextureWrap wrap_s, wrap_t;
        bool needs_lod, mipmapped, nearest_level;
        std::int32_t last;
        bool min_linear, mag_linear;
        F base_width, base_height;
        bool modulate;
    };

    static bool is_linear(TextureFilter f) {
        return f == TextureFilter::Linear || f == TextureFilter::LinearMipmapNearest ||
               f == TextureFilter::LinearMipmapLinear;
    }

    static Unit unit_of(const TextureUnit& t) {
        const PackedLevels& p = *t.packed;
        Unit u{};
        u.texels = p.texels.data();
        u.offset = p.offset.data();
        u.width = p.width.data();
        u.height = p.height.data();
        u.single_level = !t.mipmapped;
        u.width0 = V::splati(p.width[0]);
        u.height0 = V::splati(p.height[0]);
        u.pot_s = t.pot_s;
        u.pot_t = t.pot_t;
        u.wrap_s = t.state.wrap_s;
        u.wrap_t = t.state.wrap_t;
        u.needs_lod = t.needs_lod;
        u.mipmapped = t.mipmapped;
        u.nearest_level = t.state.min_filter == TextureFilter::NearestMipmapNearest ||
                          t.state.min_filter == TextureFilter::LinearMipmapNearest;
        u.last = static_cast<std::int32_t>(t.last_level);
        u.min_linear = is_linear(t.state.min_filter);
        u.mag_linear = is_linear(t.state.mag_filter);
        u.base_width = V::splat(t.base_width);
        u.base_height = V::splat(t.base_height);
        u.modulate = t.state.env == TextureEnv::Modulate;
        return u;
    }

    // lp_build_ifloor with SSE4.1 rounding: cvttps2dq of the floor (INT32_MIN where it does
    // not fit, as texture.cpp's ifloor gives it).
    [[gnu::always_inline]] static I ifloor(F x) { return V::to_int_trunc(V::floor(x)); }
    [[gnu::always_inline]] static I clamp_i(I v, I lo, I hi) {
        return V::min_i32(V::max_i32(v, lo), hi);
    }

    // texture.cpp nearest_repeat_or_edge, for a lane's level size n.
    [[gnu::always_inline]] static I nearest_axis(F u, I n, bool pot, TextureWrap wrap) {
        const F nf = V::to_float(n);
        const I one = V::splati(1);
        if (wrap == TextureWrap::Repeat) {
            if (pot) return V::and_i(ifloor(V::mul(u, nf)), V::sub32(n, one));
            // lp_build_fract_safe: the fraction, then minps(f, 1 - 2^-24) (a NaN fraction
            // becomes 1 - 2^-24).
            constexpr float kBelowOne = 0x1.fffffep-1f;
            const F f0 = V::sub(u, V::floor(u));
            const F f = V::select_f(V::lt_f(f0, V::splat(kBelowOne)), V::splat(kBelowOne), f0);
            return V::to_int_trunc(V::mul(f, nf));
        }
        return clamp_i(ifloor(V::mul(u, nf)), V::splati(0), V::sub32(n, one));
    }

    struct LinearAxis {
        I i0, i1, w;  // w: the weight in units of 1/256
    };
    // texture.cpp linear_aos (lp_build_sample_wrap_linear_int), for a lane's level size n.
    [[gnu::always_inline]] static LinearAxis linear_axis(F u, I n, bool pot, TextureWrap wrap) {
        const I one = V::splati(1);
        const I last = V::sub32(n, one);
        const I bias = V::splati(128);
        const I low_byte = V::splati(255);
        LinearAxis a;
        if (wrap == TextureWrap::Repeat && !pot) {
            // lp_build_coord_repeat_npot_linear_int: the fraction scaled by n, then by 256.
            const F f = V::sub(u, V::floor(u));
            const F scaled = V::mul(V::mul(f, V::to_float(n)), V::splat(256.0f));
            const I s = V::sub32(V::to_int_rne(scaled), bias);
            a.w = V::and_i(s, low_byte);
            I i0 = V::sra32(s, 8);
            i0 = V::select(V::lt_i(i0, V::splati(0)), i0, last);
            i0 = V::min_i32(i0, last);
            a.i0 = i0;
            a.i1 = V::select(V::eq_i(i0, last), V::add32(i0, one), V::splati(0));
            return a;
        }
        const F size256 = V::to_float(V::sll32(n, 8));  // exact: n <= 2^23
        const I s = V::sub32(V::to_int_rne(V::mul(u, size256)), bias);
        a.w = V::and_i(s, low_byte);
        const I i0 = V::sra32(s, 8);
        const I i1 = V::add32(i0, one);
        if (wrap == TextureWrap::Repeat) {
            a.i0 = V::and_i(i0, last);
            a.i1 = V::and_i(i1, last);
        } else {
            a.i0 = clamp_i(i0, V::splati(0), last);
            a.i1 = clamp_i(i1, V::splati(0), last);
        }
        return a;
    }

    // A level's size and place per lane (levels 0 to 15: PackedLevels::kMaxLevels).
    struct LevelLanes {
        I offset, width, height;
    };
    [[gnu::always_inline]] static LevelLanes level_lanes(const Unit& u, I level) {
        if (u.single_level) return {V::splati(0), u.width0, u.height0};
        return {V::lookup16(u.offset, level), V::lookup16(u.width, level),
                V::lookup16(u.height, level)};
    }

    // The texel (x, y) of a level in the live lanes; coordinates are clamped into the level
    // (texture.cpp LevelView::texel), which no wrap above leaves anyway.
    [[gnu::always_inline]] static I fetch(const Unit& u, const LevelLanes& l, I x, I y, M live) {
        const I zero = V::splati(0);
        const I one = V::splati(1);
        x = clamp_i(x, zero, V::sub32(l.width, one));
        y = clamp_i(y, zero, V::sub32(l.height, one));
        return V::gather(u.texels, V::add32(l.offset, V::add32(V::mullo32(y, l.width), x)), live);
    }

    // lerp8 of the four bytes of a and b with weight w (0 to 255) a lane: a + ((w * (b - a) +
    // 128) >> 8) per byte, on 16-bit lanes as pmulhrsw gives it: ((b - a) * (w << 7) + 2^14)
    // >> 15 is the same floor for |b - a| <= 255.
    [[gnu::always_inline]] static I lerp_bytes(I w, I a, I b) {
        const I w16 = V::sll16(V::or_i(w, V::sll32(w, 16)), 7);
        const I low = V::splati(0x00ff00ff);
        const I ae = V::and_i(a, low);
        const I be = V::and_i(b, low);
        const I ao = V::srl16(a, 8);
        const I bo = V::srl16(b, 8);
        const I re = V::add16(ae, V::mulhrs16(V::sub16(be, ae), w16));
        const I ro = V::add16(ao, V::mulhrs16(V::sub16(bo, ao), w16));
        return V::or_i(re, V::sll16(ro, 8));
    }

    // One level sampled at (s, t): rgba8 a lane (texture.cpp sample_level_aos).
    [[gnu::always_inline]] static I sample_level(const Unit& u, const LevelLanes& l, F s, F t,
                                                 bool linear, M live) {
        if (!linear) {
            return fetch(u, l, nearest_axis(s, l.width, u.pot_s, u.wrap_s),
                         nearest_axis(t, l.height, u.pot_t, u.wrap_t), live);
        }
        const LinearAxis x = linear_axis(s, l.width, u.pot_s, u.wrap_s);
        const LinearAxis y = linear_axis(t, l.height, u.pot_t, u.wrap_t);
        const I t00 = fetch(u, l, x.i0, y.i0, live);
        const I t10 = fetch(u, l, x.i1, y.i0, live);
        const I t01 = fetch(u, l, x.i0, y.i1, live);
        const I t11 = fetch(u, l, x.i1, y.i1, live);
        return lerp_bytes(y.w, lerp_bytes(x.w, t00, t10), lerp_bytes(x.w, t01, t11));
    }

    // Where the level of detail leads each lane: the levels, their weight in 1/256 (0 where
    // one level is read), and whether the quad takes the linear image filter.
    struct Lod {
        I level0, level1, frac8;
        M linear;
        bool two_levels;  // some lane blends two levels
    };

    // texture.cpp quad_lod with exact rho and no brilinear blend; sq and tq hold each lane's
    // quad's pixels 0, 1 and 2.
    [[gnu::always_inline]] static Lod lod_of(const Unit& u, const F* sq, const F* tq) {
        const I zero = V::splati(0);
        const M all = V::mask_if(true);
        Lod q{zero, zero, zero, V::mask_if(u.mag_linear), false};
        if (!u.needs_lod) return q;
        // Differences of the coordinates first, then scaled to base-level texels.
        const F dsdx = V::mul(u.base_width, V::sub(sq[1], sq[0]));
        const F dtdx = V::mul(u.base_height, V::sub(tq[1], tq[0]));
        const F dsdy = V::mul(u.base_width, V::sub(sq[2], sq[0]));
        const F dtdy = V::mul(u.base_height, V::sub(tq[2], tq[0]));
        const F rx = V::add(V::mul(dsdx, dsdx), V::mul(dtdx, dtdx));
        const F ry = V::add(V::mul(dsdy, dsdy), V::mul(dtdy, dtdy));
        const F rho2 = V::max(rx, ry);  // maxps: rx unless it compares greater... as max_ps
        // Unordered: a NaN rho counts as minified.
        const M minified = V::nle_f(rho2, V::splat(1.0f));
        q.linear = V::m_or(V::m_and(minified, V::mask_if(u.min_linear)),
                           V::m_andnot(minified, V::mask_if(u.mag_linear)));
        if (!u.mipmapped || V::none(minified)) return q;
        const I bits = V::as_int(rho2);
        const I e = V::and_i(V::srl32(bits, 23), V::splati(0xff));
        const I last = V::splati(u.last);
        if (u.nearest_level) {
            // Level k for rho2 in [2^(2k-1), 2^(2k+1)).
            const I level = clamp_i(V::sra32(V::sub32(e, V::splati(126)), 1), zero, last);
            q.level0 = q.level1 = V::select(minified, zero, level);
            return q;
        }
        // lp_build_fast_log2: (exponent - 1) + mantissa in [1, 2), halved for rho.
        const F mantissa =
            V::as_float(V::or_i(V::and_i(bits, V::splati(0x7fffff)), V::splati(0x3f800000)));
        const F lod =
            V::mul(V::add(V::to_float(V::sub32(e, V::splati(128))), mantissa), V::splat(0.5f));
        const F fl = V::floor(lod);
        const I ipart = V::to_int_trunc(fl);
        F frac = V::sub(lod, fl);
        // split_levels: below level 0 or from the last level on, one level and no weight.
        const M below = V::lt_i(ipart, zero);
        const M beyond = V::m_andnot(V::lt_i(ipart, last), all);
        const M one_level = V::m_or(below, beyond);
        I l0 = V::select(below, ipart, zero);
        l0 = V::select(beyond, l0, last);
        const I l1 = V::select(one_level, V::add32(ipart, V::splati(1)), l0);
        frac = V::select_f(one_level, frac, V::splat(0.0f));
        frac = V::max(frac, V::splat(0.0f));
        const I frac8 = V::to_int_trunc(V::mul(frac, V::splat(256.0f)));
        // Lanes that are not minified read level 0 alone.
        q.level0 = V::select(minified, zero, l0);
        q.level1 = V::select(minified, zero, l1);
        q.frac8 = V::select(minified, zero, frac8);
        q.two_levels = !V::none(V::m_andnot(V::eq_i(q.level0, q.level1), all));
        return q;
    }

    // The texture's rgba8 for the lanes (the min and mag image filters as each lane's quad
    // decides, one or two levels).
    [[gnu::always_inline]] static I sample(const Unit& u, const Lod& q, F s, F t, M live) {
        const I c0 = sample_filtered(u, q, q.level0, s, t, live);
        if (!q.two_levels) return c0;
        return lerp_bytes(q.frac8, c0, sample_filtered(u, q, q.level1, s, t, live));
    }
    // One level per lane, each lane's image filter.
    [[gnu::always_inline]] static I sample_filtered(const Unit& u, const Lod& q, I level, F s, F t,
                                                    M live) {
        const LevelLanes l = level_lanes(u, level);
        const M lin = V::m_and(q.linear, live);
        const M near = V::m_andnot(q.linear, live);
        if (V::none(near)) return sample_level(u, l, s, t, true, live);
        if (V::none(lin)) return sample_level(u, l, s, t, false, live);
        return V::select(q.linear, sample_level(u, l, s, t, false, near),
                         sample_level(u, l, s, t, true, lin));
    }

    // The texture coordinates (and, for the pixel's own row, the colour) at (px, py).
    struct Attributes {
        F s, t;
        F color[4];
    };
    template <bool kColor>
    [[gnu::always_inline]] static Attributes attributes_at(const PlaneV* p, const float* flat,
                                                           const PlaneV& wp, F px, F py, bool fma) {
        Attributes a;
        F v[8];
        if constexpr (S == ShadeModel::Flat) {
            for (int j = 0; j < 8; ++j) v[j] = V::splat(flat[j]);
        } else if constexpr (S == ShadeModel::NoPerspective) {
            for (int j : {4, 5, 7}) v[j] = Base::at(p[j], px, py, fma);
            if constexpr (kColor) {
                for (int j = 0; j < 4; ++j) v[j] = Base::at(p[j], px, py, fma);
            }
        } else {
            const F w = V::div(V::splat(1.0f), Base::at(wp, px, py, fma));
            for (int j : {4, 5, 7}) v[j] = V::mul(Base::at(p[j], px, py, fma), w);
            if constexpr (kColor) {
                for (int j = 0; j < 4; ++j) v[j] = V::mul(Base::at(p[j], px, py, fma), w);
            }
        }
        const F rq = V::div(V::splat(1.0f), v[7]);
        a.s = V::mul(v[4], rq);
        a.t = V::mul(v[5], rq);
        if constexpr (kColor) {
            for (int j = 0; j < 4; ++j) a.color[j] = v[j];
        }
        return a;
    }

    static void shade_rows(const KernelState& k, const SetupList& list, const SetupPrimitive& prim,
                           const RowBlock& b, Framebuffer& fb) {
        const Plane* planes = list.planes.data() + prim.planes;
        const float* flat = list.flat.data() + prim.flat;
        const bool fma = k.options.fma;
        const bool owners = !fb.owner.empty();
        const auto width = static_cast<std::int32_t>(fb.width);
        const typename Base::DepthTest depth = Base::depth_test_of(k, planes, prim);
        const Unit u = unit_of(*k.texture);
        const PlaneV wp = Base::splat(planes[kWPlane]);
        PlaneV ap[8];
        if constexpr (S != ShadeModel::Flat) {
            for (std::size_t j = 0; j < 8; ++j)
                ap[j] = Base::splat(planes[kFirstAttributePlane + j]);
        }
        const I owner = V::splati(static_cast<std::int32_t>(prim.owner));
        const F lanes = V::lane_index();
        constexpr std::uint64_t kLaneBits = (std::uint64_t{1} << kLanes) - 1;
        constexpr float kInv255 = 1.0f / 255.0f;  // unorm8_to_float's constant
        // Lanes start at an even x: the mask shifted by one when x0 is odd, its last bit then
        // in a second word.
        const std::int32_t shift = b.x0 & 1;
        const std::int32_t x_start = b.x0 - shift;

        for (int r = 0; r < Base::kAhead && r < b.rows; ++r) Base::prefetch_row(b, r, fb);
        for (int r = 0; r < b.rows; ++r) {
            if (r + Base::kAhead < b.rows) Base::prefetch_row(b, r + Base::kAhead, fb);
            if (b.mask[r] == 0) continue;
            const std::int32_t y = b.y0 + r;
            const F py = V::splat(static_cast<float>(y));
            const F py_other = V::splat(static_cast<float>(y ^ 1));
            const bool odd_row = (y & 1) != 0;
            const std::size_t row = static_cast<std::size_t>(y) * fb.width;
            std::uint32_t* depth_row = fb.depth.empty() ? nullptr : fb.depth.data() + row;
            auto* color_row = reinterpret_cast<std::uint32_t*>(fb.color8.data()) + row;
            std::uint32_t* owner_row = owners ? fb.owner.data() + row : nullptr;
            const std::uint64_t words[2] = {b.mask[r] << shift,
                                            shift != 0 ? b.mask[r] >> 63 : std::uint64_t{0}};
            for (int word = 0; word < 2; ++word) {
                std::uint64_t m = words[word];
                while (m != 0) {
                    const int base = std::countr_zero(m) & ~(kLanes - 1);
                    const auto bits = static_cast<unsigned>((m >> base) & kLaneBits);
                    m &= ~(kLaneBits << base);
                    const std::int32_t x = x_start + 64 * word + base;
                    const bool inside = x + kLanes <= width;
                    M live = V::from_bits(bits);
                    const F px = V::add(V::splat(static_cast<float>(x)), lanes);
                    if constexpr (D != DepthFormat::None) {
                        live = Base::depth_stage(depth, px, py, fma, depth_row + x, inside, live);
                        if (V::none(live)) continue;
                    }
                    // The colour is read only to modulate.
                    const Attributes own = u.modulate
                                               ? attributes_at<true>(ap, flat, wp, px, py, fma)
                                               : attributes_at<false>(ap, flat, wp, px, py, fma);
                    Lod q;
                    if (u.needs_lod) {
                        const Attributes other =
                            attributes_at<false>(ap, flat, wp, px, py_other, fma);
                        const Attributes& even = odd_row ? other : own;
                        const Attributes& odd = odd_row ? own : other;
                        const F sq[3] = {V::dup_even(even.s), V::dup_odd(even.s),
                                         V::dup_even(odd.s)};
                        const F tq[3] = {V::dup_even(even.t), V::dup_odd(even.t),
                                         V::dup_even(odd.t)};
                        q = lod_of(u, sq, tq);
                    } else {
                        q = lod_of(u, nullptr, nullptr);
                    }
                    const I texel = sample(u, q, own.s, own.t, live);
                    F c[4];
                    for (int j = 0; j < 4; ++j) {
                        const I byte = V::and_i(V::srl32(texel, 8 * j), V::splati(0xff));
                        c[j] = V::mul(V::to_float(byte), V::splat(kInv255));
                        if (u.modulate) c[j] = V::mul(own.color[j], c[j]);
                    }
                    Base::color_stage(Base::pack_unorm8(c), color_row + x,
                                      owners ? owner_row + x : nullptr, owner, inside, live);
                }
            }
        }
    }
};

// The textured kernel for a draw's state, as a function pointer.
template <class V>
FragmentKernel::ShadeRowsFn pick_vector_textured_kernel(ShadeModel s, DepthFormat d,
                                                        BlendPreset b) {
    const auto by_blend = [&]<ShadeModel kS, DepthFormat kD>() -> FragmentKernel::ShadeRowsFn {
        switch (b) {
            case BlendPreset::None:
                return &VectorTexturedKernel<V, kS, kD, BlendPreset::None>::shade_rows;
            case BlendPreset::Alpha:
                return &VectorTexturedKernel<V, kS, kD, BlendPreset::Alpha>::shade_rows;
            case BlendPreset::Add:
                return &VectorTexturedKernel<V, kS, kD, BlendPreset::Add>::shade_rows;
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
