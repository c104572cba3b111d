#pragma once
// The n-link pendulum on a cart (examples/models/nlink_cart.py; SymPy's
// n_link_pendulum_on_cart), built directly with the CAS: cart position q0, link angles q1..qN
// from the upward vertical, point masses m0..mN, link lengths l1..lN, gravity g along -y.
#include "phynjo/cas/cas.hpp"

#include <string>
#include <vector>

namespace phynjo::bench {

struct NLinkModel {
    std::vector<cas::Expr> coordinates;
    cas::Expr lagrangian;
};

inline NLinkModel nlink_cart(int n) {
    using namespace cas;
    NLinkModel model;
    for (int i = 0; i <= n; ++i) model.coordinates.push_back(symbol("q" + std::to_string(i)));
    const auto& q = model.coordinates;
    const Expr g = symbol("g");
    Expr x = q[0], y = Expr(0);
    std::vector<Expr> kinetic, potential;
    for (int i = 0; i <= n; ++i) {
        if (i > 0) {
            const Expr l = symbol("l" + std::to_string(i));
            x = x - l * sin(q[i]);
            y = y + l * cos(q[i]);
        }
        const Expr m = symbol("m" + std::to_string(i));
        const Expr xd = total_time_derivative(x, q), yd = total_time_derivative(y, q);
        kinetic.push_back(rational(1, 2) * m * (pow(xd, Expr(2)) + pow(yd, Expr(2))));
        potential.push_back(m * y);
    }
    model.lagrangian = add(kinetic) - g * add(potential);
    return model;
}

} // namespace phynjo::bench
