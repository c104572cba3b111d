// main() of a generated simulator: it names the model's parameters and hands over to the
// runtime's tested command-line driver (phynjo/runtime/simulate/model_main.hpp).
#include "emit_detail.hpp"

#include <sstream>

namespace phynjo::codegen::detail {

std::string emit_main(const Model& m) {
    std::ostringstream s;
    s << "\n// ---- main: the runtime's command-line simulator (phynjo/runtime/simulate/model_main.hpp) ----\n"
      << "int main(int argc, char** argv) {\n"
      << "    " << m.name << "::Parameters P;\n"
      << "    const phynjo::runtime::ModelCommandLine model{\"" << m.name << "\", {";
    for (std::size_t j = 0; j < m.parameters.size(); ++j)
        s << (j ? ",\n        " : "\n        ") << "{\"" << m.parameters[j].name << "\", [&P](double v) { P." << m.parameters[j].name
          << " = v; }}";
    s << "},\n"
      << "                                                  [&P] { return " << m.name << "::system(P); }};\n"
      << "#ifdef PHYNJO_MPI // phynjo_add_model links phynjo::mpi: a sweep started by mpirun is shared among the ranks\n"
      << "    return phynjo::mpi::model_main(argc, argv, model);\n"
      << "#else\n"
      << "    return phynjo::runtime::model_main(argc, argv, model);\n"
      << "#endif\n"
      << "}\n";
    return s.str();
}

} // namespace phynjo::codegen::detail
