#include "phynjo/runtime/collision/collision_manager.hpp"

namespace phynjo::runtime {

CollisionManager::CollisionManager(BroadPhase kind, double cell_size) : kind_(kind), grid_(cell_size) {}

CollisionManager::CollisionManager(BroadPhase kind, std::span<const AABB> boxes, double cell_size)
    : CollisionManager(kind, cell_size) {
    update(boxes);
}

void CollisionManager::update(std::span<const AABB> boxes) { boxes_.assign(boxes.begin(), boxes.end()); }

void CollisionManager::update(std::span<const SphereBB> spheres) {
    boxes_.resize(spheres.size());
    for (std::size_t i = 0; i < spheres.size(); ++i) boxes_[i] = aabb_from_sphere(spheres[i]);
}

void CollisionManager::reserve(std::size_t volumes, std::size_t pairs) {
    boxes_.reserve(volumes);
    pairs_.reserve(pairs);
    sap_.reserve(volumes);
    grid_.reserve(volumes, pairs);
}

const std::vector<CandidatePair>& CollisionManager::run_broad_phase() {
    switch (kind_) {
    case BroadPhase::brute_force: brute_force_pairs(boxes_, pairs_); break;
    case BroadPhase::sweep_and_prune: sap_.find_pairs(boxes_, pairs_); break;
    case BroadPhase::uniform_grid: grid_.find_pairs(boxes_, pairs_); break;
    }
    return pairs_;
}

} // namespace phynjo::runtime
