#include "phynjo/runtime/particles/particles3d.hpp"

#include <string>

namespace phynjo::runtime {

World make_particles(const Registry& components, int partitions) {
    std::vector<std::string> fields{"x", "y", "z", "vx", "vy", "vz", "m", "ax", "ay", "az"};
    if (partitions > 1)
        for (int k = 0; k < partitions; ++k)
            for (const char* a : {"ax#", "ay#", "az#"}) fields.push_back(a + std::to_string(k));
    return World(std::make_shared<Layout>(components, std::move(fields)));
}

NumericRule kick3d(double c, const std::shared_ptr<const Layout>& layout) {
    const std::size_t n = layout->components.size();
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(n));
    NumericRule r{"kick3d(" + std::to_string(c) + ")", Domain::of(*layout, {"vx", "vy", "vz"}, all),
                  Domain::of(*layout, {"ax", "ay", "az"}, all), nullptr, layout};
    r.step = [=](double dt, World& w) {
        const double h = c * dt;
        for (int k = 0; k < 3; ++k) {
            double* v = w.field(static_cast<FieldId>(kVX + k)).data();
            const double* a = w.field(static_cast<FieldId>(kAX + k)).data();
            for (std::size_t i = 0; i < n; ++i) v[i] += h * a[i];
        }
    };
    return r;
}

State3D state3d(const World& w) {
    return State3D{w.field(kX), w.field(kY), w.field(kZ), w.field(kVX), w.field(kVY), w.field(kVZ), w.field(kMass)};
}

NumericRule kick3d(const Force3D& force, double c, const std::shared_ptr<const Layout>& layout) {
    const std::size_t n = layout->components.size();
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(n));
    NumericRule r{"kick3d_force(" + std::to_string(c) + ")", Domain::of(*layout, {"vx", "vy", "vz"}, all),
                  Domain::of(*layout, {"x", "y", "z", "m"}, all), nullptr, layout};
    r.step = [=](double dt, World& w) {
        thread_local std::vector<double> F;
        F.assign(3 * n, 0.0);
        const State3D s = state3d(w);
        for (Index i = 0; i < n; ++i) { // forces from the state at the start of the kick
            const auto f = force(s, i).first;
            for (std::size_t k = 0; k < 3; ++k) F[3 * i + k] = f[k];
        }
        for (Index i = 0; i < n; ++i)
            for (std::size_t k = 0; k < 3; ++k) w.at(static_cast<FieldId>(kVX + k), i) += c * dt * F[3 * i + k] / w.at(kMass, i);
    };
    return r;
}

NumericRule drift3d(double c, const std::shared_ptr<const Layout>& layout) {
    const std::size_t n = layout->components.size();
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(n));
    NumericRule r{"drift3d(" + std::to_string(c) + ")", Domain::of(*layout, {"x", "y", "z"}, all),
                  Domain::of(*layout, {"vx", "vy", "vz"}, all), nullptr, layout};
    r.step = [=](double dt, World& w) {
        const double h = c * dt;
        for (int k = 0; k < 3; ++k) {
            double* x = w.field(static_cast<FieldId>(kX + k)).data();
            const double* v = w.field(static_cast<FieldId>(kVX + k)).data();
            for (std::size_t i = 0; i < n; ++i) x[i] += h * v[i];
        }
    };
    return r;
}

} // namespace phynjo::runtime
