// Straight-line bodies for generated functions: one CSE pass over all outputs of a function,
// locals declared only for the variables used.
#include "emit_detail.hpp"

#include <map>
#include <unordered_set>

namespace phynjo::codegen::detail {

namespace {

/// The loads of the user variables a CSE result uses, in a deterministic order.
std::string loads(const Names& names, const cas::CseResult& r, bool& uses_t, bool& uses_params) {
    // the variables used, in a deterministic order
    std::vector<Expr> all = r.outputs;
    for (const auto& [t, v] : r.assignments) all.push_back(v);
    std::map<std::string, Expr> used;
    for (Expr v : cas::free_variables(all))
        if (names.is_user(v)) used.emplace(names.local(v), v);
    std::string s;
    uses_t = false;
    uses_params = false;
    for (const auto& [local, v] : used) {
        if (v == cas::time_symbol()) uses_t = true;
        else {
            if (local[0] == 'k') uses_params = true;
            s += names.load(v);
        }
    }
    return s;
}

} // namespace

std::string body(const Names& names, const std::vector<Expr>& outputs, std::vector<std::string>& results,
                 bool& uses_t, bool& uses_params) {
    const cas::CseResult r = cas::cse(outputs, {.prefix = names.temp_prefix(), .hoist_power_bases = true});
    cas::CppOptions cpp;
    cpp.variable_name = [&](Expr v) { return names.local(v); };
    std::string s = loads(names, r, uses_t, uses_params);
    for (const auto& [t, v] : r.assignments) s += "    const double " + names.local(t) + " = " + cas::to_cpp(v, cpp) + ";\n";
    results.clear();
    for (Expr o : r.outputs) results.push_back(cas::to_cpp(o, cpp));
    return s;
}

void body_split(const Names& names, const std::vector<Expr>& outputs, const std::vector<Expr>& late_variables,
                std::vector<std::string>& results, std::string& early, std::string& late, bool& uses_t, bool& uses_params) {
    const cas::CseResult r = cas::cse(outputs, {.prefix = names.temp_prefix(), .hoist_power_bases = true});
    cas::CppOptions cpp;
    cpp.variable_name = [&](Expr v) { return names.local(v); };
    early = loads(names, r, uses_t, uses_params);
    late.clear();
    std::unordered_set<Expr> is_late(late_variables.begin(), late_variables.end());
    for (const auto& [t, v] : r.assignments) {
        bool depends = false;
        for (Expr x : cas::free_variables(v))
            if (is_late.count(x)) {
                depends = true;
                break;
            }
        if (depends) is_late.insert(t);
        (depends ? late : early) += "    const double " + names.local(t) + " = " + cas::to_cpp(v, cpp) + ";\n";
    }
    results.clear();
    for (Expr o : r.outputs) results.push_back(cas::to_cpp(o, cpp));
}

std::string unused(bool uses_t, bool uses_params, bool has_t) {
    std::string s;
    if (has_t && !uses_t) s += "    (void)t;\n";
    if (!uses_params) s += "    (void)P;\n";
    return s;
}

} // namespace phynjo::codegen::detail
