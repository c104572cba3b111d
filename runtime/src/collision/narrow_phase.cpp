#include "phynjo/runtime/collision/narrow_phase.hpp"

#include "phynjo/runtime/rigid/rigid_world.hpp"

#include <cmath>
#include <stdexcept>

namespace phynjo::runtime {

void Plane::validate() const {
    if (!normal.allFinite() || !std::isfinite(offset)) throw std::invalid_argument("plane: not finite");
    if (std::abs(normal.norm() - 1) > 1e-9) throw std::invalid_argument("plane: the normal is not a unit vector");
}

namespace {

/// Margin of body k: one value for all, or one per body.
struct Margins {
    double all;
    std::span<const double> each;
    double operator[](std::size_t k) const { return each.empty() ? all : each[k]; }
};

void sphere_pairs(const World& w, std::span<const CandidatePair> pairs, std::span<const Index> ids, Margins margin,
                  std::vector<Contact>& out) {
    const double *x = w.field(kX).data(), *y = w.field(kY).data(), *z = w.field(kZ).data(),
                 *r = w.field(kRadius).data();
    for (const CandidatePair& p : pairs) {
        const Index a = ids[p.a], b = ids[p.b];
        if (!(r[a] > 0) || !(r[b] > 0)) continue; // only sphere ⊗ sphere
        const double dx = x[a] - x[b], dy = y[a] - y[b], dz = z[a] - z[b];
        const double m = margin.each.empty() ? margin.all : margin.each[p.a] + margin.each[p.b];
        const double d2 = dx * dx + dy * dy + dz * dz, reach = r[a] + r[b] + m;
        if (d2 >= reach * reach) continue;
        const double d = std::sqrt(d2);
        Contact c;
        c.a = a;
        c.b = b;
        c.normal = d > 0 ? Eigen::Vector3d(dx / d, dy / d, dz / d) : Eigen::Vector3d(0, 1, 0);
        c.separation = d - r[a] - r[b];
        out.push_back(c);
    }
}

void sphere_planes(const World& w, std::span<const Index> bodies, std::span<const Plane> planes, Margins margin,
                   std::vector<Contact>& out) {
    const double *x = w.field(kX).data(), *y = w.field(kY).data(), *z = w.field(kZ).data(),
                 *r = w.field(kRadius).data();
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const Index a = bodies[i];
        if (!(r[a] > 0)) continue;
        for (std::size_t k = 0; k < planes.size(); ++k) {
            const Plane& pl = planes[k];
            const double s = pl.normal.x() * x[a] + pl.normal.y() * y[a] + pl.normal.z() * z[a] - pl.offset - r[a];
            if (s >= margin[i]) continue;
            Contact c;
            c.a = a;
            c.b = a;
            c.plane = static_cast<int>(k);
            c.normal = pl.normal;
            c.separation = s;
            out.push_back(c);
        }
    }
}

} // namespace

void sphere_sphere_contacts(const World& w, std::span<const CandidatePair> pairs, std::span<const Index> ids,
                            double margin, std::vector<Contact>& out) {
    sphere_pairs(w, pairs, ids, {margin, {}}, out);
}
void sphere_sphere_contacts(const World& w, std::span<const CandidatePair> pairs, std::span<const Index> ids,
                            std::span<const double> margins, std::vector<Contact>& out) {
    sphere_pairs(w, pairs, ids, {0, margins}, out);
}
void sphere_plane_contacts(const World& w, std::span<const Index> bodies, std::span<const Plane> planes,
                           double margin, std::vector<Contact>& out) {
    sphere_planes(w, bodies, planes, {margin, {}}, out);
}
void sphere_plane_contacts(const World& w, std::span<const Index> bodies, std::span<const Plane> planes,
                           std::span<const double> margins, std::vector<Contact>& out) {
    sphere_planes(w, bodies, planes, {0, margins}, out);
}

} // namespace phynjo::runtime
