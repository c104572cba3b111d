#pragma once
/// \file
/// Rewriting passes: expand, simplify, substitution, free symbols.
#include "phynjo/cas/expr.hpp"
#include "phynjo/cas/node_map.hpp"

#include <span>
#include <unordered_map>
#include <vector>

namespace phynjo::cas {

/// The node `e` with its children replaced by `args` (same count), re-canonicalized.
Expr rebuild(Expr e, std::span<const Expr> args);
/// The node `x` with each child c replaced by `child(c)`: `x` itself when no child changed,
/// else rebuilt (the step of every bottom-up pass).
template <typename Child>
Expr with_children(Expr x, Child&& child) {
    std::vector<Expr> a;
    a.reserve(x->nargs);
    bool same = true;
    for (Expr c : x.args()) {
        a.push_back(child(c));
        same = same && a.back() == c;
    }
    return same ? x : rebuild(x, a);
}

/// Distributes products over sums and raises sums to positive integer powers, recursively,
/// so that the result is a sum of products. Throws LimitError beyond
/// `limits::max_expand_terms` terms.
Expr expand(Expr e);

/// Canonical form plus `sin(u)^2 + cos(u)^2 → 1` inside sums (on the expression as given and
/// on its expansion; the smaller result wins), repeated to a fixed point, so that
/// `simplify(simplify(e)) == simplify(e)`.
Expr simplify(Expr e);

/// Only the sin²+cos² rule of simplify, on the expression as given (no expansion): cheap.
Expr trig_simplify_only(Expr e);

/// Greedy multivariate Horner form, for evaluation: in every sum, the factor shared by the
/// most terms is pulled out (a·x + a·y + b·z → a·(x + y) + b·z), repeatedly and bottom-up.
/// The value is unchanged; the operation count usually drops a lot. Deterministic (ties go
/// to the canonical order).
Expr horner(Expr e);
/// horner() of each, sharing the work on common subexpressions.
std::vector<Expr> horner(std::span<const Expr> es);

/// Replaces every occurrence of each key (any subexpression, matched structurally) by its
/// value, bottom-up, re-canonicalizing.
Expr subs(Expr e, const std::unordered_map<Expr, Expr>& replacements);

/// The symbols in `e` (a TimeDerivative `x'` contributes `x`), sorted by name.
std::vector<Expr> free_symbols(Expr e);
/// The variables in `e`: symbols and time derivatives (x' alone does not make x a variable
/// of e), sorted by name then order.
std::vector<Expr> free_variables(Expr e);
/// The variables of several expressions together (one traversal).
std::vector<Expr> free_variables(std::span<const Expr> es);
/// True if `e` contains `x` (structurally).
bool contains(Expr e, Expr x);
/// True if `e` uses one of the variables in `vars` (Symbols, or x' as a whole: a walk that does
/// not look inside a time derivative, as free_variables does not).
bool contains_any(Expr e, const NodeSet& vars);

} // namespace phynjo::cas
