#pragma once
/// \file
/// The forces DSL in 1-D: force generators on NState worlds (gravity, springs, anchors,
/// drag, 1-D Newtonian gravity, custom terms) that add and scale, each with its potential.
/// They lower to rules through the NState kick, and with the NState drift make the
/// splitting the symplectic integrators compose.
#include "phynjo/runtime/core/splitting.hpp"
#include "phynjo/runtime/particles/nstate.hpp"

#include <functional>
#include <span>
#include <string>
#include <vector>

namespace phynjo::runtime {

/// A force on 1-D point masses (NState worlds), as a sum of terms. Each term adds its
/// contribution F_i (N) into a buffer and may define a potential energy (J).
class Force1D {
public:
    struct Term {
        std::string name;
        ComponentSet targets; ///< components that receive a force
        std::vector<FieldId> fields_read; ///< q, p and/or m
        ComponentSet sources; ///< components whose state it reads
        std::function<void(const World&, double scale, std::span<double> F)> add;
        std::function<double(const World&)> potential; ///< empty: non-conservative
        double scale = 1;
    };

    /// Uniform gravity along −q: F_i = −m_i g. Potential Σ m_i g q_i.
    static Force1D gravity(double g, const ComponentSet& bodies);
    /// Hooke spring between i and j with stiffness k (N/m) and rest length l0 (m):
    /// F_i = −k (|q_i − q_j| − l0) sgn(q_i − q_j), F_j = −F_i. Potential ½k(|q_i−q_j|−l0)².
    static Force1D spring(Index i, Index j, double k, double rest_length);
    /// Spring from i to a fixed anchor at position a: F_i = −k (q_i − a − l0)… (1-D, l0 along +q).
    static Force1D anchor(Index i, double anchor, double k, double rest_length = 0);
    /// Linear drag F_i = −γ v_i = −γ p_i/m_i (γ in kg/s). Not conservative.
    static Force1D drag(double gamma, const ComponentSet& bodies);
    /// Newtonian gravity in 1-D: F_i = Σ_j G m_i m_j sgn(q_j − q_i)/(q_j − q_i)², each pair
    /// once. Potential −Σ_{i<j} G m_i m_j/|q_i − q_j|.
    static Force1D newtonian(double G, const ComponentSet& bodies);
    /// Any pure function of the world that adds into F for `targets`, reading `sources`.
    static Force1D custom(std::string name, ComponentSet targets, ComponentSet sources,
                          std::function<void(const World&, std::span<double> F)> add);

    friend Force1D operator+(Force1D a, const Force1D& b);
    friend Force1D operator*(double s, Force1D f);

    /// F ← F + force (F has one entry per component of the world).
    void accumulate(const World& w, std::span<double> F) const;
    /// The potential energy of the conservative terms, J.
    [[nodiscard]] double potential(const World& w) const;
    [[nodiscard]] ComponentSet targets() const;
    /// The entries the force reads (for the kick's domain).
    [[nodiscard]] Domain reads() const;
    [[nodiscard]] const std::vector<Term>& terms() const noexcept { return terms_; }

private:
    std::vector<Term> terms_;
};

/// p_i ← p_i + c·dt·F_i for the force's targets. Domain: p of the targets.
NumericRule kick(const Force1D& force, double c, const std::shared_ptr<const Layout>& layout);

/// Total energy of an NState under `force`: Σ p²/2m + potential.
double total_energy(const World& nstate, const Force1D& force);

/// drift/kick of 1-D point masses `bodies` under `force` (for symplectic_euler, leapfrog_dkd,
/// leapfrog_kdk, forest_ruth).
Splitting nstate_splitting(const Force1D& force, const ComponentSet& bodies, std::shared_ptr<const Layout> layout);

} // namespace phynjo::runtime
