#include "phynjo/runtime/particles/force3d.hpp"

#include <cmath>

namespace phynjo::runtime {

Force3D Force3D::gravity(double g) {
    return Force3D([g](const State3D& s, Index c) {
        return std::pair<Vec3, Vec3>{Vec3{0, -s.m[c] * g, 0}, Vec3{0, 0, 0}};
    });
}
Force3D Force3D::spring(Index i, Index j, double k, double l0) {
    return Force3D([=](const State3D& s, Index c) {
        if (c != i && c != j) return std::pair<Vec3, Vec3>{};
        const Vec3 d{s.x[i] - s.x[j], s.y[i] - s.y[j], s.z[i] - s.z[j]};
        const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (len == 0) return std::pair<Vec3, Vec3>{};
        const double f = -k * (len - l0) / len * (c == i ? 1.0 : -1.0);
        return std::pair<Vec3, Vec3>{Vec3{f * d[0], f * d[1], f * d[2]}, Vec3{}};
    });
}
Force3D Force3D::drag(double gamma) {
    return Force3D([gamma](const State3D& s, Index c) {
        return std::pair<Vec3, Vec3>{Vec3{-gamma * s.vx[c], -gamma * s.vy[c], -gamma * s.vz[c]}, Vec3{}};
    });
}
std::pair<Vec3, Vec3> Force3D::operator()(const State3D& s, Index c) const {
    std::pair<Vec3, Vec3> total{};
    for (const Field& f : fields_) {
        const auto [F, T] = f(s, c);
        for (int k = 0; k < 3; ++k) {
            total.first[k] += F[k];
            total.second[k] += T[k];
        }
    }
    for (int k = 0; k < 3; ++k) {
        total.first[k] *= scale_;
        total.second[k] *= scale_;
    }
    return total;
}
Force3D operator+(Force3D a, const Force3D& b) {
    // fold each side's scale into its fields so that sums of scaled forces stay exact
    Force3D r;
    r.fields_.push_back([a](const State3D& s, Index c) { return a(s, c); });
    r.fields_.push_back([b](const State3D& s, Index c) { return b(s, c); });
    return r;
}
Force3D operator*(double s, Force3D f) {
    f.scale_ *= s;
    return f;
}

} // namespace phynjo::runtime
