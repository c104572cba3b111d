#pragma once
/// \file
/// The collision manager, a façade: build it with a broad phase and the bounding
/// volumes, update the volumes every step, run the broad phase. Swapping the broad phase is
/// one argument; nothing downstream changes (every broad phase yields the same sorted pairs).
#include "phynjo/runtime/collision/broad_phase.hpp"

#include <variant>

namespace phynjo::runtime {

class CollisionManager {
public:
    /// buildManager: `cell_size` is used by the uniform grid only (0: automatic).
    explicit CollisionManager(BroadPhase kind = BroadPhase::uniform_grid, double cell_size = 0);
    CollisionManager(BroadPhase kind, std::span<const AABB> boxes, double cell_size = 0);

    /// updateManager: the current volumes (copied; reuses storage, no steady-state allocation).
    void update(std::span<const AABB> boxes);
    void update(std::span<const SphereBB> spheres);
    /// Reserves storage for `volumes` volumes and `pairs` candidate pairs: later steps within
    /// those counts allocate nothing.
    void reserve(std::size_t volumes, std::size_t pairs);
    /// runBroadPhase: the intersecting pairs of the current volumes, sorted (a < b). The
    /// reference stays valid until the next call.
    const std::vector<CandidatePair>& run_broad_phase();

    [[nodiscard]] BroadPhase kind() const noexcept { return kind_; }
    [[nodiscard]] std::span<const AABB> boxes() const noexcept { return boxes_; }

private:
    BroadPhase kind_;
    std::vector<AABB> boxes_;
    std::vector<CandidatePair> pairs_;
    SweepAndPrune sap_;
    UniformGrid grid_;
};

} // namespace phynjo::runtime
