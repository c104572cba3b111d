#pragma once
/// \file
/// Common-subexpression elimination over a list of expressions.
#include "phynjo/cas/expr.hpp"

#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace phynjo::cas {

/// Straight-line form of a list of expressions: temporaries in dependency order, then the
/// outputs in terms of them.
struct CseResult {
    std::vector<std::pair<Expr, Expr>> assignments; ///< (temporary symbol, its value)
    std::vector<Expr> outputs;
};

struct CseOptions {
    /// Temporaries are named PREFIX0, PREFIX1, …; underscores are appended to the prefix
    /// until no name clashes with a symbol of the input.
    std::string prefix = "x";
    /// Also give a temporary to every compound base of an integer power, so that a printer
    /// can write `t*t` instead of calling pow.
    bool hoist_power_bases = false;
    /// Compute a sum from another sum of the same DAG that has all but one or two of its
    /// terms: x = y + t (the partial sums of a chain cost one addition each). The outputs
    /// are the same expressions; only the temporaries differ.
    bool share_partial_sums = true;
};

/// Every compound subexpression used more than once in the DAG of `outputs` gets a
/// temporary. Deterministic: the same input gives the same assignments.
CseResult cse(std::span<const Expr> outputs, const CseOptions& options = {});

} // namespace phynjo::cas
