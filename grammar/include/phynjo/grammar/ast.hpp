#pragma once
/// \file
/// The position-tagged syntax tree of the expression language (docs/language.md, *Expressions*).
/// Precedence is the tree's shape: Sum of Products of Unary of Power of Postfix of Primary.
#include <boost/optional.hpp>
#include <boost/spirit/home/x3/support/ast/position_tagged.hpp>
#include <boost/spirit/home/x3/support/ast/variant.hpp>

#include <string>
#include <vector>

namespace phynjo::grammar::ast {

namespace x3 = boost::spirit::x3;

struct Number : x3::position_tagged {
    std::string text; ///< as written: `9.81`, `1e-3`
};

struct Name : x3::position_tagged {
    std::string text;
};

struct Expression;
struct Unary;

/// `f(arg)`, `f(arg, more…)` (atan2(y, x)).
struct Call : x3::position_tagged {
    Name function;
    x3::forward_ast<Expression> arg;
    std::vector<x3::forward_ast<Expression>> more; ///< the arguments after the first
};

/// `( expression )`.
struct Paren : x3::position_tagged {
    x3::forward_ast<Expression> inner;
};

struct Primary : x3::variant<Number, Call, Name, Paren> {
    using base_type::base_type;
    using base_type::operator=;
};

/// `primary'''`: time derivatives.
struct Postfix : x3::position_tagged {
    Primary primary;
    std::string primes; ///< one `'` per derivative
};

/// `base ^ exponent` (right associative: the exponent is a Unary).
struct Power : x3::position_tagged {
    Postfix base;
    boost::optional<x3::forward_ast<Unary>> exponent;
};

/// `-…-power`.
struct Unary : x3::position_tagged {
    std::string signs; ///< one `-` per negation
    Power power;
};

/// `[unit]` (docs/language.md, *Units*): the text between the brackets, as written.
struct Unit : x3::position_tagged {
    std::string text;
};

/// `* operand` or `/ operand`.
struct ProductOp : x3::position_tagged {
    char op = '*';
    Unary operand;
};

/// A product, and the unit of a product of numbers: `9.81 [m/s^2]`, `1/2 [N/m]`, which
/// the product may go on after: `0.5 [N]*x` (the unit binds to the numbers before it).
struct Product : x3::position_tagged {
    Unary first;
    std::vector<ProductOp> rest;
    boost::optional<Unit> unit;
    std::vector<ProductOp> after; ///< the factors after the unit
};

/// `+ operand` or `- operand`.
struct SumOp : x3::position_tagged {
    char op = '+';
    Product operand;
};

struct Expression : x3::position_tagged {
    Product first;
    std::vector<SumOp> rest;
};

// ---- .lag statements (docs/language.md, *Statements*) -------------------------------------

/// `NAME = EXPR` in `parameters`, or `Q = EXPR` / `Q' = EXPR` in `initial`.
struct Binding : x3::position_tagged {
    Name name;
    std::string primes;
    Expression value;
};

struct ModelStmt : x3::position_tagged {
    Name name;
};
/// A coordinate and its unit: `x [m]`.
struct CoordinateDecl : x3::position_tagged {
    Name name;
    boost::optional<Unit> unit;
};
struct CoordinatesStmt : x3::position_tagged {
    std::vector<CoordinateDecl> names;
};
struct ParametersStmt : x3::position_tagged {
    std::vector<Binding> items;
};
struct LetStmt : x3::position_tagged {
    Name name;
    boost::optional<Unit> unit; ///< parsed to be rejected: a let takes its dimension from its value
    Expression value;
};
struct LagrangianStmt : x3::position_tagged {
    Expression value;
};
struct DissipationStmt : x3::position_tagged {
    Expression value;
};
struct ForceStmt : x3::position_tagged {
    Name coordinate;
    Expression value;
};
struct InitialStmt : x3::position_tagged {
    std::vector<Binding> items;
};

/// `input u = 0, …`: exogenous inputs with defaults.
struct InputStmt : x3::position_tagged {
    std::vector<Binding> items;
};
/// `constraint NAME: A = B`.
struct ConstraintStmt : x3::position_tagged {
    Name name;
    Expression lhs;
    Expression rhs;
};

/// One action of an event: a reset `Q = EXPR` or `Q' = EXPR`, or `stop` (a name with
/// no value; the front end decides what a name without a value means).
struct EventAction : x3::position_tagged {
    Name name;
    std::string primes;
    boost::optional<Expression> value;
};
/// `event NAME: A < B -> ACTIONS` (relation '<' or '>').
struct EventStmt : x3::position_tagged {
    Name name;
    Expression lhs;
    char relation = '<';
    Expression rhs;
    std::vector<EventAction> actions;
};

/// A point `(X, Y, Z)` of a shape, world frame.
struct Point : x3::position_tagged {
    Expression x, y, z;
};
/// `sphere R at (X, Y, Z)`.
struct Sphere : x3::position_tagged {
    Expression radius;
    Point centre;
};
/// `segment (X1, Y1, Z1) to (X2, Y2, Z2)`.
struct Segment : x3::position_tagged {
    Point from, to;
};
/// `capsule R from (X1, Y1, Z1) to (X2, Y2, Z2)`: the segment thickened by R.
struct Capsule : x3::position_tagged {
    Expression radius;
    Point from, to;
};
/// `ANGLE about (AX, AY, AZ)`: a turn by ANGLE (rad, right-handed) about a constant axis.
struct Rotation : x3::position_tagged {
    Expression angle;
    Point axis;
};
/// `box (HX, HY, HZ) at (X, Y, Z) [rotated ROTATION [then ROTATION]…]`: half extents, centre,
/// and the turns applied in order (each about an axis of the world frame).
struct Box : x3::position_tagged {
    Point half_extents, centre;
    std::vector<Rotation> rotations;
};
struct Geometry : x3::variant<Sphere, Segment, Capsule, Box> {
    using base_type::base_type;
    using base_type::operator=;
};
/// `shape NAME: GEOMETRY` (docs/language.md, *Shapes*).
struct ShapeStmt : x3::position_tagged {
    Name name;
    Geometry geometry;
};

struct Statement : x3::variant<ModelStmt, CoordinatesStmt, ParametersStmt, LetStmt, LagrangianStmt, DissipationStmt,
                               ForceStmt, InitialStmt, InputStmt, ConstraintStmt, EventStmt, ShapeStmt> {
    using base_type::base_type;
    using base_type::operator=;
};

} // namespace phynjo::grammar::ast
