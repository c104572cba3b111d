#include "phynjo/runtime/particles/nstate.hpp"

#include "phynjo/runtime/core/errors.hpp"

#include <cmath>
#include <stdexcept>

namespace phynjo::runtime {

World make_nstate(const Registry& components, const std::vector<double>& masses,
                  const std::vector<std::string>& extra_fields) {
    std::vector<std::string> fields{"q", "p", "m"};
    fields.insert(fields.end(), extra_fields.begin(), extra_fields.end());
    auto layout = std::make_shared<Layout>(components, std::move(fields));
    World w(layout);
    if (!masses.empty() && masses.size() != w.size())
        throw std::invalid_argument("make_nstate: " + std::to_string(masses.size()) + " masses for " +
                                    std::to_string(w.size()) + " components");
    for (Index i = 0; i < w.size(); ++i) {
        const double m = masses.empty() ? 1.0 : masses[i];
        if (!(m > 0) || !std::isfinite(m))
            throw InvalidBody("mass of '" + components.label(i) + "' must be positive and finite, got " + std::to_string(m));
        w.at(kM, i) = m;
    }
    return w;
}

double kinetic_energy(const World& w) {
    double e = 0;
    for (Index i = 0; i < w.size(); ++i) e += w.at(kP, i) * w.at(kP, i) / (2 * w.at(kM, i));
    return e;
}

double total_momentum(const World& w) {
    double p = 0;
    for (Index i = 0; i < w.size(); ++i) p += w.at(kP, i);
    return p;
}

NumericRule drift(const ComponentSet& bodies, double c, const std::shared_ptr<const Layout>& layout) {
    NumericRule r;
    r.name = "drift(" + std::to_string(c) + ")";
    r.domain = Domain(kQ, bodies);
    r.reads = Domain(kP, bodies) | Domain(kM, bodies);
    r.layout = layout;
    r.step = [bodies, c](double dt, World& w) {
        for (Index i : bodies.indices()) w.at(kQ, i) += c * dt * w.at(kP, i) / w.at(kM, i);
    };
    return r;
}

} // namespace phynjo::runtime
