#pragma once
/// \file
/// Broad phases: from N axis-aligned boxes, the set P of pairs (i, j), i < j, whose boxes
/// intersect (closed intervals, as `intersects(AABB, AABB)`). Every algorithm returns exactly
/// that set, sorted lexicographically, so the narrow phase and the contact solver see the
/// same pairs in the same order whichever broad phase ran (and results are deterministic).
///
/// - brute_force_pairs: all N(N−1)/2 tests; the oracle the others are tested against.
/// - SweepAndPrune: endpoints sorted along the axis of largest spread, then a sweep that
///   tests only boxes whose intervals overlap on that axis. The order is kept between calls
///   and re-sorted by insertion sort, O(N) when bodies move little (temporal coherence).
/// - UniformGrid: cells of size s ≥ the largest box extent; each box is filed under the cell
///   of its lower corner, so two intersecting boxes are in the same or adjacent cells (their
///   lower corners are less than s apart on every axis); expected O(N) for even densities.
#include "phynjo/runtime/collision/bounding_volume.hpp"
#include "phynjo/runtime/core/component.hpp"

#include <compare>
#include <cstdint>
#include <span>
#include <vector>

namespace phynjo::runtime {

/// A candidate pair of box indices, a < b.
struct CandidatePair {
    Index a = 0, b = 0;
    friend auto operator<=>(const CandidatePair&, const CandidatePair&) = default;
};

/// Which broad phase a CollisionManager runs.
enum class BroadPhase { brute_force, sweep_and_prune, uniform_grid };

/// out ← every intersecting pair, by testing all of them. O(N²).
void brute_force_pairs(std::span<const AABB> boxes, std::vector<CandidatePair>& out);

/// Sweep and prune with a persistent sorted order (reuse one object across steps).
class SweepAndPrune {
public:
    /// out ← every intersecting pair. Throws std::invalid_argument for a non-finite or
    /// inverted box (naming its index).
    void find_pairs(std::span<const AABB> boxes, std::vector<CandidatePair>& out);
    /// Reserves the scratch for `boxes` boxes: later calls with at most that many allocate nothing.
    void reserve(std::size_t boxes) { order_.reserve(boxes); }

private:
    std::vector<Index> order_;
    int axis_ = 0;
};

/// Uniform grid: a dense cell table when the scene's box of cells holds at most ~4 cells per
/// box (piles, gases), a hashed one otherwise (no bound on the extent of the scene).
class UniformGrid {
public:
    /// `cell_size` (m): 0 chooses the largest box extent; a smaller value than that is raised
    /// to it (the grid needs s ≥ every extent).
    explicit UniformGrid(double cell_size = 0) : requested_(cell_size) {}
    /// out ← every intersecting pair. Throws std::invalid_argument for a non-finite or
    /// inverted box (naming its index).
    void find_pairs(std::span<const AABB> boxes, std::vector<CandidatePair>& out);
    /// Reserves the scratch (cell tables included, dense or hashed) for `boxes` boxes and
    /// `pairs` intersecting pairs: later calls with at most that many allocate nothing.
    void reserve(std::size_t boxes, std::size_t pairs = 0);
    /// The cell size used by the last call, m.
    [[nodiscard]] double cell_size() const noexcept { return cell_; }

private:
    double requested_ = 0, cell_ = 0;
    std::vector<std::uint64_t> keys_;       // cell key of each box
    std::vector<std::uint64_t> table_keys_; // open addressing: cell key (or empty)
    std::vector<std::uint32_t> table_begin_, table_count_;
    std::vector<Index> sorted_;             // boxes grouped by cell
    std::vector<AABB> by_cell_;             // dense tables: the boxes in sorted_'s order
    std::vector<Index> scratch_;
    std::vector<CandidatePair> found_;      // dense tables: the pairs cell by cell, then sorted
    std::vector<std::uint32_t> first_;      // dense tables: counting sort by the pairs' a
};

/// Throws std::invalid_argument if a box is not finite or has lo > hi.
void check_boxes(std::span<const AABB> boxes);

} // namespace phynjo::runtime
