// Classical RK4 on y = (q, q'), y' = (q', q''(t, q, q')) for generated models, as one rule
// (the five stages of rk4_stages.hpp fused: the same operations in the same order, so the
// same bits, without an interpreter action and a scratch fill per stage). Order 4; not
// symplectic. Reference: W. Kutta, Z. Math. Phys. 46, 435 (1901); Hairer, Nørsett, Wanner,
// Solving Ordinary Differential Equations I, §II.1. Constrained models: RK4 on the index-1
// system (q'' from the KKT solve), then a projection onto the constraints (Hairer, Lubich,
// Wanner, Geometric Numerical Integration, §IV.4). A system with generated code's fused
// kernel `rk4_step` takes its step from it: the same operations in the same order, with the
// stages' accelerations inlined (tests/codegen/test_kernels.cpp compares the two, bit for bit).
#include "phynjo/runtime/integrators/lagrangian_rk4.hpp"

#include <vector>

namespace phynjo::runtime {

NumericWorkflow lagrangian_rk4(const LagrangianSystem& s, const std::shared_ptr<const Layout>& layout,
                               const ProjectionOptions& projection) {
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(s.dof));
    const Domain state = Domain(kGQ, all) | Domain(kGV, all);
    const Domain storage = Domain(kGRkQ0, all) | Domain(kGRkV0, all) | Domain(kGRkAQ, all) | Domain(kGRkAV, all);
    NumericRule r{"lagrangian_rk4", state | storage, {}, nullptr, layout};
    if (s.rk4_step) // generated code's fused step: the operations below, in their order
        r.step = [acc = s.accelerations, step = s.rk4_step, n = s.dof](double dt, World& w) {
            thread_local std::vector<double> kv;
            if (kv.size() < n) kv.resize(n);
            const std::span<double> k(kv.data(), n);
            acc(w.time + 0.0 * dt, w.field(kGQ), w.field(kGV), k);
            step(w.time, dt, w.field(kGQ), w.field(kGV), k);
        };
    else
    r.step = [acc = s.accelerations, n = s.dof](double dt, World& w) {
        // q'' of each stage; per thread, so that one workflow may step worlds on several threads
        thread_local std::vector<double> kv;
        if (kv.size() < n) kv.resize(n);
        double *q = w.field(kGQ).data(), *v = w.field(kGV).data(), *q0 = w.field(kGRkQ0).data(),
               *v0 = w.field(kGRkV0).data(), *aq = w.field(kGRkAQ).data(), *av = w.field(kGRkAV).data();
        for (std::size_t i = 0; i < n; ++i) {
            q0[i] = q[i];
            v0[i] = v[i];
            aq[i] = av[i] = 0;
        }
        const std::span<double> k(kv.data(), n);
        auto stage = [&](double c, double weight, double next, bool last) {
            acc(w.time + c * dt, w.field(kGQ), w.field(kGV), k);
            for (std::size_t i = 0; i < n; ++i) {
                const double kq = v[i], kvi = k[i]; // k_q = q' at the stage's state
                aq[i] += weight * kq;
                av[i] += weight * kvi;
                if (last) {
                    q[i] = q0[i] + dt * aq[i];
                    v[i] = v0[i] + dt * av[i];
                } else {
                    q[i] = q0[i] + next * dt * kq;
                    v[i] = v0[i] + next * dt * kvi;
                }
            }
        };
        stage(0.0, 1.0 / 6, 0.5, false);
        stage(0.5, 2.0 / 6, 0.5, false);
        stage(0.5, 2.0 / 6, 1.0, false);
        stage(1.0, 1.0 / 6, 0, true);
    };
    NumericWorkflow rk4 = NumericWorkflow::run(r);
    if (s.n_constraints == 0) return rk4;
    return NumericWorkflow::seq(rk4, NumericWorkflow::run(constraint_projection_rule(s, layout, projection)));
}

} // namespace phynjo::runtime
