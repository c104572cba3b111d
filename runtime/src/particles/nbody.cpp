// Direct-summation N-body gravity: structure of arrays, each pair once, and a j-loop that
// GCC vectorizes (the i-accumulators are `omp simd` reductions, so no -ffast-math is needed
// and the summation order is fixed by the binary, not by the thread count).
#include "phynjo/runtime/particles/nbody.hpp"
#include "phynjo/runtime/particles/detail/pair_block.hpp"

#include <algorithm>
#include <cmath>

namespace phynjo::runtime {

namespace {

/// Row boundaries splitting the pair triangle into `parts` blocks of equal pair counts.
std::vector<std::size_t> balanced_rows(std::size_t n, int parts) {
    std::vector<std::size_t> b{0};
    const double total = 0.5 * static_cast<double>(n) * static_cast<double>(n - (n > 0 ? 1 : 0));
    double acc = 0;
    std::size_t i = 0;
    for (int k = 1; k < parts; ++k) {
        const double target = total * k / parts;
        while (i < n && acc + static_cast<double>(n - 1 - i) <= target) acc += static_cast<double>(n - 1 - i++);
        b.push_back(i);
    }
    b.push_back(n);
    return b;
}

} // namespace

NumericWorkflow nbody_accelerations(const NBodyGravity& g, const std::shared_ptr<const Layout>& layout, int partitions) {
    const std::size_t n = layout->components.size();
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(n));
    const Domain positions = Domain::of(*layout, {"x", "y", "z", "m"}, all);
    const Domain acc = Domain::of(*layout, {"ax", "ay", "az"}, all);
    const double eps2 = g.softening * g.softening, G = g.G;
    if (partitions <= 1) {
        NumericRule r{"nbody_accelerations", acc, positions, nullptr, layout};
        r.step = [=](double, World& w) {
            double *ax = w.field(kAX).data(), *ay = w.field(kAY).data(), *az = w.field(kAZ).data();
            std::fill_n(ax, n, 0.0);
            std::fill_n(ay, n, 0.0);
            std::fill_n(az, n, 0.0);
            detail::pair_block(w.field(kX).data(), w.field(kY).data(), w.field(kZ).data(), w.field(kMass).data(), ax, ay, az,
                       0, n, n, eps2);
            for (std::size_t i = 0; i < n; ++i) {
                ax[i] *= G;
                ay[i] *= G;
                az[i] *= G;
            }
        };
        return NumericWorkflow::run(r);
    }
    const auto rows = balanced_rows(n, partitions);
    std::vector<NumericWorkflow> partial;
    std::vector<std::array<FieldId, 3>> parts;
    for (int k = 0; k < partitions; ++k) {
        const std::string s = std::to_string(k);
        const std::array<FieldId, 3> f{layout->field("ax#" + s), layout->field("ay#" + s), layout->field("az#" + s)};
        parts.push_back(f);
        const Domain writes = Domain(f[0], all) | Domain(f[1], all) | Domain(f[2], all);
        NumericRule r{"nbody_partial_" + s, writes, positions, nullptr, layout};
        const std::size_t begin = rows[static_cast<std::size_t>(k)], end = rows[static_cast<std::size_t>(k) + 1];
        r.step = [=](double, World& w) {
            double *ax = w.field(f[0]).data(), *ay = w.field(f[1]).data(), *az = w.field(f[2]).data();
            std::fill_n(ax, n, 0.0);
            std::fill_n(ay, n, 0.0);
            std::fill_n(az, n, 0.0);
            detail::pair_block(w.field(kX).data(), w.field(kY).data(), w.field(kZ).data(), w.field(kMass).data(), ax, ay, az,
                       begin, end, n, eps2);
        };
        partial.push_back(NumericWorkflow::run(r));
    }
    Domain partial_fields;
    for (const auto& f : parts) partial_fields = partial_fields | Domain(f[0], all) | Domain(f[1], all) | Domain(f[2], all);
    NumericRule combine{"nbody_combine", acc, partial_fields, nullptr, layout};
    combine.step = [=](double, World& w) {
        for (int c = 0; c < 3; ++c) {
            double* a = w.field(static_cast<FieldId>(kAX + c)).data();
            std::fill_n(a, n, 0.0);
            for (const auto& f : parts) { // fixed order: the result does not depend on threads
                const double* p = w.field(f[static_cast<std::size_t>(c)]).data();
                for (std::size_t i = 0; i < n; ++i) a[i] += p[i];
            }
            for (std::size_t i = 0; i < n; ++i) a[i] *= G;
        }
    };
    return NumericWorkflow::seq(NumericWorkflow::par(std::move(partial)), NumericWorkflow::run(combine));
}

double nbody_energy(const World& w, const NBodyGravity& g) {
    const std::size_t n = w.size();
    double kinetic = 0, potential = 0;
    const double eps2 = g.softening * g.softening;
    for (Index i = 0; i < n; ++i) {
        const double v2 = w.at(kVX, i) * w.at(kVX, i) + w.at(kVY, i) * w.at(kVY, i) + w.at(kVZ, i) * w.at(kVZ, i);
        kinetic += 0.5 * w.at(kMass, i) * v2;
        for (Index j = i + 1; j < n; ++j) {
            const double dx = w.at(kX, j) - w.at(kX, i), dy = w.at(kY, j) - w.at(kY, i), dz = w.at(kZ, j) - w.at(kZ, i);
            potential -= g.G * w.at(kMass, i) * w.at(kMass, j) / std::sqrt(dx * dx + dy * dy + dz * dz + eps2);
        }
    }
    return kinetic + potential;
}

Vec3 nbody_momentum(const World& w) {
    Vec3 p{0, 0, 0};
    for (Index i = 0; i < w.size(); ++i)
        for (int k = 0; k < 3; ++k) p[static_cast<std::size_t>(k)] += w.at(kMass, i) * w.at(static_cast<FieldId>(kVX + k), i);
    return p;
}

} // namespace phynjo::runtime
