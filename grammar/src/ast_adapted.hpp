#pragma once
// Fusion adaptation of the AST, for the X3 rules only.
#include "phynjo/grammar/ast.hpp"

#include <boost/fusion/include/adapt_struct.hpp>

BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::Number, text)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::Name, text)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::Call, function, arg, more)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::Paren, inner)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::Postfix, primary, primes)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::Power, base, exponent)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::Unary, signs, power)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::ProductOp, op, operand)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::Unit, text)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::Product, first, rest, unit)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::SumOp, op, operand)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::Expression, first, rest)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::Binding, name, primes, value)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::ModelStmt, name)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::CoordinateDecl, name, unit)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::CoordinatesStmt, names)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::ParametersStmt, items)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::LetStmt, name, unit, value)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::LagrangianStmt, value)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::DissipationStmt, value)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::ForceStmt, coordinate, value)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::InitialStmt, items)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::InputStmt, items)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::ConstraintStmt, name, lhs, rhs)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::EventAction, name, primes, value)
BOOST_FUSION_ADAPT_STRUCT(phynjo::grammar::ast::EventStmt, name, lhs, relation, rhs, actions)
