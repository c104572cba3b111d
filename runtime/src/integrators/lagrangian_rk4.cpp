// Classical RK4 on y = (q, q'), y' = (q', q''(t, q, q')) for generated models, as the five
// stage rules shared with the NState rk4 (rk4_stages.hpp). Order 4; not symplectic.
// Reference: W. Kutta, Z. Math. Phys. 46, 435 (1901); Hairer, Nørsett, Wanner, Solving
// Ordinary Differential Equations I, §II.1. Constrained models: RK4 on the index-1 system
// (q'' from the KKT solve), then a projection onto the constraints (Hairer, Lubich, Wanner,
// Geometric Numerical Integration, §IV.4).
#include "phynjo/runtime/integrators/lagrangian_rk4.hpp"

#include "rk4_stages.hpp"

namespace phynjo::runtime {

NumericWorkflow lagrangian_rk4(const LagrangianSystem& s, const std::shared_ptr<const Layout>& layout,
                               const ProjectionOptions& projection) {
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(s.dof));
    // f(t, q, q') = (q', q''(t, q, q')); the stage storage is fields 2…5 of the world.
    auto derivative = [acc = s.accelerations](double t, const World& w, std::span<double> kq, std::span<double> kv) {
        const std::size_t n = w.size();
        acc(t, w.field(kGQ), w.field(kGV), kv.first(n));
        for (Index i = 0; i < n; ++i) kq[i] = w.at(kGV, i);
    };
    auto rk4 = detail::rk4_workflow({kGQ, kGV, kGRkQ0, kGRkV0, kGRkAQ, kGRkAV}, all, {}, derivative, layout);
    if (s.n_constraints == 0) return rk4;
    return NumericWorkflow::seq(rk4, NumericWorkflow::run(constraint_projection_rule(s, layout, projection)));
}

} // namespace phynjo::runtime
