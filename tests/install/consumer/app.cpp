// Uses a model compiled by phynjo_add_model from an installed phynjo.
#include "pendulum.hpp"

#include <array>
#include <cmath>
#include <cstdio>

int main() {
    const pendulum::Parameters P;
    std::array<double, 1> q{}, v{}, a{};
    pendulum::initial_state(P, q, v);
    pendulum::accelerations(P, 0.0, q, v, a);
    std::printf("theta'' = %.12g\n", a[0]);
    return std::fabs(a[0] + 9.81 * std::sin(1.0)) < 1e-12 ? 0 : 1; // g/l sin(θ0) with θ0 = 1, l = 1
}
