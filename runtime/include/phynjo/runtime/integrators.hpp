#pragma once
/// \file
/// Integrators built as workflows of drift and kick rules (one source file each, with its
/// order, symplecticity and reference).
#include "phynjo/runtime/forces.hpp"

namespace phynjo::runtime {

/// The two flows a splitting method alternates: drift(c) advances positions by c·dt with
/// the momenta held, kick(c) advances momenta by c·dt with the positions held.
struct Splitting {
    std::function<NumericRule(double c)> drift;
    std::function<NumericRule(double c)> kick;
};

/// drift/kick of 1-D point masses `bodies` under `force`.
Splitting nstate_splitting(const Force1D& force, const ComponentSet& bodies, std::shared_ptr<const Layout> layout);

/// Symplectic Euler: kick(1) then drift(1). Order 1, symplectic.
NumericWorkflow symplectic_euler(const Splitting& s);
/// Leapfrog, drift-kick-drift (Störmer–Verlet). Order 2, symplectic, time-reversible.
NumericWorkflow leapfrog_dkd(const Splitting& s);
/// Leapfrog, kick-drift-kick (velocity Verlet). Order 2, symplectic, time-reversible.
NumericWorkflow leapfrog_kdk(const Splitting& s);
/// Forest–Ruth: three leapfrog stages with θ = 1/(2 − 2^(1/3)). Order 4, symplectic.
NumericWorkflow forest_ruth(const Splitting& s);

/// The stage storage rk4 needs in an NState world (make_nstate(…, …, rk4_fields())).
std::vector<std::string> rk4_fields();
/// Classical Runge–Kutta on q' = p/m, p' = F(q, p): save, four stages, combine — five
/// rules over the world's stage fields. Order 4, not symplectic.
NumericWorkflow rk4(const Force1D& force, const ComponentSet& bodies, std::shared_ptr<const Layout> layout);

} // namespace phynjo::runtime
