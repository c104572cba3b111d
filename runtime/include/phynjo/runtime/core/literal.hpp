#pragma once
/// \file
/// Literals (docs/architecture.md, glossary): a scalar per component (SLit) and a Boolean
/// flag per component (FlagLit), dense arrays over a registry's indices; an entry never
/// written reads as 0 (false). Quantities with dimensions: unit_literal.hpp.
#include "phynjo/runtime/core/component.hpp"

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

} // namespace phynjo::runtime
