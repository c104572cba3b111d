// The contact solver's detection: the broad phase over the bodies' and model spheres' bounds, then the narrow phase (solver.hpp).
#include "solver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace phynjo::runtime::contact_detail {

void Solver::detect(const World& w, double dt) {
    contacts_.clear();
    // Speculative margins (ContactOptions::margin): the given one for every pair, or per body
    // min(r, max(2|v|dt, slop, r/50)) — twice the distance it can cover in the step, and at
    // least a small fixed distance so that bodies at rest that (nearly) touch keep their
    // contacts — and a pair's margin the sum of its two.
    const bool uniform = options_.margin >= 0;
    margins_.resize(ids_.size());
    for (std::size_t k = 0; k < ids_.size(); ++k) {
        const Body& b = bodies_[k];
        margins_[k] = uniform ? 0.5 * options_.margin
                              : std::min(b.r, std::max(2 * std::sqrt(dot(b.v, b.v)) * dt, std::max(options_.slop, 0.02 * b.r)));
    }
    if (sphere_pairs_) {
        spheres_.resize(ids_.size());
        for (std::size_t k = 0; k < ids_.size(); ++k) {
            const Body& b = bodies_[k];
            spheres_[k] = SphereBB{{b.p[0], b.p[1], b.p[2]}, b.r + margins_[k]};
        }
        // The rigid bodies through the broad phase; the few model spheres, often larger than
        // the pile's (a uniform grid sizes its cells by the largest), against every body.
        manager_.update(std::span<const SphereBB>(spheres_.data(), n_rigid_));
        const std::vector<CandidatePair>* pairs = &manager_.run_broad_phase();
        if (n_rigid_ < ids_.size()) {
            model_pairs_ = *pairs;
            for (std::size_t k = n_rigid_; k < ids_.size(); ++k)
                for (std::size_t j = 0; j < k; ++j) {
                    if (j >= n_rigid_ && bodies_[j].model == bodies_[k].model) continue; // one model: no pair
                    const double reach = spheres_[j].radius + spheres_[k].radius;
                    if ((spheres_[j].center - spheres_[k].center).squaredNorm() < reach * reach)
                        model_pairs_.push_back({static_cast<Index>(j), static_cast<Index>(k)});
                }
            pairs = &model_pairs_;
        }
        if (uniform)
            sphere_sphere_contacts(w, *pairs, ids_, options_.margin, contacts_);
        else
            sphere_sphere_contacts(w, *pairs, ids_, std::span<const double>(margins_), contacts_);
    }
    if (uniform)
        sphere_plane_contacts(w, ids_, planes_, options_.margin, contacts_);
    else
        sphere_plane_contacts(w, ids_, planes_, std::span<const double>(margins_), contacts_);
    // Scratch indices instead of component indices.
    local_.resize(w.size());
    for (std::size_t k = 0; k < ids_.size(); ++k) local_[ids_[k]] = static_cast<Index>(k);
    rows_.resize(contacts_.size());
    const auto stat = static_cast<std::uint32_t>(ids_.size());
    std::size_t kept = 0;
    for (std::size_t c = 0; c < contacts_.size(); ++c) {
        const Contact& k = contacts_[c];
        const std::uint32_t a = local_[k.a], b = k.plane >= 0 ? stat : local_[k.b];
        // Spheres of one model do not collide with each other (scene.hpp).
        if (b != stat && bodies_[a].model >= 0 && bodies_[a].model == bodies_[b].model) continue;
        Row& r = rows_[kept++];
        r.a = a;
        r.b = b;
        r.plane = k.plane;
        r.jn = r.jt1 = r.jt2 = 0;
        r.slot = -1;
    }
    rows_.resize(kept);
}

} // namespace phynjo::runtime::contact_detail
