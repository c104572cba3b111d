// Compiled by ctest twice: with -DPHYNJO_CONTROL it must compile; without, it must not,
// because it adds metres to kilograms.
#include "phynjo/runtime/core/unit_literal.hpp"

int main() {
    using namespace phynjo::runtime;
    ULiteral<si::length> x(1);
#ifdef PHYNJO_CONTROL
    ULiteral<si::length> y(1);
#else
    ULiteral<si::mass> y(1);
#endif
    auto z = x + y;
    return static_cast<int>(z.size()) - 1;
}
