// The contact solver's coupling of model spheres and capsules (scenes): a model's M, G and B = P M⁻¹Jᵀ at the step's state, impulses on its points as changes of q' (or q), the model written back (solver.hpp).
#include "solver.hpp"
#include "cholesky.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace phynjo::runtime::contact_detail {

namespace {
/// The 6 entries (xx, yy, zz, xy, xz, yz) of the symmetric part of a.
void store_symmetric(const double (&a)[3][3], double* A) {
    A[0] = a[0][0], A[1] = a[1][1], A[2] = a[2][2];
    A[3] = 0.5 * (a[0][1] + a[1][0]), A[4] = 0.5 * (a[0][2] + a[2][0]), A[5] = 0.5 * (a[1][2] + a[2][1]);
}
} // namespace

void Solver::gather_model(const World& w, ModelScratch& m, std::size_t index) {
    const LagrangianSystem& s = *m.placed.system;
    const std::size_t n = s.dof, ns = m.placed.spheres.size(), nk = m.placed.ends.size(), nx = m.placed.boxes.size(),
                      nb = 3 * (ns + 2 * nk) + 6 * nx, nc = s.n_constraints;
    for (std::size_t i = 0; i < n; ++i) {
        m.q[i] = w.at(q_field_, m.placed.coordinates[i]);
        m.qd[i] = w.at(qd_field_, m.placed.coordinates[i]);
        if (!std::isfinite(m.q[i]) || !std::isfinite(m.qd[i]))
            throw Error("contact: the state of model '" + m.placed.name + "' is not finite");
    }
    const double t = w.time;
    m.sync.q = m.q; // sizes fixed: no allocation
    m.sync.qd = m.qd;
    sphere_states(m.placed, t, m.sync); // centres, ends, velocities, J and Jc (row-major)
    // Row c of the points' Jacobian: the spheres' 3·ns rows, then the capsules' 6 each, then
    // the boxes' 6 each (centre, spin).
    auto jrow = [&](std::size_t c) {
        return c < 3 * ns ? &m.sync.J[c * n] : c < 3 * ns + 6 * nk ? &m.sync.Jc[(c - 3 * ns) * n] : &m.sync.Jb[(c - 3 * ns - 6 * nk) * n];
    };
    s.mass_matrix(t, m.q, m.qd, m.M);
    if (!cholesky(m.M.data(), n))
        throw Error("contact: the mass matrix of model '" + m.placed.name + "' is not positive definite at t = " +
                    std::to_string(t) + " s: its spheres' effective masses are undefined");
    // B = M⁻¹ Jᵀ (n × 3·ns, row-major), column by column.
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < nb; ++c) m.B[i * nb + c] = jrow(c)[i];
    for (std::size_t c = 0; c < nb; ++c) cholesky_solve(m.M.data(), n, &m.B[c], nb);
    if (nc > 0) { // B ← B − M⁻¹Gᵀ (G M⁻¹ Gᵀ)⁻¹ G B: the impulses keep G Δq' = 0
        s.constraint_matrix(t, m.q, m.G); // nc × n
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t k = 0; k < nc; ++k) m.MinvGt[i * nc + k] = m.G[k * n + i];
        for (std::size_t k = 0; k < nc; ++k) cholesky_solve(m.M.data(), n, &m.MinvGt[k], nc);
        for (std::size_t a = 0; a < nc; ++a)
            for (std::size_t b = 0; b < nc; ++b) {
                double v = 0;
                for (std::size_t i = 0; i < n; ++i) v += m.G[a * n + i] * m.MinvGt[i * nc + b];
                m.S[a * nc + b] = v;
            }
        if (!cholesky(m.S.data(), nc))
            throw Error("contact: the constraints of model '" + m.placed.name + "' are dependent at t = " + std::to_string(t) +
                        " s (G M⁻¹ Gᵀ is singular)");
        for (std::size_t a = 0; a < nc; ++a)
            for (std::size_t c = 0; c < nb; ++c) {
                double v = 0;
                for (std::size_t i = 0; i < n; ++i) v += m.G[a * n + i] * m.B[i * nb + c];
                m.GB[a * nb + c] = v;
            }
        for (std::size_t c = 0; c < nb; ++c) cholesky_solve(m.S.data(), nc, &m.GB[c], nb);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t c = 0; c < nb; ++c) {
                double v = 0;
                for (std::size_t a = 0; a < nc; ++a) v += m.MinvGt[i * nc + a] * m.GB[a * nb + c];
                m.B[i * nb + c] -= v;
            }
    }
    for (std::size_t j = 0; j < ns; ++j) {
        double a[3][3];
        for (std::size_t r = 0; r < 3; ++r)
            for (std::size_t c = 0; c < 3; ++c) {
                double v = 0;
                for (std::size_t i = 0; i < n; ++i) v += m.sync.J[(3 * j + r) * n + i] * m.B[i * nb + 3 * j + c];
                a[r][c] = v;
            }
        store_symmetric(a, &m.A[6 * j]); // J_s B_s: symmetric up to round-off
        Body& b = bodies_[m.first + j];
        b = Body{};
        b.model = static_cast<int>(index);
        b.sphere = static_cast<int>(j);
        b.r = m.placed.radii[j];
        for (std::size_t k = 0; k < 3; ++k) {
            b.p[k] = m.sync.P[3 * j + k];
            b.v[k] = m.sync.V[3 * j + k];
        }
    }
    for (std::size_t k = 0; k < nk; ++k) {
        // A_ij = J_i B_j of the ends i, j: A₁₁, A₂₂ and the symmetric part of A₁₂
        const std::size_t e1 = 3 * ns + 6 * k, e2 = e1 + 3;
        double* A = &m.A[6 * ns + 18 * k];
        const std::size_t at[3][2] = {{e1, e1}, {e2, e2}, {e1, e2}};
        for (int x = 0; x < 3; ++x) {
            double a[3][3];
            for (std::size_t r = 0; r < 3; ++r)
                for (std::size_t c = 0; c < 3; ++c) {
                    const double* row = jrow(at[x][0] + r);
                    double v = 0;
                    for (std::size_t i = 0; i < n; ++i) v += row[i] * m.B[i * nb + at[x][1] + c];
                    a[r][c] = v;
                }
            store_symmetric(a, A + 6 * x);
        }
        Body& b = bodies_[m.first_capsule + k];
        b = Body{};
        b.model = static_cast<int>(index);
        b.sphere = static_cast<int>(k);
        b.shape = Shape::capsule;
        b.r = m.placed.capsule_radii[k];
        for (std::size_t d = 0; d < 3; ++d) {
            b.p[d] = m.sync.E[6 * k + d];
            b.p2[d] = m.sync.E[6 * k + 3 + d];
            b.v[d] = m.sync.EV[6 * k + d];
            b.v2[d] = m.sync.EV[6 * k + 3 + d];
        }
    }
    for (std::size_t k = 0; k < nx; ++k) {
        // A_box = G B_box, G the box's 6 rows (centre, spin): its generalised inverse mass
        const std::size_t c0 = 3 * (ns + 2 * nk) + 6 * k;
        double* A = &m.A[6 * ns + 18 * nk + 36 * k];
        for (std::size_t r = 0; r < 6; ++r)
            for (std::size_t c = 0; c < 6; ++c) {
                const double* row = jrow(c0 + r);
                double v = 0;
                for (std::size_t i = 0; i < n; ++i) v += row[i] * m.B[i * nb + c0 + c];
                A[6 * r + c] = v;
            }
        for (std::size_t r = 0; r < 6; ++r) // symmetric up to round-off
            for (std::size_t c = r + 1; c < 6; ++c) A[6 * r + c] = A[6 * c + r] = 0.5 * (A[6 * r + c] + A[6 * c + r]);
        Body& b = bodies_[m.first_box + k];
        b = Body{};
        b.model = static_cast<int>(index);
        b.sphere = static_cast<int>(k);
        b.shape = Shape::box;
        for (std::size_t d = 0; d < 3; ++d) {
            b.p[d] = m.sync.BX[7 * k + d];
            b.v[d] = m.sync.BV[6 * k + d];
            b.w[d] = m.sync.BV[6 * k + 3 + d];
            b.h[d] = m.placed.box_half_extents[3 * k + d];
        }
        for (std::size_t d = 0; d < 4; ++d) b.q[d] = m.sync.BX[7 * k + 3 + d];
    }
}

void Solver::model_impulse(const Body& X, const double* lambda, std::vector<Body>& B, bool position, double s,
                           const double* arm) {
    ModelScratch& m = models_[static_cast<std::size_t>(X.model)];
    const std::size_t n = m.q.size(), ns = m.placed.spheres.size(), nk = m.placed.ends.size(),
                      nb = 3 * (ns + 2 * nk) + 6 * m.placed.boxes.size();
    if (X.shape == Shape::box) { // the wrench (Λ, arm × Λ)
        double moment[3] = {0, 0, 0};
        if (arm != nullptr) cross(arm, lambda, moment);
        model_wrench(X, lambda, moment, B, position);
        return;
    }
    if (X.shape == Shape::capsule) { // B(s) Λ = (1 − s) B₁ Λ + s B₂ Λ
        const std::size_t c = 3 * ns + 6 * static_cast<std::size_t>(X.sphere);
        for (std::size_t i = 0; i < n; ++i) {
            const double* row = &m.B[i * nb + c];
            m.dq[i] = (1 - s) * (row[0] * lambda[0] + row[1] * lambda[1] + row[2] * lambda[2]) +
                      s * (row[3] * lambda[0] + row[4] * lambda[1] + row[5] * lambda[2]);
        }
    } else {
        const std::size_t c = 3 * static_cast<std::size_t>(X.sphere);
        for (std::size_t i = 0; i < n; ++i) {
            const double* row = &m.B[i * nb + c];
            m.dq[i] = row[0] * lambda[0] + row[1] * lambda[1] + row[2] * lambda[2];
        }
    }
    follow_model(m, B, position);
}

void Solver::follow_model(ModelScratch& m, std::vector<Body>& B, bool position) {
    const std::size_t n = m.q.size(), ns = m.placed.spheres.size(), nk = m.placed.ends.size(), nx = m.placed.boxes.size();
    std::vector<double>& target = position ? m.q : m.qd;
    for (std::size_t i = 0; i < n; ++i) target[i] += m.dq[i];
    for (std::size_t j = 0; j < ns; ++j) {
        Body& b = B[m.first + j];
        double* out = position ? b.p : b.v;
        for (std::size_t k = 0; k < 3; ++k) {
            const double* row = &m.sync.J[(3 * j + k) * n];
            double d = 0;
            for (std::size_t i = 0; i < n; ++i) d += row[i] * m.dq[i];
            out[k] += d;
        }
    }
    for (std::size_t j = 0; j < nk; ++j) {
        Body& b = B[m.first_capsule + j];
        double* out[2] = {position ? b.p : b.v, position ? b.p2 : b.v2};
        for (std::size_t e = 0; e < 6; ++e) {
            const double* row = &m.sync.Jc[(6 * j + e) * n];
            double d = 0;
            for (std::size_t i = 0; i < n; ++i) d += row[i] * m.dq[i];
            out[e / 3][e % 3] += d;
        }
    }
    for (std::size_t j = 0; j < nx; ++j) { // a box's centre moves, and it turns by J_ω Δq
        Body& b = B[m.first_box + j];
        double d6[6];
        for (std::size_t e = 0; e < 6; ++e) {
            const double* row = &m.sync.Jb[(6 * j + e) * n];
            double d = 0;
            for (std::size_t i = 0; i < n; ++i) d += row[i] * m.dq[i];
            d6[e] = d;
        }
        for (int d = 0; d < 3; ++d) (position ? b.p : b.v)[d] += d6[d];
        if (position) rotate_by(b.q, d6 + 3);
        else
            for (int d = 0; d < 3; ++d) b.w[d] += d6[3 + d];
    }
}

double Solver::model_box_k(const Body& X, const double* g1, const double* g2) const {
    const ModelScratch& m = models_[static_cast<std::size_t>(X.model)];
    const double* a = &m.A[6 * m.placed.spheres.size() + 18 * m.placed.ends.size() + 36 * static_cast<std::size_t>(X.sphere)];
    double k = 0;
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) k += g1[r] * a[6 * r + c] * g2[c];
    return k;
}

void Solver::model_wrench(const Body& X, const double* force, const double* moment, std::vector<Body>& B, bool position) {
    ModelScratch& m = models_[static_cast<std::size_t>(X.model)];
    const std::size_t n = m.q.size(), nb = 3 * (m.placed.spheres.size() + 2 * m.placed.ends.size()) + 6 * m.placed.boxes.size();
    const double g[6] = {force[0], force[1], force[2], moment[0], moment[1], moment[2]};
    const std::size_t c = 3 * (m.placed.spheres.size() + 2 * m.placed.ends.size()) + 6 * static_cast<std::size_t>(X.sphere);
    for (std::size_t i = 0; i < n; ++i) {
        const double* row = &m.B[i * nb + c];
        double d = 0;
        for (int e = 0; e < 6; ++e) d += row[e] * g[e];
        m.dq[i] = d;
    }
    follow_model(m, B, position);
}

void Solver::scatter_model(World& w, ModelScratch& m) {
    for (std::size_t i = 0; i < m.q.size(); ++i) {
        w.at(q_field_, m.placed.coordinates[i]) = m.q[i];
        w.at(qd_field_, m.placed.coordinates[i]) = m.qd[i];
    }
    sync_model_spheres(m.placed, q_field_, qd_field_, w.time, w, m.sync); // the exact centres at the corrected q
}

} // namespace phynjo::runtime::contact_detail
