// Writes the CSE'd M and f that phynjo-lagc emits for a model, one `name = expr` per line
// in the input syntax, so that bench_lagc can count their operations with SymPy's counter.
//   usage: nlink_ops MODEL.lag OUT.txt
#include "phynjo/cas/cas.hpp"
#include "phynjo/codegen/equations.hpp"
#include "phynjo/codegen/frontend.hpp"

#include <fstream>
#include <iostream>
#include <iterator>

int main(int argc, char** argv) {
    using namespace phynjo;
    if (argc != 3) return 2;
    std::ifstream in(argv[1]);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    grammar::DiagnosticSink sink(argv[1], text);
    auto model = codegen::read_model(text, argv[1], sink);
    if (!model) return std::cerr << sink.format_all(), 1;
    auto eom = codegen::derive(*model, sink);
    if (!eom) return std::cerr << sink.format_all(), 1;
    std::vector<cas::Expr> all;
    const std::size_t n = eom->dof;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i; j < n; ++j) all.push_back(eom->mass_matrix[i * n + j]);
    all.insert(all.end(), eom->forcing.begin(), eom->forcing.end());
    all = cas::horner(all); // as the emitter does
    const auto r = cas::cse(all, {.prefix = "x", .hoist_power_bases = true});
    std::ofstream out(argv[2]);
    for (const auto& [t, v] : r.assignments) out << cas::to_string(t) << " = " << cas::to_string(v) << "\n";
    for (std::size_t k = 0; k < r.outputs.size(); ++k) out << "out" << k << " = " << cas::to_string(r.outputs[k]) << "\n";
    return 0;
}
