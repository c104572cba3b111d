// The generated functions of the example models, evaluated at states read from stdin, for
// sympy_check.py (an independent SymPy derivation) to compare with: accelerations, momenta
// and energy at the parameters' defaults.
// usage: sympy_probe MODEL   stdin: one state a line, "t q_1 … q_n qdot_1 … qdot_n"
//        stdout: one line a state, "qddot_1 … qddot_n p_1 … p_n E" (17 significant digits)
#include "cart_pole.hpp"
#include "double_pendulum.hpp"
#include "nlink_cart_5.hpp"
#include "pendulum.hpp"
#include "spring_pendulum.hpp"

#include <cstdio>
#include <iostream>
#include <string_view>
#include <vector>

namespace {

template <typename Parameters, std::size_t dof>
struct Model {
    void (*accelerations)(const Parameters&, double, std::span<const double>, std::span<const double>, std::span<double>);
    void (*momenta)(const Parameters&, double, std::span<const double>, std::span<const double>, std::span<double>);
    double (*energy)(const Parameters&, double, std::span<const double>, std::span<const double>);
};

template <typename Parameters, std::size_t dof>
int probe(const Model<Parameters, dof>& m) {
    const Parameters P;
    std::vector<double> q(dof), v(dof), a(dof), p(dof);
    double t = 0;
    while (std::cin >> t) {
        for (auto& x : q) std::cin >> x;
        for (auto& x : v) std::cin >> x;
        if (!std::cin) return 1;
        m.accelerations(P, t, q, v, a);
        m.momenta(P, t, q, v, p);
        for (double x : a) std::printf("%.17g ", x);
        for (double x : p) std::printf("%.17g ", x);
        std::printf("%.17g\n", m.energy(P, t, q, v));
    }
    return 0;
}

#define PHYNJO_PROBE(NS)                                                                                     \
    if (name == #NS)                                                                                         \
        return probe(Model<NS::Parameters, NS::dof>{&NS::accelerations, &NS::momenta, &NS::energy});

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: sympy_probe MODEL < states\n");
        return 2;
    }
    const std::string_view name = argv[1];
    PHYNJO_PROBE(pendulum)
    PHYNJO_PROBE(double_pendulum)
    PHYNJO_PROBE(spring_pendulum)
    PHYNJO_PROBE(cart_pole)
    PHYNJO_PROBE(nlink_cart_5)
    std::fprintf(stderr, "sympy_probe: unknown model '%s'\n", argv[1]);
    return 2;
}
