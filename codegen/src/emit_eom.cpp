// --emit=eom: M and f in the input syntax, one line per entry.
#include "phynjo/codegen/emit.hpp"

#include "phynjo/cas/cas.hpp"

namespace phynjo::codegen {

std::string emit_eom(const Model& m, const EquationsOfMotion& eom) {
    const std::size_t n = m.dof();
    std::string s = "# " + m.name + ": M*q'' = f with q = (";
    for (std::size_t i = 0; i < n; ++i) s += (i ? ", " : "") + m.coordinates[i].name;
    s += ")\n";
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            s += "M(" + std::to_string(i + 1) + "," + std::to_string(j + 1) + ") = " + cas::to_string(eom.mass_matrix[i * n + j]) + "\n";
    for (std::size_t i = 0; i < n; ++i) s += "f(" + std::to_string(i + 1) + ") = " + cas::to_string(eom.forcing[i]) + "\n";
    return s;
}

} // namespace phynjo::codegen
