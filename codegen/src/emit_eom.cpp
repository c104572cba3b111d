// --emit=eom: M and f in the input syntax, one line per entry.
#include "phynjo/codegen/emit.hpp"

#include "phynjo/cas/cas.hpp"

namespace phynjo::codegen {

namespace detail {
/// For the reader (--emit=eom, --emit=latex): the expanded and simplified form (sin² + cos² =
/// 1 applied to the expansion) when it is no longer than the derived one, as the derivation
/// keeps large expressions in their factored form for the code generator. Expansion is
/// tried on expressions of up to 2,000 nodes (as trees) only: beyond that it costs more
/// than it can gain.
cas::Expr readable(cas::Expr e) {
    if (cas::tree_size(e) > 2000) return e;
    try {
        const cas::Expr s = cas::simplify(e);
        return cas::tree_size(s) <= cas::tree_size(e) ? s : e;
    } catch (const cas::Error&) { // a budget (LimitError) or a domain error: the derived form it is
        return e;
    }
}
} // namespace detail

std::string emit_eom(const Model& m, const EquationsOfMotion& eom) {
    const std::size_t n = m.dof();
    std::string s = "# " + m.name + ": M*q'' = f with q = (";
    for (std::size_t i = 0; i < n; ++i) s += (i ? ", " : "") + m.coordinates[i].name;
    s += ")\n";
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            s += "M(" + std::to_string(i + 1) + "," + std::to_string(j + 1) + ") = " + cas::to_string(detail::readable(eom.mass_matrix[i * n + j])) + "\n";
    for (std::size_t i = 0; i < n; ++i) s += "f(" + std::to_string(i + 1) + ") = " + cas::to_string(detail::readable(eom.forcing[i])) + "\n";
    if (const std::size_t mc = eom.n_constraints; mc > 0) {
        s += "# constraints: M*q'' = f + G^T*lambda, G*q'' = gamma, with lambda = (";
        for (std::size_t k = 0; k < mc; ++k) s += (k ? ", " : "") + std::string("lambda_") + m.constraints[k].name;
        s += ")\n";
        for (std::size_t k = 0; k < mc; ++k) {
            const auto row = std::to_string(k + 1);
            s += "phi(" + row + ") = " + cas::to_string(detail::readable(eom.residuals[k])) + "  # " + m.constraints[k].name +
                 (m.constraints[k].holonomic ? ", holonomic" : ", nonholonomic") + "\n";
            for (std::size_t j = 0; j < n; ++j)
                s += "G(" + row + "," + std::to_string(j + 1) + ") = " +
                     cas::to_string(detail::readable(eom.constraint_matrix[k * n + j])) + "\n";
            s += "gamma(" + row + ") = " + cas::to_string(detail::readable(eom.gamma[k])) + "\n";
        }
    }
    return s;
}

} // namespace phynjo::codegen
