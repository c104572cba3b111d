// The velocity passes L manifolds at a time (solver.hpp, WideGroupOf): L = 4 or 8 blocks of
// the same point count (or L one-point rows, solve_rows) near each other in the schedule, on
// 2L different bodies, solved in SIMD lanes — the exact block LCP of solve_block, as Box2D v3
// solves its contacts in wide lanes. Eight lanes where the build targets AVX-512 (kMachineLanes:
// one register of eight doubles, 32 registers for a group's bodies and points), else four; the
// transposes between the items' rows and the lanes work on fours, eight lanes being two.
// Box2D colours its constraint graph for that, which reorders the whole pass; a pile then
// settles worse than in the schedule's order (bodies one after another), so here a block
// joins a group only if it shares no body with the group or with any item it is moved ahead
// of: it commutes with all of them, and the pass does exactly what the schedule's order does.
// Each lane does the operations solve_block_friction and solve_block_normal do, in the same
// order: the same bits as one block at a time wherever the compiler forms the same fused
// multiply–adds (always without -march).
#include "solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace phynjo::runtime::contact_detail {

namespace {

/// How far ahead of a block pack_groups looks for the L − 1 partners of a group of L, items.
constexpr std::size_t window_of(int lanes) { return 24 * static_cast<std::size_t>(lanes); }

} // namespace

void Solver::pack_groups() {
    groups4_.clear();
    groups8_.clear();
    group_start_.clear();
    if (!options_.wide || options_.scheme != ContactScheme::gauss_seidel || !models_.empty() || shape_field_ < 0) return;
    with_lanes([&](auto lanes) { pack_groups(groups<lanes()>()); });
}

template <int L>
void Solver::pack_groups(std::vector<WideGroupOf<L>>& groups) {
    const std::size_t fixed = ids_.size(); // the static body: read by any number of items, never changed
    const std::size_t items = schedule_.size();
    // stamp_[x]: the window (its number) that last marked body x: 2w as a member of the
    // group being packed, 2w + 1 as a body of an item the members would be moved ahead of.
    stamp_.assign(bodies_.size(), 0);
    sorted_.clear();
    std::uint32_t window = 0;
    // Each item's bodies and its kind: a block's point count — 4 for three points too, which
    // ride in the lanes of four-point blocks (padded: load_groups) rather than wait, rare as
    // they are, for three more of their own — 1 for a point row (a manifold of one point), 0
    // for a sphere's row (never in a group); and the items of each kind not yet placed (a kind
    // with fewer than L left makes no group).
    item_bodies_.resize(items);
    std::size_t left[5] = {0, 0, 0, 0, 0};
    for (std::size_t at = 0; at < items; ++at) {
        const std::int64_t item = schedule_[at];
        ItemBodies& x = item_bodies_[at];
        if (item >= 0) {
            const Row& c = rows_[static_cast<std::size_t>(item)];
            x = {c.a, c.b, c.point ? 1u : 0u};
        } else {
            const Block& k = blocks_[static_cast<std::size_t>(-1 - item)];
            x = {k.a, k.b, static_cast<std::uint32_t>(k.count == 3 ? 4 : k.count)};
        }
        ++left[x.kind];
    }
    // The scans visit open items only (a third of those they passed were taken already):
    // skip_[j] = j while item j is open; a taken item's leads on to the next (path halving).
    skip_.resize(items + 1);
    for (std::size_t j = 0; j <= items; ++j) skip_[j] = static_cast<std::uint32_t>(j);
    auto next_open = [&](std::size_t j) {
        while (skip_[j] != j) {
            skip_[j] = skip_[skip_[j]];
            j = skip_[j];
        }
        return j;
    };
    for (std::size_t at = 0; at < items; ++at) {
        if (skip_[at] != at) continue; // in a group already
        const std::int64_t item = schedule_[at];
        const std::uint32_t a = item_bodies_[at].a, b = item_bodies_[at].b;
        const std::size_t count = item_bodies_[at].kind;
        if (count == 0 || left[count] < L) {
            --left[count];
            sorted_.push_back(item);
            continue;
        }
        ++window;
        const std::uint32_t member = 2 * window, passed = 2 * window + 1;
        std::size_t found[L] = {at};
        int n = 1;
        stamp_[a] = member;
        if (b != fixed) stamp_[b] = member;
        // Without branches (which items join is unpredictable): stamps only grow, so a body is
        // free — neither a member nor passed in this window — where its stamp is below
        // `member`. An open item that does not join stays behind the group, and whatever is
        // moved ahead must not touch its bodies: its bodies become members if it joins (or
        // were), else passed. The static body's stamp is written but never read (an item is
        // free of it).
        const std::size_t end = std::min(items, at + window_of(L) + 1);
        for (std::size_t j = next_open(at + 1); j < end && n < L; j = next_open(j + 1)) {
            const ItemBodies& x = item_bodies_[j];
            const std::uint32_t sa = stamp_[x.a], sb = stamp_[x.b];
            const bool joins = (x.kind == count) & (sa < member) & ((x.b == fixed) | (sb < member));
            stamp_[x.a] = passed - static_cast<std::uint32_t>(joins | (sa == member));
            stamp_[x.b] = passed - static_cast<std::uint32_t>(joins | (sb == member));
            found[n] = j;
            n += joins ? 1 : 0;
        }
        if (n < L) {
            --left[count];
            sorted_.push_back(item);
            continue;
        }
        left[count] -= L;
        group_start_.push_back(sorted_.size());
        groups.emplace_back();
        WideGroupOf<L>& g = groups.back();
        g.count = static_cast<int>(count);
        for (int l = 0; l < L; ++l) {
            skip_[found[l]] = static_cast<std::uint32_t>(found[l] + 1);
            sorted_.push_back(schedule_[found[l]]);
            const std::int64_t x = schedule_[found[l]];
            g.block[l] = static_cast<std::uint32_t>(x < 0 ? -1 - x : x);
        }
    }
    schedule_.swap(sorted_);
}

namespace {

/// A block of fewer points than its group's lanes (three in a group of four-point blocks), padded with
/// points that never press: no lever arm, no impulse, and a minimum velocity no point reaches
/// (finite: 0 × −∞ would be NaN). K and K⁺ are zero beyond the block's points (fill_block), so
/// every sum the lanes form over the padded points adds exact zeros — the block's own bits.
template <int L>
void pad_points(const Block& k, WideGroupOf<L>& g, int l) {
    for (std::size_t j = k.count; j < static_cast<std::size_t>(g.count); ++j) {
        g.jn[j][l] = 0;
        g.bias[j][l] = -1e300;
        for (int d = 0; d < 3; ++d) g.ua[j][d][l] = 0;
    }
}

/// A block's last set and its inverse, padded: in[j] = 1 for the points j of S, and
/// last[4i + j] = (K_SS + 1e-9 diag)⁻¹ at the places of points i, j of S, zero elsewhere
/// (try_set's sums over S, with zero terms between).
void padded_last(const Block& k, double* in, double* last) {
    for (int j = 0; j < 4; ++j) in[j] = k.last_known && (k.last_set & (1u << j)) != 0 ? 1 : 0;
    for (int e = 0; e < 16; ++e) last[e] = 0;
    if (!k.last_known) return;
    int idx[4], n = 0;
    for (int j = 0; j < 4; ++j)
        if (k.last_set & (1u << j)) idx[n++] = j;
    for (int p = 0; p < n; ++p)
        for (int q = 0; q < n; ++q) last[4 * idx[p] + idx[q]] = k.last_inv[4 * p + q];
}

/// The block's last set in lane l (padded_last).
template <int L>
void pad_last(const Block& k, WideGroupOf<L>& g, int l) {
    double in[4], last[16];
    padded_last(k, in, last);
    g.known[l] = k.last_known ? 1 : 0;
    for (int j = 0; j < 4; ++j) g.in[j][l] = in[j];
    for (int e = 0; e < 16; ++e) g.last[e][l] = last[e];
}

} // namespace

void Solver::store_groups() {
    auto store = [&](const auto& groups) {
        for (const auto& g : groups)
            for (int l = 0; l < g.kLanes; ++l) {
                if (g.count == 1) {
                    Row& c = rows_[g.block[l]];
                    c.jn = g.jn[0][l], c.jt1 = g.jt1[l], c.jt2 = g.jt2[l];
                    continue;
                }
                Block& k = blocks_[g.block[l]];
                k.jt1 = g.jt1[l], k.jt2 = g.jt2[l], k.jtw = g.jtw[l];
                for (int j = 0; j < 4; ++j) k.jn[j] = g.jn[j][l];
            }
    };
    store(groups4_);
    store(groups8_);
}

// The helpers below take and return 32- and 64-byte vectors; in a build without AVX GCC warns
// that such a function's ABI differs from an AVX build's. They are internal and inlined: no ABI.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace {

/// L doubles, and L lane masks (all bits set where true), as GCC's vector extensions: one
/// register under -march with AVX (L = 4) or AVX-512 (L = 8), several SSE2 registers without.
template <int L>
struct Lanes;
template <>
struct Lanes<4> {
    using V = double __attribute__((vector_size(32)));
    using Mask = long long __attribute__((vector_size(32)));
};
template <>
struct Lanes<8> {
    using V = double __attribute__((vector_size(64)));
    using Mask = long long __attribute__((vector_size(64)));
};
template <int L>
using LV = typename Lanes<L>::V;
template <int L>
using LM = typename Lanes<L>::Mask;
// Four doubles: the unit of the transposes between items' rows and lanes.
using V4 = Lanes<4>::V;
using Mask4 = Lanes<4>::Mask;

/// The lane vector of a group's array (its L doubles).
template <int L>
[[gnu::always_inline]] inline typename Lanes<L>::V load(const double (&p)[L]) {
    typename Lanes<L>::V v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
template <int L>
[[gnu::always_inline]] inline void store(double (&p)[L], const typename Lanes<L>::V& v) {
    std::memcpy(p, &v, sizeof v);
}
[[gnu::always_inline]] inline V4 load4(const double* p) {
    V4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void store4(double* p, const V4& v) { std::memcpy(p, &v, sizeof v); }
template <class V>
[[gnu::always_inline]] inline V splat(double x) {
    V v;
    for (std::size_t l = 0; l < sizeof(V) / sizeof(double); ++l) v[l] = x;
    return v;
}
template <class V, class Mask>
[[gnu::always_inline]] inline V select(const Mask& m, const V& a, const V& b) {
    return m ? a : b;
}

/// The lanes' sign bits (a lane mask's set lanes), lane l at bit l.
template <class Mask>
[[gnu::always_inline]] inline unsigned lane_bits(const Mask& m) {
#if defined(__AVX512F__)
    if constexpr (sizeof(Mask) == 64) return _mm512_cmplt_epi64_mask(reinterpret_cast<__m512i>(m), _mm512_setzero_si512());
#endif
#if defined(__AVX__)
    if constexpr (sizeof(Mask) == 32) return static_cast<unsigned>(_mm256_movemask_pd(reinterpret_cast<__m256d>(m)));
#endif
    unsigned bits = 0;
    for (std::size_t l = 0; l < sizeof(Mask) / sizeof(long long); ++l) bits |= m[l] < 0 ? 1u << l : 0u;
    return bits;
}
/// Whether every lane is set; whether any is.
template <class Mask>
[[gnu::always_inline]] inline bool all_lanes(const Mask& m) {
    return lane_bits(m) == (1u << (sizeof(Mask) / sizeof(long long))) - 1;
}
template <class Mask>
[[gnu::always_inline]] inline bool any_lane(const Mask& m) {
    return lane_bits(m) != 0;
}

/// Lanes 4h to 4h + 3 of v; and the lanes of two fours (or of one: L = 4).
template <class V>
[[gnu::always_inline]] inline V4 quarter(const V& v, int h) {
    if constexpr (sizeof(V) == sizeof(V4)) {
        return v;
    } else {
        return h == 0 ? __builtin_shufflevector(v, v, 0, 1, 2, 3) : __builtin_shufflevector(v, v, 4, 5, 6, 7);
    }
}
template <int L>
[[gnu::always_inline]] inline typename Lanes<L>::V join(const V4* q) {
    if constexpr (L == 4) return q[0];
    else return __builtin_shufflevector(q[0], q[1], 0, 1, 2, 3, 4, 5, 6, 7);
}

/// out[i][l] = r[l][i]: four lanes' rows of four values as four lane vectors (gather's shuffles).
[[gnu::always_inline]] inline void transpose4(const V4* r, V4* out) {
    const V4 t0 = __builtin_shuffle(r[0], r[1], Mask4{0, 4, 2, 6}), t1 = __builtin_shuffle(r[0], r[1], Mask4{1, 5, 3, 7});
    const V4 t2 = __builtin_shuffle(r[2], r[3], Mask4{0, 4, 2, 6}), t3 = __builtin_shuffle(r[2], r[3], Mask4{1, 5, 3, 7});
    out[0] = __builtin_shuffle(t0, t2, Mask4{0, 1, 4, 5}), out[2] = __builtin_shuffle(t0, t2, Mask4{2, 3, 6, 7});
    out[1] = __builtin_shuffle(t1, t3, Mask4{0, 1, 4, 5}), out[3] = __builtin_shuffle(t1, t3, Mask4{2, 3, 6, 7});
}

/// clamp_disk in each lane.
template <class V>
[[gnu::always_inline]] inline void clamp_disk_lanes(V& n1, V& n2, const V& limit) {
    const V q = n1 * n1 + n2 * n2;
    const auto outside = q > limit * limit;
    if (!any_lane(outside)) return; // friction that sticks in every lane: no root, no division
    V mag;
    for (std::size_t l = 0; l < sizeof(V) / sizeof(double); ++l) mag[l] = std::sqrt(q[l]);
    const V s = select(mag > 0, limit / mag, splat<V>(0));
    const auto scale = outside & (mag > limit);
    n1 = select(scale, n1 * s, n1);
    n2 = select(scale, n2 * s, n2);
}

/// The velocities, spins, inverse masses and world inverse inertias of a group's bodies, lane
/// by lane (side a and side b), and the velocities and spins written back.
template <int L>
struct LaneBodies {
    using V = typename Lanes<L>::V;
    using Mask = typename Lanes<L>::Mask;
    V av[3], aw[3], bv[3], bw[3];
    // The inverse masses and inertias stay in the group, loaded where used: held in registers
    // through a kernel, they were spilled to the stack (a copy of what the group holds).
    const WideGroupOf<L>& group;
    [[gnu::always_inline]] LaneBodies(const std::vector<Body>& bodies, const WideGroupOf<L>& g) : group(g) {
        gather(bodies, g.a, av, aw);
        gather(bodies, g.b, bv, bw);
    }
    /// v and ω of L bodies, one lane each, by fours (gather4).
    [[gnu::always_inline]] static void gather(const std::vector<Body>& bodies, const std::uint32_t* at, V* v, V* w) {
        V4 c[6][L / 4];
        for (int h = 0; h < L / 4; ++h) {
            V4 q[6];
            gather4(bodies, at + 4 * h, q);
            for (int i = 0; i < 6; ++i) c[i][h] = q[i];
        }
        v[0] = join<L>(c[0]), v[1] = join<L>(c[1]), v[2] = join<L>(c[2]);
        w[0] = join<L>(c[3]), w[1] = join<L>(c[4]), w[2] = join<L>(c[5]);
    }
    /// v₀ v₁ v₂ ω₀ ω₁ ω₂ (out[0..5]) of four bodies, one lane each: each body's v₀ v₁ v₂ ω₀ and
    /// ω₁ ω₂ read as a row of four and a pair, and transposed (Body keeps v and w in a row).
    [[gnu::always_inline]] static void gather4(const std::vector<Body>& bodies, const std::uint32_t* at, V4* out) {
        static_assert(offsetof(Body, w) == offsetof(Body, v) + 3 * sizeof(double));
        // v₀ v₁ v₂ ω₀ as one row of four, ω₁ ω₂ as a pair: the same widths as scatter's stores,
        // so that a group reading a body the group before it wrote gets the values forwarded
        // from the stores (a load wider than the store it overlaps waits for the store to retire).
        using V2 = double __attribute__((vector_size(16)));
        V4 r[4];
        V2 h[4];
        // Unrolled, r and h stay in registers (GCC keeps the loop and its arrays on the stack
        // otherwise; the lanes read bodies at every pass: 4 % of a pile's instructions).
#pragma GCC unroll 4
        for (int l = 0; l < 4; ++l) {
            const char* x = reinterpret_cast<const char*>(&bodies[at[l]]) + offsetof(Body, v);
            std::memcpy(&r[l], x, sizeof(V4)), std::memcpy(&h[l], x + 4 * sizeof(double), sizeof(V2));
        }
        transpose4(r, out);
        // (ω₁ ω₂ of lanes 0 and 2, then of lanes 1 and 3) → ω₁ and ω₂ of the four lanes.
        const V4 x = __builtin_shufflevector(h[0], h[2], 0, 1, 2, 3), y = __builtin_shufflevector(h[1], h[3], 0, 1, 2, 3);
        out[4] = __builtin_shuffle(x, y, Mask4{0, 4, 2, 6});
        out[5] = __builtin_shuffle(x, y, Mask4{1, 5, 3, 7});
    }
    /// gather's inverse: v and ω of the lanes' bodies written back, the static body `fixed` left alone.
    [[gnu::always_inline]] static void scatter(std::vector<Body>& bodies, const std::uint32_t* at, const V* v, const V* w, std::size_t fixed) {
        for (int h = 0; h < L / 4; ++h) {
            const V4 columns[4] = {quarter(v[0], h), quarter(v[1], h), quarter(v[2], h), quarter(w[0], h)};
            scatter4(bodies, at + 4 * h, columns, quarter(w[1], h), quarter(w[2], h), fixed);
        }
    }
    [[gnu::always_inline]] static void scatter4(std::vector<Body>& bodies, const std::uint32_t* at, const V4* columns, const V4& w1, const V4& w2,
                         std::size_t fixed) {
        V4 row[4];
        transpose4(columns, row);
        const V4 p0 = __builtin_shuffle(w1, w2, Mask4{0, 4, 2, 6}), p1 = __builtin_shuffle(w1, w2, Mask4{1, 5, 3, 7});
        // Lane l's ω₁ ω₂: the low (l even) or high half of p0 (l = 0, 2) or p1 (l = 1, 3).
        auto put = [&](int l, const V4& pair, int half) {
            if (at[l] == fixed) return;
            char* x = reinterpret_cast<char*>(&bodies[at[l]]) + offsetof(Body, v);
            std::memcpy(x, &row[l], sizeof(V4));
            std::memcpy(x + 4 * sizeof(double), reinterpret_cast<const char*>(&pair) + 2 * half * sizeof(double), 2 * sizeof(double));
        };
        put(0, p0, 0), put(1, p1, 0), put(2, p0, 1), put(3, p1, 1);
    }
    /// The velocity of a's point at the lever arm ra relative to b's at rb (point_velocity):
    /// (v_a + ω_a × r_a) − (v_b + ω_b × r_b).
    [[gnu::always_inline]] void velocity_at(const V* ra, const V* rb, V* dv) const {
        const V wa0 = aw[1] * ra[2] - aw[2] * ra[1], wa1 = aw[2] * ra[0] - aw[0] * ra[2], wa2 = aw[0] * ra[1] - aw[1] * ra[0];
        const V wb0 = bw[1] * rb[2] - bw[2] * rb[1], wb1 = bw[2] * rb[0] - bw[0] * rb[2], wb2 = bw[0] * rb[1] - bw[1] * rb[0];
        dv[0] = av[0] + wa0 - bv[0] - wb0;
        dv[1] = av[1] + wa1 - bv[1] - wb1;
        dv[2] = av[2] + wa2 - bv[2] - wb2;
    }
    /// The impulse p on side a and −p on side b where `go`, with the moments u (a's) and s (b's)
    /// about their centres: v_a += p/m_a, ω_a += I_a⁻¹u, v_b −= p/m_b, ω_b −= I_b⁻¹s.
    [[gnu::always_inline]] void impulse(const Mask& go, const V& p0, const V& p1, const V& p2, const V& u0, const V& u1, const V& u2,
                 const V& s0, const V& s1, const V& s2) {
        const double(&aii)[6][L] = group.aii, (&bii)[6][L] = group.bii;
        const V aim = load(group.aim), bim = load(group.bim);
        const V ia0 = load(aii[0]) * u0 + load(aii[3]) * u1 + load(aii[4]) * u2;
        const V ia1 = load(aii[3]) * u0 + load(aii[1]) * u1 + load(aii[5]) * u2;
        const V ia2 = load(aii[4]) * u0 + load(aii[5]) * u1 + load(aii[2]) * u2;
        const V ib0 = load(bii[0]) * s0 + load(bii[3]) * s1 + load(bii[4]) * s2;
        const V ib1 = load(bii[3]) * s0 + load(bii[1]) * s1 + load(bii[5]) * s2;
        const V ib2 = load(bii[4]) * s0 + load(bii[5]) * s1 + load(bii[2]) * s2;
        av[0] = select(go, av[0] + aim * p0, av[0]);
        av[1] = select(go, av[1] + aim * p1, av[1]);
        av[2] = select(go, av[2] + aim * p2, av[2]);
        aw[0] = select(go, aw[0] + ia0, aw[0]);
        aw[1] = select(go, aw[1] + ia1, aw[1]);
        aw[2] = select(go, aw[2] + ia2, aw[2]);
        bv[0] = select(go, bv[0] - bim * p0, bv[0]);
        bv[1] = select(go, bv[1] - bim * p1, bv[1]);
        bv[2] = select(go, bv[2] - bim * p2, bv[2]);
        bw[0] = select(go, bw[0] - ib0, bw[0]);
        bw[1] = select(go, bw[1] - ib1, bw[1]);
        bw[2] = select(go, bw[2] - ib2, bw[2]);
    }
    /// `fixed`: the static body, left at rest.
    [[gnu::always_inline]] void scatter(std::vector<Body>& bodies, const WideGroupOf<L>& g, std::size_t fixed) const {
        scatter(bodies, g.a, av, aw, fixed);
        scatter(bodies, g.b, bv, bw, fixed);
    }
};

/// y = inv r on the set `in` (zero outside it, inv padded with zeros there) in the lanes of
/// `ok`, and the lanes where that solves (try_set): y ≥ 0 on the set and the points left out
/// not sinking (w = b + K y ≥ bias).
template <int M, int L>
[[gnu::always_inline]] inline LM<L> solve_on_set(const WideGroupOf<L>& g, LM<L> ok, const LM<L>* in, const LV<L> (*inv)[M],
                                                 const LV<L>* b, const LV<L>* r, LV<L>* y) {
    using V = LV<L>;
    const V zero = splat<V>(0);
    for (int p = 0; p < M; ++p) {
        y[p] = zero;
        for (int q = 0; q < M; ++q) y[p] += inv[p][q] * r[q];
        ok &= ~in[p] | (y[p] >= 0);
        y[p] = select(in[p], y[p], zero);
    }
    for (int i = 0; i < M; ++i) { // the points left out must not sink
        V w = b[i];
        for (int j = 0; j < M; ++j) w += load(g.k[4 * i + j]) * y[j];
        const V bias = load(g.bias[i]);
        const V size = select(bias < 0, -bias, bias); // std::abs
        ok &= in[i] | ~(w < bias - 1e-12 * (1 + size));
    }
    return ok;
}

/// A set of pressing points tried in each lane of `go` (solve_lcp_of's `attempt`): `in` its
/// points, its (K_SS + 1e-9 diag)⁻¹ by Gauss–Jordan into inv — padded to the block's points,
/// the identity outside S, which the elimination leaves exact: the same bits as invert_spd
/// on S alone — and y = inv r on S (zero outside it). Where it solves: y ≥ 0 on S and the
/// points left out not sinking. Lanes where a pivot is not positive are left out (their
/// scalar "inverse" is not one, and only the scalar search reproduces it).
template <int M, int L>
LM<L> try_lane_set(const WideGroupOf<L>& g, LM<L> ok, const LM<L>* in, const LV<L>* b, const LV<L>* r, LV<L>* y, LV<L> (*a)[M]) {
    using V = LV<L>;
    const V zero = splat<V>(0), one = splat<V>(1);
    for (int p = 0; p < M; ++p)
        for (int q = 0; q < M; ++q) {
            const V kpq = load(g.k[4 * p + q]);
            a[p][q] = p == q ? select(in[p], kpq * (1 + 1e-9), one) : select(in[p] & in[q], kpq, zero);
        }
    for (int k = 0; k < M; ++k) ok &= a[k][k] > 0; // invert_spd_checked's two refusals: a diagonal,
    for (int k = 0; k < M; ++k) {
        ok &= a[k][k] > 0; // then a pivot, not positive
        const V piv = one / a[k][k];
        a[k][k] = one;
        for (int j = 0; j < M; ++j) a[k][j] *= piv;
        for (int i = 0; i < M; ++i) {
            if (i == k) continue;
            const V f = a[i][k];
            a[i][k] = zero;
            for (int j = 0; j < M; ++j) a[i][j] -= f * a[k][j];
        }
    }
    return solve_on_set<M>(g, ok, in, a, b, r, y);
}

/// The lanes whose search found a new last set (`lanes`): its points and padded inverse, for
/// the caller to keep in the block (record_found).
template <int M, int L>
struct FoundSets {
    LM<L> lanes;
    LM<L> in[M];
    LV<L> inv[M][M];
};

/// try_full_and_last's lanes that neither the full nor the last set solves (`need`): the
/// points the full set presses (x ≥ 0) unless they are the last set, then the points that sink
/// without an impulse (r > 0) unless they are the last set, that guess or all the points —
/// solve_lcp_of's order, skipping the sets it skips. Apart: the common path stays small.
template <int M, int L>
[[gnu::noinline]] void search_more(const WideGroupOf<L>& g, LM<L> need, const LM<L>& known, const LM<L>* in, const LV<L>* b,
                                   const LV<L>* r, const LV<L>* x, LV<L>* y, LM<L>& last, FoundSets<M, L>& found) {
    using V = LV<L>;
    using Mask = LM<L>;
    // The guess (the points the full set presses) unless it is the last set; then the sinking
    // points unless they are the last set, the guess or all the points.
    Mask guess[M], deep[M];
    const Mask every = need | ~need;
    Mask guess_is_last = known, deep_is_last = known, deep_is_guess = every, deep_is_all = every;
    const V points = load(g.points);
    for (int p = 0; p < M; ++p) {
        const Mask real = splat<V>(p) < points; // not a padded point (pad_points: never deep)
        guess[p] = (x[p] >= 0) & real;
        deep[p] = r[p] > 0;
        guess_is_last &= guess[p] == in[p];
        deep_is_last &= deep[p] == in[p];
        deep_is_guess &= deep[p] == guess[p];
        deep_is_all &= deep[p] | ~real;
    }
    auto attempt = [&](const Mask& go, const Mask* set) {
        if (!any_lane(go)) return;
        V t[M], a[M][M];
        const Mask ok = try_lane_set<M>(g, go, set, b, r, t, a);
        for (int p = 0; p < M; ++p) {
            y[p] = select(ok, t[p], y[p]);
            found.in[p] = select(ok, set[p], found.in[p]);
            for (int q = 0; q < M; ++q) found.inv[p][q] = select(ok, a[p][q], found.inv[p][q]);
        }
        last |= ok;
        found.lanes |= ok;
        need &= ~ok;
    };
    attempt(need & ~guess_is_last, guess);
    attempt(need & ~deep_is_last & ~deep_is_guess & ~deep_is_all, deep);
}

/// solve_lcp_of's search in each lane of `start`, as far as it goes without the scalar
/// search's cache: x from the full set's pseudo-inverse, y from the last set's padded inverse
/// (zero outside it), r = bias − b; full and last where each solves (x ≥ 0; y ≥ 0 and the
/// points left out not sinking). Where neither does, the points the full set presses, then
/// the points that sink without an impulse — in the scalar search's order, skipping the sets
/// it skips — each solving lane's y, `last` and `found` set.
template <int M, int L>
void try_full_and_last(const WideGroupOf<L>& g, const LM<L>& start, const LV<L>* b, const LV<L>* r, LV<L>* x, LV<L>* y,
                       LM<L>& full, LM<L>& last, FoundSets<M, L>& found) {
    using V = LV<L>;
    using Mask = LM<L>;
    const V zero = splat<V>(0);
    full = start;
    found.lanes = start & ~start;
    for (int p = 0; p < M; ++p) { // try_full
        x[p] = zero;
        for (int q = 0; q < M; ++q) x[p] += load(g.inv[4 * p + q]) * r[q];
        full &= x[p] >= 0;
    }
    // Where the full set solves every lane started, the last set would change nothing: the
    // callers take x where `full`, and `last` only adds lanes of `start`.
    if (all_lanes(full == start)) {
        last = full & ~full;
        for (int p = 0; p < M; ++p) y[p] = zero;
        return;
    }
    const Mask known = load(g.known) != 0;
    Mask in[M];
    V last_inv[M][M];
    for (int p = 0; p < M; ++p) {
        in[p] = load(g.in[p]) != 0;
        for (int q = 0; q < M; ++q) last_inv[p][q] = load(g.last[4 * p + q]);
    }
    last = solve_on_set<M>(g, start & known, in, last_inv, b, r, y); // try_set on the last set
    const Mask need = start & ~full & ~last;
    if (any_lane(need)) search_more<M>(g, need, known, in, b, r, x, y, last, found);
}

/// solve_lcp_of's record of a set found in lane l: the block's last set and its inverse,
/// packed over the set's points (Block::last_inv), and the lane's padded copy (as pad_last).
template <int M, int L>
void record_found(Block& k, WideGroupOf<L>& g, const FoundSets<M, L>& found, int l) {
    unsigned set = 0;
    int idx[4], n = 0;
    for (int p = 0; p < M; ++p)
        if (found.in[p][l] != 0) set |= 1u << p, idx[n++] = p;
    k.last_set = set;
    k.last_known = true;
    for (int p = 0; p < n; ++p)
        for (int q = 0; q < n; ++q) k.last_inv[4 * p + q] = found.inv[idx[p]][idx[q]][l];
    // pad_last, without unpacking what was just packed.
    g.known[l] = 1;
    for (int j = 0; j < 4; ++j) g.in[j][l] = (set & (1u << j)) != 0 ? 1 : 0;
    for (int e = 0; e < 16; ++e) g.last[e][l] = 0;
    for (int p = 0; p < n; ++p)
        for (int q = 0; q < n; ++q) g.last[4 * idx[p] + idx[q]][l] = k.last_inv[4 * p + q];
}

/// The normal impulses l_j at a block's points where `go` (solve_block's tail): v_a += Σ l_j
/// n / m_a, ω_a += I_a⁻¹ Σ l_j u_j, and side b the opposite with its lever arms u_j + off.
template <int M, int L>
void apply_normals(LaneBodies<L>& lanes, const LM<L>& go, const LV<L>* l) {
    using V = LV<L>;
    const WideGroupOf<L>& g = lanes.group; // the points' u_j, the normal and off read from the group
    const V zero = splat<V>(0);
    V total = zero, u0 = zero, u1 = zero, u2 = zero;
    for (int j = 0; j < M; ++j) {
        total += l[j];
        u0 += l[j] * load(g.ua[j][0]);
        u1 += l[j] * load(g.ua[j][1]);
        u2 += l[j] * load(g.ua[j][2]);
    }
    const V n[3] = {load(g.n[0]), load(g.n[1]), load(g.n[2])}, off[3] = {load(g.off[0]), load(g.off[1]), load(g.off[2])};
    const double(&aii)[6][L] = lanes.group.aii, (&bii)[6][L] = lanes.group.bii;
    const V wa0 = load(aii[0]) * u0 + load(aii[3]) * u1 + load(aii[4]) * u2;
    const V wa1 = load(aii[3]) * u0 + load(aii[1]) * u1 + load(aii[5]) * u2;
    const V wa2 = load(aii[4]) * u0 + load(aii[5]) * u1 + load(aii[2]) * u2;
    u0 += total * off[0];
    u1 += total * off[1];
    u2 += total * off[2];
    const V wb0 = load(bii[0]) * u0 + load(bii[3]) * u1 + load(bii[4]) * u2;
    const V wb1 = load(bii[3]) * u0 + load(bii[1]) * u1 + load(bii[5]) * u2;
    const V wb2 = load(bii[4]) * u0 + load(bii[5]) * u1 + load(bii[2]) * u2;
    V(&av)[3] = lanes.av, (&aw)[3] = lanes.aw, (&bv)[3] = lanes.bv, (&bw)[3] = lanes.bw;
    const V aim = load(lanes.group.aim), bim = load(lanes.group.bim);
    av[0] = select(go, av[0] + aim * total * n[0], av[0]);
    av[1] = select(go, av[1] + aim * total * n[1], av[1]);
    av[2] = select(go, av[2] + aim * total * n[2], av[2]);
    bv[0] = select(go, bv[0] - bim * total * n[0], bv[0]);
    bv[1] = select(go, bv[1] - bim * total * n[1], bv[1]);
    bv[2] = select(go, bv[2] - bim * total * n[2], bv[2]);
    aw[0] = select(go, aw[0] + wa0, aw[0]);
    aw[1] = select(go, aw[1] + wa1, aw[1]);
    aw[2] = select(go, aw[2] + wa2, aw[2]);
    bw[0] = select(go, bw[0] - wb0, bw[0]);
    bw[1] = select(go, bw[1] - wb1, bw[1]);
    bw[2] = select(go, bw[2] - wb2, bw[2]);
}

/// A group's L items (blocks, rows or bodies), one a lane, whose values load_groups copies
/// into the group's lane vectors: whole 32-byte rows of the group written one after another
/// (a group is 4 kB, most of it not in the cache; written lane by lane, its lines were
/// fetched out of order: 4 % of a pile's time).
template <class Item, int L>
struct LaneItems {
    const Item* x[L];
    /// dst[i][l] = member(item l)[i] for i < N, four lanes and four values at a time by transposes.
    template <int N, class F>
    void array(F member, double (*dst)[L]) const {
        for (int h = 0; h < L; h += 4) {
            const double* src[4] = {member(*x[h]), member(*x[h + 1]), member(*x[h + 2]), member(*x[h + 3])};
            int i = 0;
            for (; i + 4 <= N; i += 4) {
                V4 r[4], c[4];
                for (int l = 0; l < 4; ++l) r[l] = load4(src[l] + i);
                transpose4(r, c);
                for (int j = 0; j < 4; ++j) store4(dst[i + j] + h, c[j]);
            }
            for (; i < N; ++i) store4(dst[i] + h, V4{src[0][i], src[1][i], src[2][i], src[3][i]});
        }
    }
    /// dst[l] = member(item l).
    template <class F>
    void scalar(F member, double* dst) const {
        for (int h = 0; h < L; h += 4) store4(dst + h, V4{member(*x[h]), member(*x[h + 1]), member(*x[h + 2]), member(*x[h + 3])});
    }
};

} // namespace

void Solver::load_groups(bool constants) {
    with_lanes([&](auto lanes) { load_groups(groups<lanes()>(), constants); });
}

template <int L>
void Solver::load_groups(std::vector<WideGroupOf<L>>& groups, bool constants) {
    for (WideGroupOf<L>& g : groups) {
        if (constants) { // the lanes' bodies, both kinds of group
            LaneItems<Body, L> lanes;
            for (int l = 0; l < L; ++l) {
                g.a[l] = g.count == 1 ? rows_[g.block[l]].a : blocks_[g.block[l]].a;
                g.b[l] = g.count == 1 ? rows_[g.block[l]].b : blocks_[g.block[l]].b;
                lanes.x[l] = &bodies_[g.a[l]];
            }
            lanes.scalar([](const Body& x) { return x.im; }, g.aim);
            lanes.template array<6>([](const Body& x) { return x.ii; }, g.aii);
            for (int l = 0; l < L; ++l) lanes.x[l] = &bodies_[g.b[l]];
            lanes.scalar([](const Body& x) { return x.im; }, g.bim);
            lanes.template array<6>([](const Body& x) { return x.ii; }, g.bii);
        }
        // What rows and blocks both hold: the normal, the tangents, their effective masses, μ
        // and the friction impulses.
        auto common = [&](const auto& items) {
            if (constants) {
                items.template array<3>([](const auto& x) { return x.n; }, g.n);
                items.template array<3>([](const auto& x) { return x.t1; }, g.t1);
                items.template array<3>([](const auto& x) { return x.t2; }, g.t2);
                items.scalar([](const auto& x) { return x.mt1; }, g.mt1);
                items.scalar([](const auto& x) { return x.mt2; }, g.mt2);
                items.scalar([](const auto& x) { return x.mu; }, g.mu);
            }
            items.scalar([](const auto& x) { return x.jt1; }, g.jt1);
            items.scalar([](const auto& x) { return x.jt2; }, g.jt2);
        };
        if (g.count == 1) { // point rows: ra, rb their lever arms, jn[0], bias[0]
            LaneItems<Row, L> rows;
            for (int l = 0; l < L; ++l) rows.x[l] = &rows_[g.block[l]];
            common(rows);
            if (constants) {
                rows.template array<3>([](const Row& c) { return c.xa; }, g.ra);
                rows.template array<3>([](const Row& c) { return c.xb; }, g.rb);
                rows.scalar([](const Row& c) { return c.mn; }, g.mn);
            }
            rows.scalar([](const Row& c) { return c.jn; }, g.jn[0]);
            rows.scalar([](const Row& c) { return c.bias; }, g.bias[0]);
            continue;
        }
        LaneItems<Block, L> blocks;
        for (int l = 0; l < L; ++l) blocks.x[l] = &blocks_[g.block[l]];
        common(blocks);
        if (constants) {
            blocks.template array<3>([](const Block& k) { return k.ra; }, g.ra);
            blocks.template array<3>([](const Block& k) { return k.rb; }, g.rb);
            blocks.template array<3>([](const Block& k) { return k.off; }, g.off);
            blocks.scalar([](const Block& k) { return k.mtw; }, g.mtw);
            blocks.scalar([](const Block& k) { return k.reach; }, g.reach);
            blocks.scalar([](const Block& k) { return static_cast<double>(k.count); }, g.points);
            blocks.template array<12>([](const Block& k) { return &k.ua[0][0]; }, &g.ua[0][0]);
            blocks.template array<16>([](const Block& k) { return k.k; }, g.k);
            blocks.template array<16>([](const Block& k) { return k.inv; }, g.inv);
        }
        blocks.scalar([](const Block& k) { return k.jtw; }, g.jtw);
        blocks.template array<4>([](const Block& k) { return k.jn; }, g.jn);
        blocks.template array<4>([](const Block& k) { return k.bias; }, g.bias);
        for (int l = 0; l < L; ++l) pad_points(*blocks.x[l], g, l);
        // pad_last of the L lanes (the collisions may have solved a block already), each
        // lane's padded set and inverse transposed into the group.
        struct Padded {
            double in[4], last[16];
        } padded[L];
        for (int l = 0; l < L; ++l) padded_last(*blocks.x[l], padded[l].in, padded[l].last);
        blocks.scalar([](const Block& k) { return k.last_known ? 1.0 : 0.0; }, g.known);
        LaneItems<Padded, L> pads;
        for (int l = 0; l < L; ++l) pads.x[l] = &padded[l];
        pads.template array<4>([](const Padded& x) { return x.in; }, g.in);
        pads.template array<16>([](const Padded& x) { return x.last; }, g.last);
    }
}

template <int M, int L>
void Solver::solve_group(WideGroupOf<L>& g) {
    using V = LV<L>;
    using Mask = LM<L>;
    // The lanes' bodies (distinct: pack_groups).
    LaneBodies<L> lanes(bodies_, g);
    const V(&av)[3] = lanes.av, (&aw)[3] = lanes.aw, (&bv)[3] = lanes.bv, (&bw)[3] = lanes.bw;
    V n[3], ra[3], rb[3];
    for (int d = 0; d < 3; ++d) n[d] = load(g.n[d]), ra[d] = load(g.ra[d]), rb[d] = load(g.rb[d]);
    const V zero = splat<V>(0);
    // solve_block_friction and apply_central.
    {
        V dv[3];
        lanes.velocity_at(ra, rb, dv);
        const V dv0 = dv[0], dv1 = dv[1], dv2 = dv[2];
        V load_sum = zero;
        for (int j = 0; j < M; ++j) load_sum += load(g.jn[j]);
        const V limit = load(g.mu) * load_sum;
        const V t10 = load(g.t1[0]), t11 = load(g.t1[1]), t12 = load(g.t1[2]);
        const V t20 = load(g.t2[0]), t21 = load(g.t2[1]), t22 = load(g.t2[2]);
        const V jt1 = load(g.jt1), jt2 = load(g.jt2), jtw = load(g.jtw);
        V n1 = jt1 - (dv0 * t10 + dv1 * t11 + dv2 * t12) * load(g.mt1);
        V n2 = jt2 - (dv0 * t20 + dv1 * t21 + dv2 * t22) * load(g.mt2);
        clamp_disk_lanes(n1, n2, limit);
        const V wn = (aw[0] - bw[0]) * n[0] + (aw[1] - bw[1]) * n[1] + (aw[2] - bw[2]) * n[2];
        const V tw = jtw - wn * load(g.mtw), reach = load(g.reach);
        const V lo = -limit * reach, hi = limit * reach;
        const V ntw = select(tw < lo, lo, select(hi < tw, hi, tw)); // std::clamp
        const V l1 = n1 - jt1, l2 = n2 - jt2, ltw = ntw - jtw;
        store(g.jt1, n1), store(g.jt2, n2), store(g.jtw, ntw);
        const Mask apply = (l1 != 0) | (l2 != 0) | (ltw != 0);
        const V p0 = l1 * t10 + l2 * t20, p1 = l1 * t11 + l2 * t21, p2 = l1 * t12 + l2 * t22;
        const V u0 = ra[1] * p2 - ra[2] * p1 + ltw * n[0];
        const V u1 = ra[2] * p0 - ra[0] * p2 + ltw * n[1];
        const V u2 = ra[0] * p1 - ra[1] * p0 + ltw * n[2];
        const V s0 = rb[1] * p2 - rb[2] * p1 + ltw * n[0];
        const V s1 = rb[2] * p0 - rb[0] * p2 + ltw * n[1];
        const V s2 = rb[0] * p1 - rb[1] * p0 + ltw * n[2];
        lanes.impulse(apply, p0, p1, p2, u0, u1, u2, s0, s1, s2);
    }
    // solve_block: b = v − K a, the full set, the last set, then the likely sets; the lanes
    // none of them solves go through solve_block_normal once the others are stored.
    V off[3];
    for (int d = 0; d < 3; ++d) off[d] = load(g.off[d]);
    const V vn = (av[0] - bv[0]) * n[0] + (av[1] - bv[1]) * n[1] + (av[2] - bv[2]) * n[2] -
                 (bw[0] * off[0] + bw[1] * off[1] + bw[2] * off[2]);
    const V dw0 = aw[0] - bw[0], dw1 = aw[1] - bw[1], dw2 = aw[2] - bw[2];
    V jn[M], b[M], r[M], x[M], y[M], ua[M][3];
    for (int i = 0; i < M; ++i) {
        jn[i] = load(g.jn[i]);
        for (int d = 0; d < 3; ++d) ua[i][d] = load(g.ua[i][d]);
    }
    for (int i = 0; i < M; ++i) {
        b[i] = vn + (dw0 * ua[i][0] + dw1 * ua[i][1] + dw2 * ua[i][2]);
        for (int j = 0; j < M; ++j) b[i] -= load(g.k[4 * i + j]) * jn[j];
        r[i] = load(g.bias[i]) - b[i];
    }
    Mask full, last;
    FoundSets<M, L> found;
    try_full_and_last<M>(g, zero == zero, b, r, x, y, full, last, found);
    // The solved lanes' impulses applied (solve_block's tail).
    const Mask solved = full | last;
    V step[M];
    for (int j = 0; j < M; ++j) {
        const V xj = select(full, x[j], y[j]);
        step[j] = xj - jn[j];
        store(g.jn[j], select(solved, xj, jn[j]));
    }
    apply_normals<M>(lanes, solved, step);
    lanes.scatter(bodies_, g, ids_.size());
    for (int l = 0; l < L; ++l) {
        if (found.lanes[l] != 0) record_found<M>(blocks_[g.block[l]], g, found, l);
        if (solved[l] != 0) continue;
        Block& k = blocks_[g.block[l]];
        for (int j = 0; j < 4; ++j) k.jn[j] = g.jn[j][l];
        solve_block_normal(k, bodies_, /*lanes_tried=*/true);
        for (int j = 0; j < 4; ++j) g.jn[j][l] = k.jn[j];
        pad_last(k, g, l);
    }
}

template <int L>
void Solver::solve_rows(WideGroupOf<L>& g) {
    using V = LV<L>;
    using Mask = LM<L>;
    // solve_row_friction then solve_row_normal of L point rows (apply_point on both sides).
    LaneBodies<L> lanes(bodies_, g);
    V xa[3], xb[3], n[3], t1[3], t2[3];
    for (int d = 0; d < 3; ++d)
        xa[d] = load(g.ra[d]), xb[d] = load(g.rb[d]), n[d] = load(g.n[d]), t1[d] = load(g.t1[d]), t2[d] = load(g.t2[d]);
    const V zero = splat<V>(0);
    // point_velocity: (v_a + ω_a × r_a) − (v_b + ω_b × r_b).
    // apply_point(p) where `go`.
    auto apply = [&](const Mask& go, const V& p0, const V& p1, const V& p2) {
        const V u0 = xa[1] * p2 - xa[2] * p1, u1 = xa[2] * p0 - xa[0] * p2, u2 = xa[0] * p1 - xa[1] * p0;
        const V s0 = xb[1] * p2 - xb[2] * p1, s1 = xb[2] * p0 - xb[0] * p2, s2 = xb[0] * p1 - xb[1] * p0;
        lanes.impulse(go, p0, p1, p2, u0, u1, u2, s0, s1, s2);
    };
    V dv[3];
    const V jn = load(g.jn[0]);
    {
        lanes.velocity_at(xa, xb, dv);
        const V vt1 = dv[0] * t1[0] + dv[1] * t1[1] + dv[2] * t1[2];
        const V vt2 = dv[0] * t2[0] + dv[1] * t2[1] + dv[2] * t2[2];
        const V jt1 = load(g.jt1), jt2 = load(g.jt2);
        V n1 = jt1 - vt1 * load(g.mt1), n2 = jt2 - vt2 * load(g.mt2);
        const V limit = load(g.mu) * jn;
        clamp_disk_lanes(n1, n2, limit);
        const V l1 = n1 - jt1, l2 = n2 - jt2;
        store(g.jt1, n1), store(g.jt2, n2);
        apply((l1 != 0) | (l2 != 0), l1 * t1[0] + l2 * t2[0], l1 * t1[1] + l2 * t2[1], l1 * t1[2] + l2 * t2[2]);
    }
    {
        lanes.velocity_at(xa, xb, dv);
        const V vn = dv[0] * n[0] + dv[1] * n[1] + dv[2] * n[2];
        const V want = jn - (vn - load(g.bias[0])) * load(g.mn);
        const V next = select(want < 0, zero, want); // std::max(want, 0.0)
        const V l = next - jn;
        store(g.jn[0], next);
        apply(l != 0, l * n[0], l * n[1], l * n[2]);
    }
    lanes.scatter(bodies_, g, ids_.size());
}

template <int M, int L>
bool Solver::push_group(WideGroupOf<L>& g) {
    using V = LV<L>;
    using Mask = LM<L>;
    // push_block lane by lane: the bodies' v and ω are their displacements and turns so far,
    // g.bias the points' −(separation at detection) − slop.
    LaneBodies<L> lanes(bodies_, g);
    const V(&av)[3] = lanes.av, (&aw)[3] = lanes.aw, (&bv)[3] = lanes.bv, (&bw)[3] = lanes.bw;
    V n[3], off[3];
    for (int d = 0; d < 3; ++d) n[d] = load(g.n[d]), off[d] = load(g.off[d]);
    const V zero = splat<V>(0);
    const V vn = (av[0] - bv[0]) * n[0] + (av[1] - bv[1]) * n[1] + (av[2] - bv[2]) * n[2] -
                 (bw[0] * off[0] + bw[1] * off[1] + bw[2] * off[2]);
    const V dw0 = aw[0] - bw[0], dw1 = aw[1] - bw[1], dw2 = aw[2] - bw[2];
    V b[M], r[M], x[M], y[M], ua[M][3];
    Mask deep = zero != zero;
    for (int i = 0; i < M; ++i) {
        for (int d = 0; d < 3; ++d) ua[i][d] = load(g.ua[i][d]);
        b[i] = vn + (dw0 * ua[i][0] + dw1 * ua[i][1] + dw2 * ua[i][2]);
        r[i] = load(g.bias[i]) - b[i];
        deep |= r[i] > 0;
    }
    if (!any_lane(deep)) return false;
    Mask full, last;
    FoundSets<M, L> found;
    try_full_and_last<M>(g, deep, b, r, x, y, full, last, found);
    const Mask solved = full | last;
    const V beta = splat<V>(options_.baumgarte);
    V push[M];
    for (int j = 0; j < M; ++j) push[j] = beta * select(full, x[j], y[j]);
    apply_normals<M>(lanes, solved, push);
    lanes.scatter(bodies_, g, ids_.size());
    bool moved = any_lane(solved);
    for (int l = 0; l < L; ++l) {
        if (found.lanes[l] != 0) record_found<M>(blocks_[g.block[l]], g, found, l);
        if (deep[l] == 0 || solved[l] != 0) continue;
        Block& k = blocks_[g.block[l]];
        moved = push_block(k, /*lanes_tried=*/true) || moved;
        pad_last(k, g, l);
    }
    return moved;
}

template <int L>
bool Solver::push_rows(WideGroupOf<L>& g) {
    using V = LV<L>;
    using Mask = LM<L>;
    // push_row of L point rows at once.
    LaneBodies<L> lanes(bodies_, g);
    V xa[3], xb[3], n[3];
    for (int d = 0; d < 3; ++d) xa[d] = load(g.ra[d]), xb[d] = load(g.rb[d]), n[d] = load(g.n[d]);
    V dv[3];
    lanes.velocity_at(xa, xb, dv);
    const V vn = dv[0] * n[0] + dv[1] * n[1] + dv[2] * n[2];
    const V depth = load(g.bias[0]) - vn;
    const Mask go = depth > 0;
    if (!any_lane(go)) return false;
    const V l = splat<V>(options_.baumgarte) * depth * load(g.mn);
    const V p0 = l * n[0], p1 = l * n[1], p2 = l * n[2];
    const V u0 = xa[1] * p2 - xa[2] * p1, u1 = xa[2] * p0 - xa[0] * p2, u2 = xa[0] * p1 - xa[1] * p0;
    const V s0 = xb[1] * p2 - xb[2] * p1, s1 = xb[2] * p0 - xb[0] * p2, s2 = xb[0] * p1 - xb[1] * p0;
    lanes.impulse(go, p0, p1, p2, u0, u1, u2, s0, s1, s2);
    lanes.scatter(bodies_, g, ids_.size());
    return true;
}

#define PHYNJO_WIDE_LANES(L)                                                                                               \
    template void Solver::pack_groups<L>(std::vector<WideGroupOf<L>>&);                                                    \
    template void Solver::load_groups<L>(std::vector<WideGroupOf<L>>&, bool);                                              \
    template void Solver::solve_rows<L>(WideGroupOf<L>&);                                                                  \
    template bool Solver::push_rows<L>(WideGroupOf<L>&);                                                                   \
    template void Solver::solve_group<2, L>(WideGroupOf<L>&);                                                              \
    template void Solver::solve_group<3, L>(WideGroupOf<L>&);                                                              \
    template void Solver::solve_group<4, L>(WideGroupOf<L>&);                                                              \
    template bool Solver::push_group<2, L>(WideGroupOf<L>&);                                                               \
    template bool Solver::push_group<3, L>(WideGroupOf<L>&);                                                               \
    template bool Solver::push_group<4, L>(WideGroupOf<L>&);
PHYNJO_WIDE_LANES(4)
PHYNJO_WIDE_LANES(8)
#undef PHYNJO_WIDE_LANES

} // namespace phynjo::runtime::contact_detail
