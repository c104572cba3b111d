#pragma once
/// \file
/// Derived: a model parameter defined from others (generated Parameters structs).

namespace phynjo::runtime {

/// A model parameter defined from others in the model file (`I = 1/2*Mp*R^2`): the generated
/// code computes it from their current values — it follows them — until a value is assigned
/// to it (`P.I = 0.3`), which fixes it. `P.I = Derived::following(v)` makes it follow again.
class Derived {
public:
    /// Assigning a number fixes the parameter at that value.
    constexpr Derived(double value) noexcept : value_(value), set_(true) {} // NOLINT: implicit on purpose
    /// Following its definition; `file_default` is its value at the file's defaults.
    static constexpr Derived following(double file_default) noexcept {
        Derived d(file_default);
        d.set_ = false;
        return d;
    }
    /// True once a value was assigned.
    [[nodiscard]] constexpr bool is_set() const noexcept { return set_; }
    /// The assigned value, or (while following) the value at the file's defaults.
    [[nodiscard]] constexpr double value() const noexcept { return value_; }

private:
    double value_;
    bool set_;
};

} // namespace phynjo::runtime
