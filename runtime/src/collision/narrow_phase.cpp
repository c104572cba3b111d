#include "phynjo/runtime/collision/narrow_phase.hpp"

#include "phynjo/runtime/rigid/rigid_world.hpp"

#include <cmath>
#include <stdexcept>

namespace phynjo::runtime {

void Plane::validate() const {
    if (!normal.allFinite() || !std::isfinite(offset)) throw std::invalid_argument("plane: not finite");
    if (std::abs(normal.norm() - 1) > 1e-9) throw std::invalid_argument("plane: the normal is not a unit vector");
}

void sphere_sphere_contacts(const World& w, std::span<const CandidatePair> pairs, std::span<const Index> ids,
                            double margin, std::vector<Contact>& out) {
    const double *x = w.field(kX).data(), *y = w.field(kY).data(), *z = w.field(kZ).data(),
                 *r = w.field(kRadius).data();
    for (const CandidatePair& p : pairs) {
        const Index a = ids[p.a], b = ids[p.b];
        if (!(r[a] > 0) || !(r[b] > 0)) continue; // only sphere ⊗ sphere
        const double dx = x[a] - x[b], dy = y[a] - y[b], dz = z[a] - z[b];
        const double d2 = dx * dx + dy * dy + dz * dz, reach = r[a] + r[b] + margin;
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

void sphere_plane_contacts(const World& w, std::span<const Index> bodies, std::span<const Plane> planes,
                           double margin, std::vector<Contact>& out) {
    const double *x = w.field(kX).data(), *y = w.field(kY).data(), *z = w.field(kZ).data(),
                 *r = w.field(kRadius).data();
    for (Index a : bodies) {
        if (!(r[a] > 0)) continue;
        for (std::size_t k = 0; k < planes.size(); ++k) {
            const Plane& pl = planes[k];
            const double s = pl.normal.x() * x[a] + pl.normal.y() * y[a] + pl.normal.z() * z[a] - pl.offset - r[a];
            if (s >= margin) continue;
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

} // namespace phynjo::runtime
