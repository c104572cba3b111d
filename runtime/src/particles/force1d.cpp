#include "phynjo/runtime/particles/force1d.hpp"

#include <cmath>

namespace phynjo::runtime {

Force1D Force1D::gravity(double g, const ComponentSet& bodies) {
    Term t;
    t.name = "gravity";
    t.targets = bodies;
    t.sources = bodies;
    t.fields_read = {kM};
    t.add = [bodies, g](const World& w, double s, std::span<double> F) {
        for (Index i : bodies.indices()) F[i] -= s * w.at(kM, i) * g;
    };
    t.potential = [bodies, g](const World& w) {
        double v = 0;
        for (Index i : bodies.indices()) v += w.at(kM, i) * g * w.at(kQ, i);
        return v;
    };
    t.fields_read.push_back(kQ); // the potential reads q; harmless for the kick
    Force1D f;
    f.terms_.push_back(std::move(t));
    return f;
}

Force1D Force1D::spring(Index i, Index j, double k, double l0) {
    Term t;
    t.name = "spring";
    t.targets = ComponentSet{i, j};
    t.sources = ComponentSet{i, j};
    t.fields_read = {kQ};
    t.add = [=](const World& w, double s, std::span<double> F) {
        const double d = w.at(kQ, i) - w.at(kQ, j);
        const double sgn = d > 0 ? 1.0 : d < 0 ? -1.0 : 0.0;
        const double fi = -k * (std::fabs(d) - l0) * sgn;
        F[i] += s * fi;
        F[j] -= s * fi;
    };
    t.potential = [=](const World& w) {
        const double e = std::fabs(w.at(kQ, i) - w.at(kQ, j)) - l0;
        return 0.5 * k * e * e;
    };
    Force1D f;
    f.terms_.push_back(std::move(t));
    return f;
}

Force1D Force1D::anchor(Index i, double a, double k, double l0) {
    Term t;
    t.name = "anchor";
    t.targets = ComponentSet{i};
    t.sources = ComponentSet{i};
    t.fields_read = {kQ};
    t.add = [=](const World& w, double s, std::span<double> F) { F[i] -= s * k * (w.at(kQ, i) - a - l0); };
    t.potential = [=](const World& w) {
        const double e = w.at(kQ, i) - a - l0;
        return 0.5 * k * e * e;
    };
    Force1D f;
    f.terms_.push_back(std::move(t));
    return f;
}

Force1D Force1D::drag(double gamma, const ComponentSet& bodies) {
    Term t;
    t.name = "drag";
    t.targets = bodies;
    t.sources = bodies;
    t.fields_read = {kP, kM};
    t.add = [=](const World& w, double s, std::span<double> F) {
        for (Index i : bodies.indices()) F[i] -= s * gamma * w.at(kP, i) / w.at(kM, i);
    };
    Force1D f;
    f.terms_.push_back(std::move(t));
    return f;
}

Force1D Force1D::newtonian(double G, const ComponentSet& bodies) {
    Term t;
    t.name = "newtonian";
    t.targets = bodies;
    t.sources = bodies;
    t.fields_read = {kQ, kM};
    t.add = [=](const World& w, double s, std::span<double> F) {
        const auto idx = bodies.indices();
        for (std::size_t a = 0; a < idx.size(); ++a)
            for (std::size_t b = a + 1; b < idx.size(); ++b) {
                const Index i = idx[a], j = idx[b];
                const double d = w.at(kQ, j) - w.at(kQ, i);
                const double f = G * w.at(kM, i) * w.at(kM, j) / (d * d) * (d > 0 ? 1.0 : -1.0);
                F[i] += s * f;
                F[j] -= s * f;
            }
    };
    t.potential = [=](const World& w) {
        double v = 0;
        const auto idx = bodies.indices();
        for (std::size_t a = 0; a < idx.size(); ++a)
            for (std::size_t b = a + 1; b < idx.size(); ++b)
                v -= G * w.at(kM, idx[a]) * w.at(kM, idx[b]) / std::fabs(w.at(kQ, idx[a]) - w.at(kQ, idx[b]));
        return v;
    };
    Force1D f;
    f.terms_.push_back(std::move(t));
    return f;
}

Force1D Force1D::custom(std::string name, ComponentSet targets, ComponentSet sources,
                        std::function<void(const World&, std::span<double>)> add) {
    Term t;
    t.name = std::move(name);
    t.targets = std::move(targets);
    t.sources = std::move(sources);
    t.fields_read = {kQ, kP, kM};
    t.add = [add = std::move(add)](const World& w, double s, std::span<double> F) {
        if (s == 1) {
            add(w, F);
            return;
        }
        thread_local std::vector<double> tmp;
        tmp.assign(F.size(), 0.0);
        add(w, tmp);
        for (std::size_t i = 0; i < F.size(); ++i) F[i] += s * tmp[i];
    };
    Force1D f;
    f.terms_.push_back(std::move(t));
    return f;
}

Force1D operator+(Force1D a, const Force1D& b) {
    a.terms_.insert(a.terms_.end(), b.terms_.begin(), b.terms_.end());
    return a;
}
Force1D operator*(double s, Force1D f) {
    for (auto& t : f.terms_) t.scale *= s;
    return f;
}

void Force1D::accumulate(const World& w, std::span<double> F) const {
    for (const Term& t : terms_) t.add(w, t.scale, F);
}
double Force1D::potential(const World& w) const {
    double v = 0;
    for (const Term& t : terms_)
        if (t.potential) v += t.scale * t.potential(w);
    return v;
}
ComponentSet Force1D::targets() const {
    ComponentSet s;
    for (const Term& t : terms_) s = s | t.targets;
    return s;
}
Domain Force1D::reads() const {
    Domain d;
    for (const Term& t : terms_)
        for (FieldId f : t.fields_read) d = d | Domain(f, t.sources);
    return d;
}

NumericRule kick(const Force1D& force, double c, const std::shared_ptr<const Layout>& layout) {
    NumericRule r;
    r.name = "kick(" + std::to_string(c) + ")";
    const ComponentSet targets = force.targets();
    r.domain = Domain(kP, targets);
    r.reads = force.reads();
    r.layout = layout;
    r.step = [force, targets, c](double dt, World& w) {
        thread_local std::vector<double> F; // per thread, reused: no allocation once warm
        F.assign(w.size(), 0.0);
        force.accumulate(w, F);
        for (Index i : targets.indices()) w.at(kP, i) += c * dt * F[i];
    };
    return r;
}

double total_energy(const World& w, const Force1D& force) { return kinetic_energy(w) + force.potential(w); }

Splitting nstate_splitting(const Force1D& force, const ComponentSet& bodies, std::shared_ptr<const Layout> layout) {
    return Splitting{[bodies, layout](double c) { return drift(bodies, c, layout); },
                     [force, layout](double c) { return kick(force, c, layout); }};
}

} // namespace phynjo::runtime
