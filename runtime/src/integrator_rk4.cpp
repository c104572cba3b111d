// Classical fourth-order Runge–Kutta on y = (q, p), y' = f(y) = (p/m, F(q, p)):
//   k1 = f(y0), k2 = f(y0 + dt/2·k1), k3 = f(y0 + dt/2·k2), k4 = f(y0 + dt·k3),
//   y1 = y0 + dt/6·(k1 + 2k2 + 2k3 + k4).
// Order 4; not symplectic (energy drifts slowly over long runs). Written as five rules over
// stage fields of the world — save y0; four stages that each evaluate f at the current
// stage point, add w_i·k_i to the accumulator and move to the next stage point; the last
// stage writes y1 — so the state of a step is all in the world.
// Reference: W. Kutta, Z. Math. Phys. 46, 435 (1901); Hairer, Nørsett, Wanner, Solving
// Ordinary Differential Equations I, §II.1.
#include "phynjo/runtime/integrators.hpp"

namespace phynjo::runtime {

std::vector<std::string> rk4_fields() { return {"rk4_q0", "rk4_p0", "rk4_aq", "rk4_ap"}; }

NumericWorkflow rk4(const Force1D& force, const ComponentSet& bodies, std::shared_ptr<const Layout> layout) {
    const FieldId q0 = layout->field("rk4_q0"), p0 = layout->field("rk4_p0");
    const FieldId aq = layout->field("rk4_aq"), ap = layout->field("rk4_ap");
    const Domain state = Domain(kQ, bodies) | Domain(kP, bodies);
    const Domain storage = Domain(q0, bodies) | Domain(p0, bodies) | Domain(aq, bodies) | Domain(ap, bodies);
    const Domain reads = force.reads() | Domain(kM, bodies);

    NumericRule save{"rk4_save", storage, state, nullptr, layout};
    save.step = [=](double, World& w) {
        for (Index i : bodies.indices()) {
            w.at(q0, i) = w.at(kQ, i);
            w.at(p0, i) = w.at(kP, i);
            w.at(aq, i) = w.at(ap, i) = 0;
        }
    };
    // Stage: k = f(current); acc += weight·k; current = y0 + next·dt·k (or, last, y0 + dt·(acc)).
    auto stage = [&](const std::string& name, double weight, double next, bool last) {
        NumericRule r{name, state | storage, reads, nullptr, layout};
        r.step = [=](double dt, World& w) {
            thread_local std::vector<double> F;
            F.assign(w.size(), 0.0);
            force.accumulate(w, F);
            for (Index i : bodies.indices()) {
                const double kq = w.at(kP, i) / w.at(kM, i), kp = F[i];
                w.at(aq, i) += weight * kq;
                w.at(ap, i) += weight * kp;
                if (last) {
                    w.at(kQ, i) = w.at(q0, i) + dt * w.at(aq, i);
                    w.at(kP, i) = w.at(p0, i) + dt * w.at(ap, i);
                } else {
                    w.at(kQ, i) = w.at(q0, i) + next * dt * kq;
                    w.at(kP, i) = w.at(p0, i) + next * dt * kp;
                }
            }
        };
        return NumericWorkflow::run(r);
    };
    return NumericWorkflow::seq(std::vector<NumericWorkflow>{
        NumericWorkflow::run(save), stage("rk4_k1", 1.0 / 6, 0.5, false), stage("rk4_k2", 2.0 / 6, 0.5, false),
        stage("rk4_k3", 2.0 / 6, 1.0, false), stage("rk4_k4", 1.0 / 6, 0, true)});
}

} // namespace phynjo::runtime
