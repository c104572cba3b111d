// Classical fourth-order Runge–Kutta on y = (q, p), y' = f(y) = (p/m, F(q, p)):
//   k1 = f(y0), k2 = f(y0 + dt/2·k1), k3 = f(y0 + dt/2·k2), k4 = f(y0 + dt·k3),
//   y1 = y0 + dt/6·(k1 + 2k2 + 2k3 + k4).
// Order 4; not symplectic (energy drifts slowly over long runs). Written as five rules over
// stage fields of the world — save y0; four stages that each evaluate f at the current
// stage point, add w_i·k_i to the accumulator and move to the next stage point; the last
// stage writes y1 — so the state of a step is all in the world.
// Reference: W. Kutta, Z. Math. Phys. 46, 435 (1901); Hairer, Nørsett, Wanner, Solving
// Ordinary Differential Equations I, §II.1.
#include "phynjo/runtime/integrators/rk4.hpp"

#include "rk4_stages.hpp"

namespace phynjo::runtime {

std::vector<std::string> rk4_fields() { return {"rk4_q0", "rk4_p0", "rk4_aq", "rk4_ap"}; }

NumericWorkflow rk4(const Force1D& force, const ComponentSet& bodies, std::shared_ptr<const Layout> layout) {
    const detail::Rk4Fields f{kQ, kP, layout->field("rk4_q0"), layout->field("rk4_p0"), layout->field("rk4_aq"),
                              layout->field("rk4_ap")};
    const std::vector<Index> idx(bodies.indices().begin(), bodies.indices().end());
    // f(y) = (p/m, F(q, p)); autonomous.
    auto derivative = [force, idx](double, const World& w, std::span<double> kq, std::span<double> kp) {
        force.accumulate(w, kp);
        for (Index i : idx) kq[i] = w.at(kP, i) / w.at(kM, i);
    };
    return detail::rk4_workflow(f, bodies, force.reads() | Domain(kM, bodies), derivative, layout);
}

} // namespace phynjo::runtime
