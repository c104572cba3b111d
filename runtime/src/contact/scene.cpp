// Scenes: rigid bodies and generated models in one world (scene.hpp). The contact side of the
// coupling (effective masses and impulses through the sphere Jacobians) is in model_coupling.cpp.
#include "phynjo/runtime/contact/scene.hpp"

#include "solver.hpp"

#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/integrators/lagrangian_midpoint.hpp"
#include "phynjo/runtime/integrators/lagrangian_rattle.hpp"
#include "phynjo/runtime/integrators/lagrangian_rk4.hpp"
#include "phynjo/runtime/rigid/rigid_rules.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

namespace phynjo::runtime {

Scene make_scene(const Registry& components, const std::vector<RigidBody>& bodies, const std::vector<RigidInit>& init,
                 std::vector<ModelInstance> models, const std::vector<std::string>& extra_fields) {
    // The rigid part first, validated as make_rigid_world does.
    World rigid = make_rigid_world(components, bodies, init);
    std::set<std::string> names;
    Registry reg = components;
    std::vector<PlacedModel> placed;
    for (ModelInstance& m : models) {
        if (m.name.empty()) throw std::invalid_argument("make_scene: a model instance without a name");
        if (!names.insert(m.name).second) throw std::invalid_argument("make_scene: two model instances named '" + m.name + "'");
        const LagrangianSystem& s = m.system;
        if (!s.mass_matrix || !s.initial_state || s.coordinate_names.size() != s.dof)
            throw std::invalid_argument("make_scene: model '" + m.name + "' is not a complete LagrangianSystem");
        if (s.n_spheres > 0 && (!s.shape_positions || !s.sphere_jacobians || !s.sphere_radii))
            throw std::invalid_argument("make_scene: model '" + m.name + "' has spheres but no shape functions");
        if (s.n_capsules > 0 && (!s.shape_positions || !s.capsule_jacobians || !s.capsule_radii))
            throw std::invalid_argument("make_scene: model '" + m.name + "' has capsules but no shape functions");
        if (s.n_boxes > 0 && (!s.shape_positions || !s.box_jacobians || !s.box_half_extents))
            throw std::invalid_argument("make_scene: model '" + m.name + "' has boxes but no shape functions");
        PlacedModel p;
        p.name = m.name;
        p.radii.resize(s.n_spheres);
        if (s.n_spheres > 0) s.sphere_radii(p.radii);
        p.capsule_radii.resize(s.n_capsules);
        if (s.n_capsules > 0) s.capsule_radii(p.capsule_radii);
        p.box_half_extents.resize(3 * s.n_boxes);
        if (s.n_boxes > 0) s.box_half_extents(p.box_half_extents);
        std::size_t offset = 0;
        for (std::size_t k = 0; k < s.n_shapes; ++k) {
            const ModelShape kind = s.shape_kinds[k];
            // a colliding shape's sizes must be positive
            auto positive = [&](const char* shape, const char* size, double v) {
                if (!(v > 0) || !std::isfinite(v))
                    throw std::invalid_argument(std::string("make_scene: ") + shape + " '" + s.shape_names[k] + "' of model '" +
                                                m.name + "' has " + size + " " + std::to_string(v) + " m; it must be positive");
            };
            if (kind == ModelShape::sphere) positive("sphere", "radius", p.radii[p.spheres.size()]);
            if (kind == ModelShape::capsule) positive("capsule", "radius", p.capsule_radii[p.ends.size()]);
            if (kind == ModelShape::box) {
                for (std::size_t d = 0; d < 3; ++d) positive("box", "half extent", p.box_half_extents[3 * p.boxes.size() + d]);
                p.boxes.push_back(offset);
            }
            if (kind == ModelShape::capsule) p.ends.push_back(offset);
            if (kind == ModelShape::sphere) {
                p.spheres.push_back(reg.add(m.name + "." + s.shape_names[k]));
                p.centre.push_back(offset);
            }
            offset += shape_values(kind);
        }
        for (const std::string& c : s.coordinate_names) p.coordinates.push_back(reg.add(m.name + "." + c));
        p.system = std::make_shared<const LagrangianSystem>(std::move(m.system));
        placed.push_back(std::move(p));
    }
    // The rigid world's fields (with the shape fields when a body is a box or capsule), then the extra ones.
    std::vector<std::string> fields = rigid.layout().fields;
    const auto n_rigid_fields = static_cast<FieldId>(fields.size());
    fields.insert(fields.end(), extra_fields.begin(), extra_fields.end());
    for (const char* f : {"q", "qd"})
        if (std::find(fields.begin(), fields.end(), f) != fields.end())
            throw std::invalid_argument(std::string("make_scene: an extra field is named '") + f + "'");
    fields.emplace_back("q");
    fields.emplace_back("qd");
    auto layout = std::make_shared<Layout>(reg, std::move(fields));
    Scene scene{World(layout), ComponentSet::range(0, static_cast<Index>(components.size())), {}, std::move(placed),
                layout->field("q"), layout->field("qd")};
    World& w = scene.world;
    for (FieldId f = 0; f < n_rigid_fields; ++f)
        for (Index i = 0; i < rigid.size(); ++i) w.at(f, i) = rigid.at(f, i);
    std::vector<Index> spheres;
    for (std::size_t k = 0; k < scene.models.size(); ++k) {
        const PlacedModel& p = scene.models[k];
        for (std::size_t j = 0; j < p.spheres.size(); ++j) {
            w.at(kQW, p.spheres[j]) = 1; // proxies: identity orientation, no mass, the sphere's radius
            w.at(kRadius, p.spheres[j]) = p.radii[j];
            spheres.push_back(p.spheres[j]);
        }
        for (Index c : p.coordinates) w.at(kQW, c) = 1;
        std::vector<double> q(p.system->dof), qd(p.system->dof);
        p.system->initial_state(q, qd);
        set_model_state(scene, k, q, qd);
    }
    scene.spheres = ComponentSet(std::move(spheres));
    return scene;
}

void set_model_state(Scene& scene, std::size_t k, std::span<const double> q, std::span<const double> qdot) {
    if (k >= scene.models.size()) throw std::invalid_argument("set_model_state: no model " + std::to_string(k));
    const PlacedModel& p = scene.models[k];
    if (q.size() != p.coordinates.size() || qdot.size() != p.coordinates.size())
        throw std::invalid_argument("set_model_state: model '" + p.name + "' has " + std::to_string(p.coordinates.size()) +
                                    " coordinates");
    for (std::size_t i = 0; i < q.size(); ++i) {
        if (!std::isfinite(q[i]) || !std::isfinite(qdot[i]))
            throw std::invalid_argument("set_model_state: a non-finite state for model '" + p.name + "'");
        scene.world.at(scene.q, p.coordinates[i]) = q[i];
        scene.world.at(scene.qd, p.coordinates[i]) = qdot[i];
    }
    SphereSync sync;
    sync_model_spheres(p, scene.q, scene.qd, scene.world.time, scene.world, sync);
}

std::vector<double> model_q(const Scene& scene, std::size_t k) {
    std::vector<double> q;
    for (Index c : scene.models.at(k).coordinates) q.push_back(scene.world.at(scene.q, c));
    return q;
}
std::vector<double> model_qdot(const Scene& scene, std::size_t k) {
    std::vector<double> v;
    for (Index c : scene.models.at(k).coordinates) v.push_back(scene.world.at(scene.qd, c));
    return v;
}

void sphere_states(const PlacedModel& p, double t, SphereSync& s) {
    const LagrangianSystem& sys = *p.system;
    const std::size_t n = sys.dof, ns = p.spheres.size(), nk = p.ends.size(), nb = p.boxes.size();
    const std::size_t nx = sys.n_shape_values();
    s.X.resize(nx), s.Xp.resize(nx), s.Xm.resize(nx), s.J.resize(3 * ns * n), s.P.resize(3 * ns), s.V.resize(3 * ns);
    s.Jc.resize(6 * nk * n), s.E.resize(6 * nk), s.EV.resize(6 * nk);
    s.Jb.resize(6 * nb * n), s.BX.resize(7 * nb), s.BV.resize(6 * nb);
    const double h = 6e-6 * std::max(1.0, std::abs(t));
    sys.shape_positions(t, s.q, s.X);
    sys.shape_positions(t + h, s.q, s.Xp);
    sys.shape_positions(t - h, s.q, s.Xm);
    if (ns > 0) sys.sphere_jacobians(t, s.q, s.J);
    if (nk > 0) sys.capsule_jacobians(t, s.q, s.Jc);
    if (nb > 0) sys.box_jacobians(t, s.q, s.Jb);
    // X at offset x: the position, and the velocity J q' + ∂X/∂t from Jacobian row `row`
    auto point = [&](std::size_t x, const double* row, double& P, double& V) {
        double v = (s.Xp[x] - s.Xm[x]) / (2 * h);
        for (std::size_t i = 0; i < n; ++i) v += row[i] * s.qd[i];
        P = s.X[x];
        V = v;
    };
    for (std::size_t j = 0; j < ns; ++j)
        for (std::size_t a = 0; a < 3; ++a) point(p.centre[j] + a, &s.J[(3 * j + a) * n], s.P[3 * j + a], s.V[3 * j + a]);
    for (std::size_t k = 0; k < nk; ++k)
        for (std::size_t a = 0; a < 6; ++a) point(p.ends[k] + a, &s.Jc[(6 * k + a) * n], s.E[6 * k + a], s.EV[6 * k + a]);
    for (std::size_t k = 0; k < nb; ++k) {
        const std::size_t x = p.boxes[k];
        for (std::size_t a = 0; a < 3; ++a) point(x + a, &s.Jb[(6 * k + a) * n], s.BX[7 * k + a], s.BV[6 * k + a]);
        // ω = J_ω q' + ω_t, ω_t = 2 vec(q_t ⊗ q̄) for a box turned by t or an input
        const double* q = &s.X[x + 3];
        double qt[4];
        for (std::size_t i = 0; i < 4; ++i) {
            s.BX[7 * k + 3 + i] = q[i];
            qt[i] = (s.Xp[x + 3 + i] - s.Xm[x + 3 + i]) / (2 * h);
        }
        const double wt[3] = {2 * (-qt[0] * q[1] + qt[1] * q[0] - qt[2] * q[3] + qt[3] * q[2]),
                              2 * (-qt[0] * q[2] + qt[1] * q[3] + qt[2] * q[0] - qt[3] * q[1]),
                              2 * (-qt[0] * q[3] - qt[1] * q[2] + qt[2] * q[1] + qt[3] * q[0])};
        for (std::size_t a = 0; a < 3; ++a) {
            double v = wt[a];
            for (std::size_t i = 0; i < n; ++i) v += s.Jb[(6 * k + 3 + a) * n + i] * s.qd[i];
            s.BV[6 * k + 3 + a] = v;
        }
    }
}

void sync_model_spheres(const PlacedModel& p, FieldId qf, FieldId qdf, double t, World& w, SphereSync& s) {
    const std::size_t n = p.system->dof;
    if (p.spheres.empty()) return; // capsules have no proxies
    s.q.resize(n), s.qd.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        s.q[i] = w.at(qf, p.coordinates[i]);
        s.qd[i] = w.at(qdf, p.coordinates[i]);
    }
    sphere_states(p, t, s);
    for (std::size_t j = 0; j < p.spheres.size(); ++j)
        for (int a = 0; a < 3; ++a) {
            w.at(static_cast<FieldId>(kX + a), p.spheres[j]) = s.P[3 * j + static_cast<std::size_t>(a)];
            w.at(static_cast<FieldId>(kVX + a), p.spheres[j]) = s.V[3 * j + static_cast<std::size_t>(a)];
        }
}

NumericRule model_rule(const Scene& scene, std::size_t k, ModelIntegrator integrator, const ProjectionOptions& projection) {
    if (k >= scene.models.size()) throw std::invalid_argument("model_rule: no model " + std::to_string(k));
    const PlacedModel& p = scene.models[k];
    const std::shared_ptr<const Layout>& layout = scene.world.layout_ptr();
    struct Inner {
        PlacedModel model;
        World world;
        Stepper stepper;
        SphereSync sync;
        FieldId q, qd;
    };
    World inner = make_lagrangian_world(*p.system);
    NumericWorkflow wf = [&] {
        switch (integrator) {
        case ModelIntegrator::rk4: return lagrangian_rk4(*p.system, inner.layout_ptr(), projection);
        case ModelIntegrator::midpoint: return lagrangian_midpoint(*p.system, inner.layout_ptr(), projection);
        case ModelIntegrator::rattle: return lagrangian_rattle(*p.system, inner.layout_ptr(), projection);
        }
        throw std::invalid_argument("model_rule: unknown integrator");
    }();
    auto state = std::make_shared<Inner>(Inner{p, std::move(inner), Stepper(wf), {}, scene.q, scene.qd});
    Domain writes = Domain(scene.q, ComponentSet(p.coordinates)) | Domain(scene.qd, ComponentSet(p.coordinates));
    if (!p.spheres.empty())
        writes = writes | Domain::of(*layout, {"x", "y", "z", "vx", "vy", "vz"}, ComponentSet(p.spheres));
    NumericRule r{"model:" + p.name, std::move(writes), {}, nullptr, layout};
    r.step = [state](double dt, World& w) {
        Inner& s = *state;
        const std::vector<Index>& c = s.model.coordinates;
        for (std::size_t i = 0; i < c.size(); ++i) {
            s.world.at(kGQ, static_cast<Index>(i)) = w.at(s.q, c[i]);
            s.world.at(kGV, static_cast<Index>(i)) = w.at(s.qd, c[i]);
        }
        s.world.time = w.time;
        s.stepper.step(s.world, dt);
        for (std::size_t i = 0; i < c.size(); ++i) {
            w.at(s.q, c[i]) = s.world.at(kGQ, static_cast<Index>(i));
            w.at(s.qd, c[i]) = s.world.at(kGV, static_cast<Index>(i));
        }
        // The proxies at the end of the step (the interpreter advances w.time after the step).
        sync_model_spheres(s.model, s.q, s.qd, s.world.time, w, s.sync);
    };
    return r;
}

NumericWorkflow scene_step(const Scene& scene, const Force3D& force, std::vector<Plane> planes, ContactMaterial material,
                           ContactOptions options, ModelIntegrator integrator) {
    using W = NumericWorkflow;
    const auto& layout = scene.world.layout_ptr();
    std::vector<W> parts, drifts;
    if (!scene.bodies.empty()) {
        parts.push_back(W::run(kick_force3d(force, scene.bodies, 1.0, layout)));
        drifts.push_back(W::seq(W::run(drift_trans(scene.bodies, 1.0, layout)), W::run(drift_rot(scene.bodies, 1.0, layout))));
    }
    parts.push_back(W::run(contact_rule(scene, std::move(planes), std::move(material), options)));
    for (std::size_t k = 0; k < scene.models.size(); ++k) drifts.push_back(W::run(model_rule(scene, k, integrator)));
    if (drifts.size() == 1) parts.push_back(drifts.front());
    if (drifts.size() > 1) parts.push_back(W::par(std::move(drifts)));
    return W::seq(std::move(parts));
}

double scene_energy(const Scene& scene) {
    double e = rigid_kinetic_energy(scene.world); // proxies and coordinates have no mass fields
    for (std::size_t k = 0; k < scene.models.size(); ++k)
        e += scene.models[k].system->energy(scene.world.time, model_q(scene, k), model_qdot(scene, k));
    return e;
}

NumericRule contact_rule(const Scene& scene, std::vector<Plane> planes, ContactMaterial material, ContactOptions options) {
    using namespace contact_detail;
    validate(planes, material, options);
    const auto& layout = scene.world.layout_ptr();
    const ComponentSet all = scene.bodies | scene.spheres;
    Domain writes = writes_of(*layout, all);
    std::vector<Index> coordinates;
    for (const PlacedModel& p : scene.models) coordinates.insert(coordinates.end(), p.coordinates.begin(), p.coordinates.end());
    if (!coordinates.empty()) {
        const ComponentSet c(std::move(coordinates));
        writes = writes | Domain(scene.q, c) | Domain(scene.qd, c);
        // the warm-start cache of the models' capsules and boxes, kept in their coordinates' slots
        for (std::size_t f = 0; f < layout->fields.size(); ++f)
            if (layout->fields[f].rfind("wc_", 0) == 0) writes = writes | Domain(static_cast<FieldId>(f), c);
    }
    auto solver = std::make_shared<Solver>(scene.bodies, planes, std::move(material), options, layout, true, &scene);
    NumericRule r{"contacts", std::move(writes), reads_of(*layout, all), nullptr, layout};
    r.step = [solver](double dt, World& w) { solver->step(dt, w); };
    return r;
}


} // namespace phynjo::runtime
