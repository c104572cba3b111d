// The position passes of a Gauss–Seidel world of rigid bodies with shapes (no models), on the
// step's own contacts and effective masses: each body's displacement and turn so far held in
// its velocity and spin slots, a point's separation its separation at detection plus the
// normal "velocity" of those (linear in them: n·(Δp_a − Δp_b) + Δθ_a·(r_a × n) − Δθ_b·(r_b × n)),
// and the bodies moved and turned once at the end. The passes are then the velocity passes'
// normal halves, scalar or four or eight manifolds at once (push_group, push_rows), with no anchors
// re-rotated and no K refilled per pass — the pseudo-velocities of Bullet's split impulses and
// the linearised separations of Box2D v3's solver, with the fresh corrections of Box2D v2's
// nonlinear Gauss–Seidel: each pass removes β of the depth beyond the slop that is left.
// The error of the linearisation is second order in the turns (sub-micrometre for corrections
// of millimetres on bodies of metres).
#include "solver.hpp"

#include <algorithm>

namespace phynjo::runtime::contact_detail {

bool Solver::linear_positions() const {
    return options_.scheme == ContactScheme::gauss_seidel && models_.empty() && shape_field_ >= 0;
}

bool Solver::push_row(Row& c) {
    const double vn = normal_velocity(c, bodies_[c.a], bodies_[c.b]);
    const double depth = c.bias - vn; // −(separation now) − slop
    if (!(depth > 0)) return false;
    apply_normal(c, options_.baumgarte * depth * c.mn, bodies_);
    return true;
}

bool Solver::push_block(Block& k, bool lanes_tried) {
    // solve_block's LCP with no accumulated impulse: x ≥ 0 with b + K x ≥ bias, b_j the
    // points' separations gained so far and bias_j = −(separation at detection) − slop; β x
    // applied.
    const std::size_t m = k.count;
    const double* n = k.n;
    const Body& A = bodies_[k.a];
    const Body& B = bodies_[k.b];
    double b[4] = {0, 0, 0, 0};
    bool deep = false;
    {
        const double vn = (A.v[0] - B.v[0]) * n[0] + (A.v[1] - B.v[1]) * n[1] + (A.v[2] - B.v[2]) * n[2] - dot(B.w, k.off);
        const double dw[3] = {A.w[0] - B.w[0], A.w[1] - B.w[1], A.w[2] - B.w[2]};
        for (std::size_t i = 0; i < m; ++i) {
            b[i] = vn + dot(dw, k.ua[i]);
            deep = deep || k.bias[i] - b[i] > 0;
        }
    }
    if (!deep) return false;
    double x[4];
    if (!solve_lcp(k, b, k.bias, x, lanes_tried)) return false;
    const double beta = options_.baumgarte;
    double total = 0, u[3] = {0, 0, 0};
    for (std::size_t j = 0; j < m; ++j) {
        const double l = beta * x[j];
        total += l;
        for (int d = 0; d < 3; ++d) u[d] += l * k.ua[j][d];
    }
    apply_block_normals(k, total, u);
    return true;
}

template <int L>
bool Solver::position_pass() {
    std::vector<WideGroupOf<L>>& gs = groups<L>();
    bool any = false;
    std::size_t group = 0;
    for (std::size_t at = 0; at < schedule_.size(); ++at) {
        if (group < gs.size() && group_start_[group] == at) {
            WideGroupOf<L>& g = gs[group++];
            bool moved = false;
            switch (g.count) {
            case 1: moved = push_rows(g); break;
            case 2: moved = push_group<2>(g); break;
            case 3: moved = push_group<3>(g); break;
            default: moved = push_group<4>(g); break;
            }
            any = any || moved;
            at += L - 1;
            continue;
        }
        const std::int64_t item = schedule_[at];
        const bool moved = item >= 0 ? push_row(rows_[static_cast<std::size_t>(item)])
                                     : push_block(blocks_[static_cast<std::size_t>(-1 - item)]);
        any = any || moved;
    }
    return any;
}

void Solver::push_positions(double dt) {
    const std::size_t nb = bodies_.size();
    saved_.resize(6 * nb);
    for (std::size_t i = 0; i < nb; ++i) {
        Body& X = bodies_[i];
        for (int d = 0; d < 3; ++d) {
            saved_[6 * i + d] = X.v[d], saved_[6 * i + 3 + d] = X.w[d];
            X.v[d] = X.w[d] = 0;
        }
    }
    // The rows' biases are −separation − slop (setup_rows), the blocks' their rows'.
    for (Block& k : blocks_)
        for (std::size_t j = 0; j < k.count; ++j) k.bias[j] = rows_[k.first + j].bias;
    load_groups();
    for (int it = 0; it < options_.position_iterations; ++it)
        if (!with_lanes([&](auto lanes) { return position_pass<lanes()>(); })) break;
    // The rows' separations after the passes, for the velocity passes' speculative bias and the
    // collisions; then the bodies moved and turned, their velocities back.
    // The velocity passes search each block's pressing points afresh: a set the corrections
    // ended with, tried first, would pick among a face's many ways of holding (its K has rank 3)
    // one that tilts it — the pile then sinks twice as deep.
    for (Block& k : blocks_) k.last_known = false;
    for (Row& c : rows_) {
        c.sep += normal_velocity(c, bodies_[c.a], bodies_[c.b]);
        c.bias = -std::max(c.sep, 0.0) / dt;
    }
    for (std::size_t i = 0; i < nb; ++i) {
        Body& X = bodies_[i];
        for (int d = 0; d < 3; ++d) X.p[d] += X.v[d];
        if (X.w[0] != 0 || X.w[1] != 0 || X.w[2] != 0) rotate_by(X.q, X.w);
        for (int d = 0; d < 3; ++d) X.v[d] = saved_[6 * i + d], X.w[d] = saved_[6 * i + 3 + d];
    }
}

} // namespace phynjo::runtime::contact_detail
