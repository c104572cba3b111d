#pragma once
/// \file
/// A checked model: what a .lag file means, as exact expressions.
#include "phynjo/cas/expr.hpp"

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace phynjo::codegen {

/// Where something was written (byte offset and length in the model file).
struct SourceSpan {
    std::size_t offset = 0;
    std::size_t length = 1;
};

struct Coordinate {
    std::string name;
    cas::Expr symbol;
    SourceSpan where;
    std::string unit; ///< its unit as written ("m"), else its dimension in base units (empty: none, or a file without units)
};

struct Parameter {
    std::string name;
    cas::Expr symbol;
    cas::Expr value;          ///< exact constant (numbers, pi, functions of them)
    double default_value = 0; ///< the value correctly rounded to double
    SourceSpan where;
    /// For a parameter defined from others (`I = 1/2*Mp*R^2`): that definition, in terms of
    /// earlier parameters. The generated code makes it follow them unless it is set. Null
    /// for a plain number.
    cas::Expr definition;
    [[nodiscard]] bool derived() const noexcept { return !definition.is_null(); }
    /// Declared by `input`: a parameter meant to change during a run; also listed in
    /// the generated input_names.
    bool input = false;
    std::string unit; ///< its unit as written ("N/m") when its value is one quantity, else its dimension in base units ("kg*m^2"; empty: none, or a file without units)
};

/// `constraint NAME: A = B`: φ = A − B = 0 (docs/language.md, *Constraints*).
struct Constraint {
    std::string name;
    cas::Expr phi;          ///< A − B, every `let` substituted
    /// True when φ contains no velocity: φ(q, t) = 0. Otherwise φ = a(q, t)·q' + b(q, t).
    bool holonomic = true;
    SourceSpan where;       ///< the constraint's name
};

/// One reset of an event: coordinate `coordinate` (velocity when `velocity`) becomes
/// `value`, evaluated on the state just before the event.
struct EventReset {
    std::size_t coordinate = 0;
    bool velocity = false;
    cas::Expr value; ///< every `let` substituted
    SourceSpan where; ///< the reset's name
};

/// `event NAME: A < B -> ACTIONS` (docs/language.md, *Events*): fires when g = A − B
/// crosses zero downwards (`<`, direction −1) or upwards (`>`, direction +1).
struct Event {
    std::string name;
    cas::Expr guard; ///< A − B, every `let` substituted
    int direction = -1;
    std::vector<EventReset> resets; ///< file order; empty when `stop`
    bool stop = false;
    SourceSpan where; ///< the event's name
};

/// A box's turn by `angle` (rad, right-handed) about the constant `axis` (any length but 0).
struct ShapeTurn {
    cas::Expr angle;                ///< of t, q, parameters and inputs; every `let` substituted
    std::array<cas::Expr, 3> axis;  ///< numbers and parameters
};

/// `shape NAME: sphere R at (X, Y, Z)`, `shape NAME: segment (…) to (…)`, `shape NAME:
/// capsule R from (…) to (…)` or `shape NAME: box (HX, HY, HZ) at (…) rotated … about (…)`
/// (docs/language.md, *Shapes*): geometry attached to the model's kinematics.
struct Shape {
    enum class Kind { Sphere, Segment, Capsule, Box };
    std::string name;
    Kind kind = Kind::Sphere;
    cas::Expr radius;                   ///< a sphere's or capsule's radius (parameters and numbers), m
    std::vector<cas::Expr> points;      ///< X, Y, Z of the centre, or of both ends; every `let` substituted
    std::vector<cas::Expr> half_extents; ///< a box's (HX, HY, HZ) (parameters and numbers), m
    std::vector<ShapeTurn> turns;        ///< a box's turns, applied in order (about world axes)
    /// The entries of shape_positions: 3 for a sphere's centre, 6 for the two ends of a segment
    /// or capsule, 7 for a box's centre and orientation quaternion (w, x, y, z).
    [[nodiscard]] std::size_t point_values() const noexcept {
        return kind == Kind::Sphere ? 3 : kind == Kind::Box ? 7 : 6;
    }
    /// The kind's code in the generated tables: 0 segment, 1 sphere, 2 capsule, 3 box.
    [[nodiscard]] int code() const noexcept {
        return kind == Kind::Segment ? 0 : kind == Kind::Sphere ? 1 : kind == Kind::Capsule ? 2 : 3;
    }
    SourceSpan where;                   ///< the shape's name
};

struct Model {
    std::string name; ///< C++ namespace of the generated code
    std::string source_name;
    std::vector<Coordinate> coordinates;
    std::vector<Parameter> parameters;
    cas::Expr lagrangian;           ///< L(q, q', t), every `let` substituted
    cas::Expr dissipation;          ///< R(q, q', t), 0 if absent
    std::vector<cas::Expr> forces;  ///< Q_i per coordinate, 0 if absent
    std::vector<cas::Expr> initial_q, initial_qdot; ///< in terms of the parameters; 0 if absent
    SourceSpan lagrangian_where;
    std::vector<Constraint> constraints; ///< file order
    std::vector<Event> events;           ///< file order
    std::vector<Shape> shapes;           ///< file order

    [[nodiscard]] std::size_t n_inputs() const noexcept {
        std::size_t k = 0;
        for (const auto& p : parameters) k += p.input ? 1 : 0;
        return k;
    }

    [[nodiscard]] std::size_t dof() const noexcept { return coordinates.size(); }
    [[nodiscard]] std::vector<cas::Expr> coordinate_symbols() const;
};

} // namespace phynjo::codegen
