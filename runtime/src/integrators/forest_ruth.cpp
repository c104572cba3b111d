// Forest–Ruth: the triple-jump composition of leapfrog with θ = 1/(2 − 2^(1/3)):
//   D(θ/2) K(θ) D((1−θ)/2) K(1−2θ) D((1−θ)/2) K(θ) D(θ/2)
// Order 4; symplectic (a composition of symplectic maps). The middle kick has a negative
// coefficient (1 − 2θ ≈ −1.70).
// Reference: E. Forest, R. D. Ruth, Physica D 43, 105 (1990); H. Yoshida, Phys. Lett. A 150,
// 262 (1990).
#include "phynjo/runtime/integrators/forest_ruth.hpp"

#include <cmath>

namespace phynjo::runtime {

NumericWorkflow forest_ruth(const Splitting& s) {
    using W = NumericWorkflow;
    const double theta = 1.0 / (2.0 - std::cbrt(2.0));
    return W::seq(std::vector<W>{W::run(s.drift(theta / 2)), W::run(s.kick(theta)),
                                 W::run(s.drift((1 - theta) / 2)), W::run(s.kick(1 - 2 * theta)),
                                 W::run(s.drift((1 - theta) / 2)), W::run(s.kick(theta)),
                                 W::run(s.drift(theta / 2))});
}

} // namespace phynjo::runtime
