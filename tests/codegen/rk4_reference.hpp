#pragma once
// What the tests of the variable-step solvers (test_cvode, test_ida) compare with: RK4 at a
// small fixed step (projected onto the constraints after each step for constrained models),
// and the largest difference of q and q' between two worlds.
#include "phynjo/runtime/simulate/generated.hpp"

#include <algorithm>
#include <cmath>

namespace test {

inline double difference(const phynjo::runtime::World& a, const phynjo::runtime::World& b, std::size_t n) {
    using phynjo::runtime::kGQ, phynjo::runtime::kGV;
    double d = 0;
    for (auto f : {kGQ, kGV})
        for (std::size_t i = 0; i < n; ++i) d = std::max(d, std::fabs(a.at(f, i) - b.at(f, i)));
    return d;
}

inline phynjo::runtime::World rk4_reference(const phynjo::runtime::LagrangianSystem& s, double t_end, double dt) {
    phynjo::runtime::World w = phynjo::runtime::make_lagrangian_world(s);
    phynjo::runtime::Stepper st(phynjo::runtime::lagrangian_rk4(s, w.layout_ptr()));
    const long steps = std::lround(t_end / dt);
    for (long k = 0; k < steps; ++k) st.step(w, dt);
    return w;
}

} // namespace test
