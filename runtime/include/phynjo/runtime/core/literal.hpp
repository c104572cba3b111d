#pragma once
/// \file
/// The seed's literals: a scalar per component (SLit), a Boolean flag per component
/// (FlagLit) and quantities with physical dimensions checked at compile time (ULiteral).
/// Dense arrays over a registry's indices; an entry never written reads as 0 (false).
#include "phynjo/runtime/core/component.hpp"

#include <boost/units/quantity.hpp>
#include <boost/units/systems/si.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace phynjo::runtime {

/// Scalar literal: one double per component; missing entries read as 0.
class SLit {
public:
    SLit() = default;
    explicit SLit(std::size_t n) : values_(n, 0.0), present_(n, 0) {}

    /// The value of component i, 0 when it was never set.
    [[nodiscard]] double lookup(Index i) const noexcept { return i < values_.size() && present_[i] ? values_[i] : 0.0; }
    [[nodiscard]] bool contains(Index i) const noexcept { return i < present_.size() && present_[i]; }
    /// A copy with component i set to v (pure).
    [[nodiscard]] SLit insert(Index i, double v) const {
        SLit r = *this;
        r.set(i, v);
        return r;
    }
    /// A copy with component i set to f(old value, or `dflt` when missing) (pure).
    [[nodiscard]] SLit adjust(const std::function<double(double)>& f, double dflt, Index i) const {
        SLit r = *this;
        r.set(i, f(contains(i) ? values_[i] : dflt));
        return r;
    }
    /// In place.
    void set(Index i, double v) {
        if (i >= values_.size()) {
            values_.resize(i + 1, 0.0);
            present_.resize(i + 1, 0);
        }
        values_[i] = v;
        present_[i] = 1;
    }
    [[nodiscard]] std::size_t size() const noexcept { return values_.size(); }
    friend bool operator==(const SLit&, const SLit&) = default;

private:
    std::vector<double> values_;
    std::vector<std::uint8_t> present_;
};

/// Boolean flag per component; missing entries read as false.
class FlagLit {
public:
    FlagLit() = default;
    explicit FlagLit(std::size_t n) : flags_(n, 0) {}
    [[nodiscard]] bool lookup(Index i) const noexcept { return i < flags_.size() && flags_[i]; }
    [[nodiscard]] FlagLit insert(Index i, bool v) const {
        FlagLit r = *this;
        r.set(i, v);
        return r;
    }
    void set(Index i, bool v) {
        if (i >= flags_.size()) flags_.resize(i + 1, 0);
        flags_[i] = v ? 1 : 0;
    }
    [[nodiscard]] std::size_t size() const noexcept { return flags_.size(); }
    friend bool operator==(const FlagLit&, const FlagLit&) = default;

private:
    std::vector<std::uint8_t> flags_;
};

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
