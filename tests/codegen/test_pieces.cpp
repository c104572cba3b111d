// Function bodies computed in pieces (phynjo-lagc --pieces-above, emit: cpp_body.cpp) against
// the same models emitted whole: every generated function, bit for bit, at random states.
// The *_pieces models are copies of the originals under another name, emitted with
// --pieces-above 1 (every body in pieces, split over --parts 4 files; tests/CMakeLists.txt).
// Bugs caught: a temporary read before the piece that computes it, an output stored into
// the wrong element, an early output (M, f, G, γ before the saddle-point solve) left in the
// late part, consecutive outputs copied from the wrong offset, a part file missing a function.
#include "driven.hpp"
#include "driven_pieces.hpp"
#include "four_bar.hpp"
#include "four_bar_pieces.hpp"
#include "nlink_cart_5.hpp"
#include "nlink_cart_5_pieces.hpp"
#include "relativistic.hpp"
#include "relativistic_pieces.hpp"

#include <catch2/catch.hpp>

#include <cstring>
#include <random>
#include <vector>

namespace {

/// Bitwise equality of two arrays (NaNs included).
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
    // (memcmp of empty vectors would be handed null pointers: UBSan)
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

/// Calls `f(P, t, q, qdot, out)` of both models and compares the outputs.
#define PHYNJO_SAME(fn, size, ...)                                                                                     \
    do {                                                                                                               \
        std::vector<double> a(size), b(size);                                                                          \
        A::fn(pa, t, q, v, a __VA_ARGS__);                                                                             \
        B::fn(pb, t, q, v, b __VA_ARGS__);                                                                             \
        INFO(#fn);                                                                                                     \
        CHECK(same_bits(a, b));                                                                                        \
    } while (0)

template <typename Pa, typename Pb, std::size_t n, std::size_t m, std::size_t u, typename Run>
void compare_at_random_states(Run run) {
    std::mt19937_64 rng(20261201);
    std::uniform_real_distribution<double> d(-1.0, 1.0);
    for (int k = 0; k < 20; ++k) {
        std::vector<double> q(n), v(n);
        for (auto& x : q) x = d(rng);
        for (auto& x : v) x = d(rng);
        const double t = 0.5 * (1 + d(rng));
        run(Pa{}, Pb{}, t, std::span<const double>(q), std::span<const double>(v));
    }
}

} // namespace

#define PHYNJO_COMPARE_MODEL(NA, NB)                                                                                   \
    do {                                                                                                               \
        namespace A = NA;                                                                                              \
        namespace B = NB;                                                                                              \
        constexpr std::size_t n = A::dof, m = A::n_constraints, u = A::n_inputs;                                       \
        STATIC_REQUIRE(n == B::dof);                                                                                   \
        compare_at_random_states<A::Parameters, B::Parameters, n, m, u>(                                              \
            [](const auto& pa, const auto& pb, double t, auto q, auto v) {                                            \
                {                                                                                                      \
                    std::vector<double> a(n * n), b(n * n);                                                            \
                    if constexpr (requires { A::mass_matrix(pa, t, q, v, std::span<double>(a)); }) {                   \
                        A::mass_matrix(pa, t, q, v, a);                                                                \
                        B::mass_matrix(pb, t, q, v, b);                                                                \
                    } else {                                                                                           \
                        A::mass_matrix(pa, t, q, a);                                                                   \
                        B::mass_matrix(pb, t, q, b);                                                                   \
                    }                                                                                                  \
                    CHECK(same_bits(a, b));                                                                            \
                }                                                                                                      \
                PHYNJO_SAME(forcing, n);                                                                               \
                PHYNJO_SAME(accelerations, n);                                                                         \
                PHYNJO_SAME(momenta, n);                                                                               \
                PHYNJO_SAME(generalized_forces, n);                                                                    \
                CHECK(A::energy(pa, t, q, v) == B::energy(pb, t, q, v));                                               \
                PHYNJO_SAME(rhs_jacobian, 4 * n * n);                                                                  \
                PHYNJO_SAME(input_jacobian, 2 * n * u);                                                                \
                if constexpr (m > 0) {                                                                                 \
                    PHYNJO_SAME(constraint_residuals, m);                                                              \
                    PHYNJO_SAME(constraint_velocity_residuals, m);                                                     \
                    PHYNJO_SAME(constraint_gamma, m);                                                                  \
                    std::vector<double> a(n), b(n), la(m), lb(m);                                                      \
                    A::accelerations_and_multipliers(pa, t, q, v, a, la);                                              \
                    B::accelerations_and_multipliers(pb, t, q, v, b, lb);                                              \
                    CHECK(same_bits(a, b));                                                                            \
                    CHECK(same_bits(la, lb));                                                                          \
                }                                                                                                      \
                std::vector<double> pa_(n), pb_(n), Fa(n), Fb(n), dpa(2 * n * n), dpb(2 * n * n), dFa(2 * n * n),      \
                    dFb(2 * n * n);                                                                                    \
                A::canonical_jacobian(pa, t, q, v, pa_, Fa, dpa, dFa);                                                 \
                B::canonical_jacobian(pb, t, q, v, pb_, Fb, dpb, dFb);                                                 \
                CHECK(same_bits(pa_, pb_));                                                                            \
                CHECK(same_bits(Fa, Fb));                                                                              \
                CHECK(same_bits(dpa, dpb));                                                                            \
                CHECK(same_bits(dFa, dFb));                                                                            \
            });                                                                                                        \
    } while (0)

TEST_CASE("Bodies in pieces = whole bodies, bit for bit: nlink_cart_5 (LDL^T)", "[codegen][pieces]") {
    PHYNJO_COMPARE_MODEL(nlink_cart_5, nlink_cart_5_pieces);
}
TEST_CASE("Bodies in pieces = whole bodies, bit for bit: four_bar (constraints: q'' and lambda between the halves)",
          "[codegen][pieces]") {
    PHYNJO_COMPARE_MODEL(four_bar, four_bar_pieces);
}
TEST_CASE("Bodies in pieces = whole bodies, bit for bit: driven (inputs, t)", "[codegen][pieces]") {
    PHYNJO_COMPARE_MODEL(driven, driven_pieces);
}
TEST_CASE("Bodies in pieces = whole bodies, bit for bit: relativistic (M depends on q')", "[codegen][pieces]") {
    PHYNJO_COMPARE_MODEL(relativistic, relativistic_pieces);
}
