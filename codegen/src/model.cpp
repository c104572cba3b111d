#include "phynjo/codegen/model.hpp"

namespace phynjo::codegen {
std::vector<cas::Expr> Model::coordinate_symbols() const {
    std::vector<cas::Expr> out;
    for (const auto& c : coordinates) out.push_back(c.symbol);
    return out;
}
} // namespace phynjo::codegen
