#pragma once
/// \file
/// Typed exceptions for API misuse, thrown when a workflow is built (never mid-run).
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace phynjo::runtime {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A component label that is not registered.
class UnknownComponent : public Error {
public:
    using Error::Error;
};

/// Two branches of a parallel composition write the same state, or one writes what the
/// other reads. Names the shared entries (`field:component`) and the rules involved.
class DomainOverlapError : public Error {
public:
    DomainOverlapError(std::string message, std::vector<std::string> shared)
        : Error(std::move(message)), shared_(std::move(shared)) {}
    /// The shared entries, as `field:component` (event flags: `component`).
    [[nodiscard]] const std::vector<std::string>& shared() const noexcept { return shared_; }

private:
    std::vector<std::string> shared_;
};

/// A rule wrote outside the domain it declared (found by the checked interpreter mode).
class DomainViolation : public Error {
public:
    using Error::Error;
};

/// A body that cannot exist: non-positive or non-finite mass, and (rigid bodies) a
/// non-unit quaternion or an inertia tensor that is not positive definite.
class InvalidBody : public Error {
public:
    using Error::Error;
};

/// A field name that the world does not have.
class UnknownField : public Error {
public:
    using Error::Error;
};

} // namespace phynjo::runtime

namespace phynjo::runtime {

/// The mass matrix of a generated model is singular at the given state, so M q'' = f cannot
/// be solved (raised by `accelerations`, never a silent NaN).
class SingularMassMatrix : public Error {
public:
    using Error::Error;
};

/// The constraints of a generated model are dependent at the given state (G M⁻¹ Gᵀ is
/// singular: a four-bar linkage at a dead point, two constraints that coincide there), so
/// the multipliers λ of M q'' = f + Gᵀλ, G q'' = γ are not determined. Raised by
/// `accelerations` and `accelerations_and_multipliers`; constraints() names the ones involved.
class SingularConstraints : public Error {
public:
    SingularConstraints(const std::string& message, std::vector<std::string> constraints)
        : Error(message), constraints_(std::move(constraints)) {}
    /// The constraints involved: a dependent one and those it is a combination of.
    [[nodiscard]] const std::vector<std::string>& constraints() const noexcept { return constraints_; }

private:
    std::vector<std::string> constraints_;
};

/// Initial values that violate a constraint (relative 1e-9; docs/language.md, *Constraints*).
class InconsistentInitialValues : public Error {
public:
    InconsistentInitialValues(const std::string& message, std::string constraint, double residual)
        : Error(message), constraint_(std::move(constraint)), residual_(residual) {}
    /// The first constraint violated.
    [[nodiscard]] const std::string& constraint() const noexcept { return constraint_; }
    /// Its residual φ (position level) or φ' (velocity level).
    [[nodiscard]] double residual() const noexcept { return residual_; }

private:
    std::string constraint_;
    double residual_;
};

/// A computation produced NaN or infinity from finite inputs.
class NonFiniteResult : public Error {
public:
    using Error::Error;
};

/// Events accumulate (Zeno behaviour: a ball with restitution e < 1 bounces infinitely often
/// in finite time). The message names the event and the time (simulate/events.hpp).
class ZenoError : public Error {
public:
    using Error::Error;
};

/// An implicit step did not converge.
class ConvergenceError : public Error {
public:
    using Error::Error;
};

/// The projection onto a holonomic constraint stalls with its residual away from zero: the
/// Gauss–Newton iterates reach a point where the constraint's gradient vanishes (a minimum
/// of |φ|) or stop converging there. No state near the start satisfies the constraint — at
/// these parameters perhaps none does (x² + y² = −l²). constraint() names it, residual() is
/// φ where the projection stalled.
class UnreachableConstraint : public ConvergenceError {
public:
    UnreachableConstraint(const std::string& message, std::string constraint, double residual)
        : ConvergenceError(message), constraint_(std::move(constraint)), residual_(residual) {}
    [[nodiscard]] const std::string& constraint() const noexcept { return constraint_; }
    [[nodiscard]] double residual() const noexcept { return residual_; }

private:
    std::string constraint_;
    double residual_;
};

} // namespace phynjo::runtime
