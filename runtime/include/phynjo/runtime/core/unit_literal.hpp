#pragma once
/// \file
/// A quantity with physical dimensions per component (ULiteral), checked at compile time
/// by Boost.Units: adding metres to kilograms does not compile. The one runtime header
/// that needs Boost.Units.
#include "phynjo/runtime/core/component.hpp"

#include <boost/units/quantity.hpp>
#include <boost/units/systems/si.hpp>

#include <algorithm>
#include <vector>

namespace phynjo::runtime {

namespace units = boost::units;
namespace si = boost::units::si;
using Length = units::quantity<si::length>;
using Mass = units::quantity<si::mass>;
using Time = units::quantity<si::time>;
using Velocity = units::quantity<si::velocity>;
using Momentum = units::quantity<si::momentum>;
using Force = units::quantity<si::force>;
using Energy = units::quantity<si::energy>;
using Acceleration = units::quantity<si::acceleration>;

/// A quantity of unit `Unit` per component (Boost.Units: the dimension is a type, so adding a
/// ULiteral of metres to one of kilograms does not compile). Missing entries read as 0.
template <typename Unit>
class ULiteral {
public:
    using Quantity = units::quantity<Unit>;
    ULiteral() = default;
    explicit ULiteral(std::size_t n) : values_(n, Quantity::from_value(0.0)) {}
    [[nodiscard]] Quantity lookup(Index i) const noexcept {
        return i < values_.size() ? values_[i] : Quantity::from_value(0.0);
    }
    void set(Index i, Quantity q) {
        if (i >= values_.size()) values_.resize(i + 1, Quantity::from_value(0.0));
        values_[i] = q;
    }
    [[nodiscard]] std::size_t size() const noexcept { return values_.size(); }
    /// Entry-wise sum: only of the same unit.
    friend ULiteral operator+(const ULiteral& a, const ULiteral& b) {
        ULiteral r(std::max(a.size(), b.size()));
        for (std::size_t i = 0; i < r.size(); ++i)
            r.values_[i] = a.lookup(static_cast<Index>(i)) + b.lookup(static_cast<Index>(i));
        return r;
    }

private:
    std::vector<Quantity> values_;
};

} // namespace phynjo::runtime
