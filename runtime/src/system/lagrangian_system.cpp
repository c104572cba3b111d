#include "phynjo/runtime/system/lagrangian_system.hpp"

namespace phynjo::runtime {

World make_lagrangian_world(const LagrangianSystem& s) {
    Registry r;
    for (const auto& name : s.coordinate_names) r.add(name);
    World w(std::make_shared<Layout>(r, std::vector<std::string>(kLagrangianFields.begin(), kLagrangianFields.end())));
    if (s.initial_state) s.initial_state(w.field(kGQ), w.field(kGV));
    return w;
}

} // namespace phynjo::runtime
