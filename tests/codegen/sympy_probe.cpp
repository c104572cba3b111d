// The generated functions of the example models, evaluated at states read from stdin, for
// sympy_check.py (an independent SymPy derivation) to compare with: accelerations, momenta
// and energy at the parameters' defaults; for constrained models also the multipliers (for
// sympy_constraints.py).
// usage: sympy_probe MODEL   stdin: one state a line, "t q_1 … q_n qdot_1 … qdot_n"
//        stdout: one line a state, "qddot_1 … qddot_n p_1 … p_n E lambda_1 … lambda_m"
//        (17 significant digits)
#include "atwood.hpp"
#include "bead_on_rod.hpp"
#include "cart_pole.hpp"
#include "cartesian_double_pendulum.hpp"
#include "cartesian_pendulum.hpp"
#include "double_pendulum.hpp"
#include "four_bar.hpp"
#include "functions.hpp"
#include "knife_edge.hpp"
#include "nlink_cart_5.hpp"
#include "pendulum.hpp"
#include "rolling_disk.hpp"
#include "slider_crank.hpp"
#include "spring_pendulum.hpp"

#include <cstdio>
#include <iostream>
#include <string_view>
#include <vector>

namespace {

template <typename Parameters, std::size_t dof, std::size_t nc>
struct Model {
    void (*accelerations)(const Parameters&, double, std::span<const double>, std::span<const double>, std::span<double>,
                          std::span<double>);
    void (*momenta)(const Parameters&, double, std::span<const double>, std::span<const double>, std::span<double>);
    double (*energy)(const Parameters&, double, std::span<const double>, std::span<const double>);
};

template <typename Parameters, std::size_t dof, std::size_t nc>
int probe(const Model<Parameters, dof, nc>& m) {
    const Parameters P;
    std::vector<double> q(dof), v(dof), a(dof), p(dof), lambda(nc);
    double t = 0;
    while (std::cin >> t) {
        for (auto& x : q) std::cin >> x;
        for (auto& x : v) std::cin >> x;
        if (!std::cin) return 1;
        m.accelerations(P, t, q, v, a, lambda);
        m.momenta(P, t, q, v, p);
        for (double x : a) std::printf("%.17g ", x);
        for (double x : p) std::printf("%.17g ", x);
        std::printf("%.17g", m.energy(P, t, q, v));
        for (double x : lambda) std::printf(" %.17g", x);
        std::printf("\n");
    }
    return 0;
}

#define PHYNJO_PROBE(NS)                                                                                     \
    if (name == #NS)                                                                                         \
        return probe(Model<NS::Parameters, NS::dof, NS::n_constraints>{&NS::accelerations_and_multipliers, &NS::momenta, \
                                                                       &NS::energy});

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
    PHYNJO_PROBE(cartesian_pendulum)
    PHYNJO_PROBE(cartesian_double_pendulum)
    PHYNJO_PROBE(atwood)
    PHYNJO_PROBE(bead_on_rod)
    PHYNJO_PROBE(knife_edge)
    PHYNJO_PROBE(rolling_disk)
    PHYNJO_PROBE(four_bar)
    PHYNJO_PROBE(slider_crank)
    PHYNJO_PROBE(functions)
    std::fprintf(stderr, "sympy_probe: unknown model '%s'\n", argv[1]);
    return 2;
}
