// A manifold's points solved together (solver.hpp, Block): the blocks of a step, their exact
// linear complementarity problems (normal impulses, position corrections, restitution) and K's
// inverses (block_inverse.hpp).
#include "block_inverse.hpp"
#include "solver.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace phynjo::runtime::contact_detail {

void Solver::setup_blocks() {
    // Each manifold of 2 to 4 points: K_ij = (1/m_a + 1/m_b) + (r_ai × n)·I_a⁻¹(r_aj × n) +
    // (r_bi × n)·I_b⁻¹(r_bj × n) (Jacobi: the split masses).
    blocks_.clear();
    schedule_.clear();
    const bool jacobi = options_.scheme == ContactScheme::jacobi;
    for (std::size_t i = 0; i < rows_.size();) {
        Row& c = rows_[i];
        c.block = -1;
        if (!c.point || c.block_size < 2) {
            schedule_.push_back(static_cast<std::int64_t>(i));
            ++i;
            continue;
        }
        const std::size_t m = c.block_size;
        double ra[4][3], rb[4][3];
        for (std::size_t j = 0; j < m; ++j)
            for (int d = 0; d < 3; ++d) ra[j][d] = rows_[i + j].xa[d], rb[j][d] = rows_[i + j].xb[d];
        const std::size_t index = blocks_.size();
        Block& b = blocks_.emplace_back(); // in place: a block is 1 kB
        const Body& A = bodies_[c.a];
        const Body& B = bodies_[c.b];
        const double sa = jacobi ? split_[c.a] : 1.0, sb = jacobi ? split_[c.b] : 1.0;
        fill_block(A, B, c.n, ra, rb, m, sa, sb, c.plane >= 0, b);
        b.a = c.a;
        b.b = c.b;
        b.first = i;
        for (int d = 0; d < 3; ++d) {
            b.ra[d] = b.rb[d] = 0;
            for (std::size_t j = 0; j < m; ++j) b.ra[d] += ra[j][d] / static_cast<double>(m), b.rb[d] += rb[j][d] / static_cast<double>(m);
            b.t1[d] = c.t1[d], b.t2[d] = c.t2[d];
        }
        b.reach = 0;
        for (std::size_t j = 0; j < m; ++j) {
            double e[3];
            for (int d = 0; d < 3; ++d) e[d] = ra[j][d] - b.ra[d];
            const double en = dot(e, c.n);
            b.reach += std::sqrt(std::max(dot(e, e) - en * en, 0.0)) / static_cast<double>(m);
        }
        if (!is_model_box(B)) {
            b.mt1 = 1 / point_inverse_mass(A, B, b.ra, b.rb, b.t1, sa, sb);
            b.mt2 = 1 / point_inverse_mass(A, B, b.ra, b.rb, b.t2, sa, sb);
            b.mtw = 1 / (sa * quad(A.ii, c.n) + sb * quad(B.ii, c.n));
        } else { // a model may not move or turn along some directions at all: no impulse there
            const double floor = kSingularInverseMass * (sa * inverse_mass_scale(A) + sb * inverse_mass_scale(B));
            auto inverse = [floor](double k) { return k > floor ? 1 / k : 0.0; };
            const double g[6] = {0, 0, 0, c.n[0], c.n[1], c.n[2]};
            b.mt1 = inverse(point_k(A, B, b.ra, b.rb, b.t1, sa, sb));
            b.mt2 = inverse(point_k(A, B, b.ra, b.rb, b.t2, sa, sb));
            b.mtw = inverse(sa * (is_model_box(A) ? model_box_k(A, g, g) : quad(A.ii, c.n)) + sb * model_box_k(B, g, g));
        }
        b.mu = c.mu;
        b.jt1 = b.jt2 = b.jtw = 0;
        for (std::size_t j = 0; j < m; ++j) {
            rows_[i + j].block = static_cast<int>(index);
            rows_[i + j].jt1 = rows_[i + j].jt2 = 0;
        }
        schedule_.push_back(-1 - static_cast<std::int64_t>(index));
        i += m;
    }
    pack_groups();
}

namespace {

/// The sets of pressing points of a manifold of m points (bit i: point i), largest first, and
/// where each set's inverse lies in Block::subset_inv (the full set's is Block::inv).
struct SetOrder {
    unsigned sets[16];
    int offset[16];
    int index[16]; // a set's place in `sets`
    int count = 0;
    explicit SetOrder(unsigned m) {
        const unsigned all = (1u << m) - 1;
        int at = 0;
        for (int size = static_cast<int>(m); size >= 0; --size)
            for (unsigned set = all + 1; set-- > 0;)
                if (std::popcount(set) == size) {
                    offset[count] = at;
                    index[set] = count;
                    sets[count++] = set;
                    if (size < static_cast<int>(m)) at += size * size;
                }
    }
};
const SetOrder kSetOrders[5] = {SetOrder(0), SetOrder(1), SetOrder(2), SetOrder(3), SetOrder(4)};

} // namespace

bool Solver::solve_block(Block& k, const std::vector<Body>& from, bool lanes_tried) {
    // The manifold's linear complementarity problem, solved exactly: with a the accumulated
    // impulses, v the normal velocities and b = v − K a (the velocities without them), find
    // x ≥ 0 with w = b + K x ≥ bias and x_i (w_i − bias_i) = 0, by trying the sets of
    // pressing points from all of them down to none (Box2D's block solver for two points,
    // for up to four). K of a face's four points has rank 3 (+1e-9 of its diagonal keeps
    // the full set solvable; a set of three solves it exactly).
    const std::size_t m = k.count;
    const double* n = k.n;
    double b[4] = {0, 0, 0, 0};
    {
        const Body& A = from[k.a];
        const Body& B = from[k.b];
        const double vn = (A.v[0] - B.v[0]) * n[0] + (A.v[1] - B.v[1]) * n[1] + (A.v[2] - B.v[2]) * n[2] - dot(B.w, k.off);
        const double dw[3] = {A.w[0] - B.w[0], A.w[1] - B.w[1], A.w[2] - B.w[2]};
        for (std::size_t i = 0; i < m; ++i) b[i] = vn + dot(dw, k.ua[i]);
    }
    for (std::size_t i = 0; i < m; ++i)
        for (std::size_t j = 0; j < m; ++j) b[i] -= k.k[4 * i + j] * k.jn[j];
    double x[4];
    if (!solve_lcp(k, b, k.bias, x, lanes_tried)) return false;
    double total = 0, u[3] = {0, 0, 0};
    for (std::size_t j = 0; j < m; ++j) {
        const double l = x[j] - k.jn[j];
        k.jn[j] = x[j];
        total += l;
        for (int d = 0; d < 3; ++d) u[d] += l * k.ua[j][d];
    }
    Body& A = bodies_[k.a];
    Body& B = bodies_[k.b];
    if (is_model_box(B)) { // −Σ λ_j n at its points: the force −total n, the moment −Σ λ_j r_b,j × n
        double wa[3];
        if (is_model_box(A)) { // another model's box: the force total n, the moment Σ λ_j r_a,j × n
            const double force[3] = {total * n[0], total * n[1], total * n[2]};
            model_wrench(A, force, u, bodies_, false);
        } else {
            mul_sym(A.ii, u, wa);
            for (int d = 0; d < 3; ++d) A.v[d] += A.im * total * n[d], A.w[d] += wa[d];
        }
        for (int d = 0; d < 3; ++d) u[d] += total * k.off[d];
        const double force[3] = {-total * n[0], -total * n[1], -total * n[2]}, moment[3] = {-u[0], -u[1], -u[2]};
        model_wrench(B, force, moment, bodies_, false);
        return true;
    }
    apply_block_normals(k, total, u);
    return true;
}

void Solver::apply_block_normals(const Block& k, double total, double* u) {
    Body& A = bodies_[k.a];
    Body& B = bodies_[k.b];
    double wa[3], wb[3];
    mul_sym(A.ii, u, wa);
    for (int d = 0; d < 3; ++d) u[d] += total * k.off[d];
    mul_sym(B.ii, u, wb);
    for (int d = 0; d < 3; ++d) {
        A.v[d] += A.im * total * k.n[d];
        B.v[d] -= B.im * total * k.n[d];
        A.w[d] += wa[d];
        B.w[d] -= wb[d];
    }
}

namespace {

/// The impulses x when exactly the points of `set` press (b, bias: solve_block), with `inv`
/// the inverse of K_SS (row-major, rows `stride` apart); false when one of them would pull or
/// a point left out would sink. M: the block's point count (its loops unrolled).
template <int M>
bool try_set(const Block& k, unsigned set, const double* inv, int stride, const double* b, const double* bias, double* x) {
    int idx[4];
    int n = 0;
    for (int i = 0; i < M; ++i)
        if (set & (1u << i)) idx[n++] = i;
    for (int p = 0; p < n; ++p) {
        double s = 0;
        for (int q = 0; q < n; ++q) s += inv[stride * p + q] * (bias[idx[q]] - b[idx[q]]);
        if (!(s >= 0)) return false;
        x[idx[p]] = s;
    }
    // The points left out must not sink (w_i ≥ bias_i).
    for (int i = 0; i < M; ++i) {
        if (set & (1u << i)) continue;
        double w = b[i];
        for (int j = 0; j < M; ++j) w += k.k[4 * i + j] * x[j];
        if (w < bias[i] - 1e-12 * (1 + std::abs(bias[i]))) return false;
    }
    return true;
}

/// try_set for the set of all M points (none left out); `pressing`: the points whose impulse
/// came out positive (all of them when it solves).
template <int M>
bool try_full(const double* inv, const double* b, const double* bias, double* x, unsigned& pressing) {
    double r[M];
    for (int q = 0; q < M; ++q) r[q] = bias[q] - b[q];
    pressing = 0;
    for (int p = 0; p < M; ++p) {
        double s = 0;
        for (int q = 0; q < M; ++q) s += inv[4 * p + q] * r[q];
        x[p] = s;
        if (s >= 0) pressing |= 1u << p;
    }
    return pressing == (1u << M) - 1;
}

template <int M>
bool solve_lcp_of(Block& k, const double* b, const double* bias, double* x, bool lanes_tried) {
    const SetOrder& order = kSetOrders[M];
    auto clear = [x] { std::fill_n(x, 4, 0.0); };
    clear();
    unsigned guess = 0;
    if (try_full<M>(k.inv, b, bias, x, guess)) return true; // its pressing points: the guess, wanted below either way
    if (k.last_known && !lanes_tried) {
        clear();
        if (try_set<M>(k, k.last_set, k.last_inv, 4, b, bias, x)) return true;
    }
    // The i-th set of the order with its (K_SS + 1e-9 diag)⁻¹ (computed once a step, packed
    // n × n), tried; on success it becomes the block's last set.
    auto attempt = [&](int i) {
        const unsigned set = order.sets[i];
        int idx[4], n = 0;
        for (int j = 0; j < M; ++j)
            if (set & (1u << j)) idx[n++] = j;
        double* local = k.subset_inv + order.offset[i];
        if (n > 0 && !(k.subsets_known & (1u << i))) {
            double a[16];
            for (int p = 0; p < n; ++p) {
                for (int q = 0; q < n; ++q) a[4 * p + q] = k.k[4 * idx[p] + idx[q]];
                a[4 * p + p] *= 1 + 1e-9;
            }
            invert_spd(a, n);
            for (int p = 0; p < n; ++p)
                for (int q = 0; q < n; ++q) local[n * p + q] = a[4 * p + q];
            k.subsets_known = static_cast<std::uint16_t>(k.subsets_known | (1u << i));
        }
        clear();
        if (!try_set<M>(k, set, local, n, b, bias, x)) return false;
        k.last_set = set;
        k.last_known = true;
        for (int p = 0; p < n; ++p)
            for (int q = 0; q < n; ++q) k.last_inv[4 * p + q] = local[n * p + q];
        return true;
    };
    // Then the points the full set presses (those it would pull are the ones to let go), the
    // points that sink without an impulse (b_j < bias_j), and the other sets of these sinking
    // points, largest first: the answer nearly always lies among them (in a pile: 98 % of the
    // times the first two miss). Then every other set. A face's K has rank 3, so several sets
    // may solve it; all of them give the bodies the same impulse (K (x₁ − x₂) = 0 makes
    // Jᵀ (x₁ − x₂) = 0), so the order of the search changes which one is found, not the motion.
    unsigned deep = 0;
    for (int j = 0; j < M; ++j)
        if (bias[j] - b[j] > 0) deep |= 1u << j;
    const unsigned last = k.last_known ? k.last_set : ~0u;
    if (!lanes_tried && guess != last && attempt(order.index[guess])) return true;
    if (!lanes_tried && deep != last && deep != guess && deep != (1u << M) - 1 && attempt(order.index[deep])) return true;
    for (int pass = 0; pass < 2; ++pass)
        for (int i = 1; i < order.count; ++i) {
            const unsigned set = order.sets[i];
            // first the subsets of the sinking points, then the rest
            if (set == last || set == guess || set == deep || ((set & ~deep) == 0) != (pass == 0)) continue;
            if (attempt(i)) return true;
        }
    return false;
}

} // namespace

bool Solver::solve_lcp(Block& k, const double* b, const double* bias, double* x, bool lanes_tried) const {
    // The full set first (its pseudo-inverse kept by fill_block), so that of the many impulses
    // that hold a face (its four points' K has rank 3) the same, symmetric ones are chosen when
    // every point presses; then the set that solved the block last (its inverse kept: the
    // iterations of a step mostly find the same points pressing); then the likely sets, then
    // every other (solve_lcp_of).
    switch (k.count) {
    case 1: return solve_lcp_of<1>(k, b, bias, x, lanes_tried);
    case 2: return solve_lcp_of<2>(k, b, bias, x, lanes_tried);
    case 3: return solve_lcp_of<3>(k, b, bias, x, lanes_tried);
    case 4: return solve_lcp_of<4>(k, b, bias, x, lanes_tried);
    default: return false; // blocks hold 1 to 4 points (Manifold)
    }
}

template <class Size>
void Solver::fill_block_of(const Body& A, const Body& B, const double* n, const double (*ra)[3], const double (*rb)[3], Size m,
                           double sa, double sb, bool plane, Block& k) const {
    double(&ua)[4][3] = k.ua;
    double ub[4][3], ia[4][3], ib[4][3];
    for (int j = 0; j < m; ++j) {
        cross(ra[j], n, ua[j]);
        cross(rb[j], n, ub[j]);
        mul_sym(A.ii, ua[j], ia[j]);
        mul_sym(B.ii, ub[j], ib[j]);
    }
    for (int d = 0; d < 3; ++d) k.n[d] = n[d];
    if (plane) {
        k.off[0] = k.off[1] = k.off[2] = 0;
    } else {
        const double dp[3] = {A.p[0] - B.p[0], A.p[1] - B.p[1], A.p[2] - B.p[2]};
        cross(dp, n, k.off);
    }
    k.count = static_cast<std::size_t>(m);
    for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q)
            k.k[4 * p + q] = p < m && q < m ? sa * (A.im + dot(ua[p], ia[q])) + sb * (B.im + dot(ub[p], ib[q])) : 0.0;
    if (is_model_box(B)) // the model's share: g_pᵀ A_box g_q, g = (n, r_b × n) (no I_b: B.ii is 0)
        for (int p = 0; p < m; ++p)
            for (int q = 0; q < m; ++q) {
                const double gp[6] = {n[0], n[1], n[2], ub[p][0], ub[p][1], ub[p][2]};
                const double gq[6] = {n[0], n[1], n[2], ub[q][0], ub[q][1], ub[q][2]};
                double ka;
                if (is_model_box(A)) { // another model's box as side a: g = (n, r_a × n)
                    const double hp[6] = {n[0], n[1], n[2], ua[p][0], ua[p][1], ua[p][2]};
                    const double hq[6] = {n[0], n[1], n[2], ua[q][0], ua[q][1], ua[q][2]};
                    ka = model_box_k(A, hp, hq);
                } else {
                    ka = A.im + dot(ua[p], ia[q]);
                }
                k.k[4 * p + q] = sa * ka + sb * model_box_k(B, gp, gq);
            }
    // The full set's pseudo-inverse (the least impulses that do it): four points of a face
    // give a K of rank 3, whose regularised inverse would amplify round-off unevenly; its
    // closed form (block_inverse.hpp), the eigen-decomposition for degenerate manifolds.
    double t1[3], t2[3];
    tangent_basis(n, t1, t2);
    if (!closed_form_pinv(k.k, static_cast<int>(m), t1, t2, ua, k.inv)) eigen_pinv(k.k, static_cast<int>(m), k.inv);
    k.set_known = true;
    k.last_set = 0;
    k.last_known = false;
    k.subsets_known = 0;
}

void Solver::fill_block(const Body& A, const Body& B, const double* n, const double (*ra)[3], const double (*rb)[3],
                        std::size_t m, double sa, double sb, bool plane, Block& k) const {
    with_fixed_count(static_cast<int>(m), [&](auto count) { fill_block_of(A, B, n, ra, rb, count, sa, sb, plane, k); });
}

bool Solver::correct_block(std::size_t first, Block& k) {
    // The points' corrections together, as the velocities are solved: λ ≥ 0 with
    // (K λ)_i ≥ β (depth_i − slop) and complementarity, then every body moved and turned once.
    const Row& c = rows_[first];
    const std::size_t m = c.block_size;
    Body& A = bodies_[c.a];
    Body& B = bodies_[c.b];
    double ra[4][3], rb[4][3], target[4], zero[4] = {0, 0, 0, 0};
    bool deep = false;
    for (std::size_t j = 0; j < m; ++j) {
        double xa[3], xb[3];
        anchors(rows_[first + j], xa, xb);
        const double sep = (xa[0] - xb[0]) * c.n[0] + (xa[1] - xb[1]) * c.n[1] + (xa[2] - xb[2]) * c.n[2];
        target[j] = options_.baumgarte * (-sep - options_.slop);
        deep = deep || target[j] > 0;
        for (int d = 0; d < 3; ++d) {
            const double mid = 0.5 * (xa[d] + xb[d]);
            ra[j][d] = mid - A.p[d];
            rb[j][d] = c.plane >= 0 ? 0.0 : mid - B.p[d];
        }
    }
    if (!deep) return false;
    // K at the lever arms of the first pass that needs it: the passes move the bodies by the
    // depth only, and K's pseudo-inverse is the cost of a pass.
    // Jacobi: each manifold corrected as if alone, as a point row is, and the bodies moved at
    // the end of the pass (correct_positions); split masses would divide a body's correction
    // among its contacts and leave millimetres after the passes.
    const bool jacobi = options_.scheme == ContactScheme::jacobi;
    if (!k.set_known) fill_block(A, B, c.n, ra, rb, m, 1.0, 1.0, c.plane >= 0, k);
    double x[4];
    if (!solve_lcp(k, zero, target, x)) return false;
    double p[3] = {0, 0, 0}, ta[3] = {0, 0, 0}, tb[3] = {0, 0, 0};
    for (std::size_t j = 0; j < m; ++j) {
        const double l[3] = {x[j] * c.n[0], x[j] * c.n[1], x[j] * c.n[2]};
        double u[3];
        for (int d = 0; d < 3; ++d) p[d] += l[d];
        cross(ra[j], l, u);
        for (int d = 0; d < 3; ++d) ta[d] += u[d];
        cross(rb[j], l, u);
        for (int d = 0; d < 3; ++d) tb[d] += u[d];
    }
    double wa[3], wb[3];
    mul_sym(A.ii, ta, wa);
    mul_sym(B.ii, tb, wb);
    if (is_model_box(B)) { // moved at once, also under Jacobi (its points move with the model)
        const double force[3] = {-p[0], -p[1], -p[2]}, moment[3] = {-tb[0], -tb[1], -tb[2]};
        if (is_model_box(A)) { // another model's box as side a: the wrench (P, Σ r_a × P_j)
            model_wrench(A, p, ta, bodies_, true);
        } else if (jacobi) {
            for (int d = 0; d < 3; ++d) delta_[3 * c.a + d] += A.im * p[d], turn_[3 * c.a + d] += wa[d];
        } else {
            for (int d = 0; d < 3; ++d) A.p[d] += A.im * p[d];
            rotate_by(A.q, wa);
        }
        model_wrench(B, force, moment, bodies_, true);
        return true;
    }
    if (jacobi) {
        for (int d = 0; d < 3; ++d) {
            delta_[3 * c.a + d] += A.im * p[d];
            turn_[3 * c.a + d] += wa[d];
            if (c.plane < 0) {
                delta_[3 * c.b + d] -= B.im * p[d];
                turn_[3 * c.b + d] -= wb[d];
            }
        }
        return true;
    }
    for (int d = 0; d < 3; ++d) {
        A.p[d] += A.im * p[d];
        B.p[d] -= B.im * p[d];
        wb[d] = -wb[d];
    }
    rotate_by(A.q, wa);
    if (c.plane < 0) rotate_by(B.q, wb);
    return true;
}

} // namespace phynjo::runtime::contact_detail
