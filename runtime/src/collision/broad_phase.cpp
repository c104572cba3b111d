#include "phynjo/runtime/collision/broad_phase.hpp"

#ifdef __AVX__
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace phynjo::runtime {

void check_boxes(std::span<const AABB> boxes) {
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        if (!boxes[i].lo.allFinite() || !boxes[i].hi.allFinite())
            throw std::invalid_argument("broad phase: box " + std::to_string(i) + " is not finite");
        if ((boxes[i].lo.array() > boxes[i].hi.array()).any())
            throw std::invalid_argument("broad phase: box " + std::to_string(i) + " has lo > hi");
    }
}

void brute_force_pairs(std::span<const AABB> boxes, std::vector<CandidatePair>& out) {
    check_boxes(boxes);
    out.clear();
    const auto n = static_cast<Index>(boxes.size());
    for (Index i = 0; i < n; ++i)
        for (Index j = i + 1; j < n; ++j)
            if (intersects(boxes[i], boxes[j])) out.push_back({i, j});
}

// ---- sweep and prune -------------------------------------------------------------------------

void SweepAndPrune::find_pairs(std::span<const AABB> boxes, std::vector<CandidatePair>& out) {
    check_boxes(boxes);
    out.clear();
    const std::size_t n = boxes.size();
    if (n < 2) return;
    // The axis along which the centres spread most separates the most boxes.
    Eigen::Vector3d mean = Eigen::Vector3d::Zero(), sq = Eigen::Vector3d::Zero();
    for (const AABB& b : boxes) {
        const Eigen::Vector3d c = 0.5 * (b.lo + b.hi);
        mean += c;
        sq += c.cwiseProduct(c);
    }
    mean /= static_cast<double>(n);
    const Eigen::Vector3d var = sq / static_cast<double>(n) - mean.cwiseProduct(mean);
    int axis = 0;
    var.maxCoeff(&axis);
    auto less = [&](Index i, Index j) {
        const double a = boxes[i].lo(axis), b = boxes[j].lo(axis);
        return a < b || (a == b && i < j);
    };
    bool sorted = false;
    if (order_.size() == n && axis == axis_) {
        // Insertion sort of last call's order: linear when little moved; give up (and sort
        // from scratch) once the shifts show that much did.
        std::size_t shifts = 0;
        sorted = true;
        for (std::size_t k = 1; k < n && sorted; ++k) {
            const Index x = order_[k];
            std::size_t m = k;
            while (m > 0 && less(x, order_[m - 1])) {
                order_[m] = order_[m - 1];
                --m;
                if (++shifts > 8 * n + 64) sorted = false;
            }
            order_[m] = x;
        }
    }
    if (!sorted) {
        order_.resize(n);
        std::iota(order_.begin(), order_.end(), Index{0});
        std::sort(order_.begin(), order_.end(), less);
        axis_ = axis;
    }
    for (std::size_t k = 0; k < n; ++k) {
        const Index i = order_[k];
        const double hi = boxes[i].hi(axis);
        for (std::size_t m = k + 1; m < n && boxes[order_[m]].lo(axis) <= hi; ++m) {
            const Index j = order_[m];
            if (intersects(boxes[i], boxes[j])) out.push_back({std::min(i, j), std::max(i, j)});
        }
    }
    std::sort(out.begin(), out.end());
}

// ---- uniform grid ----------------------------------------------------------------------------

namespace {

constexpr int kBits = 21;
constexpr std::int64_t kMaxCell = (std::int64_t{1} << kBits) - 1;
constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

std::uint64_t pack(std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<std::uint64_t>(x) | (static_cast<std::uint64_t>(y) << kBits) |
           (static_cast<std::uint64_t>(z) << (2 * kBits));
}
std::size_t slot_of(std::uint64_t key, std::size_t mask) {
    // splitmix64's finalizer: every key bit reaches every slot bit (a plain multiplicative
    // hash read from low bits ignored z, so cells differing only in z shared probe chains).
    key ^= key >> 30;
    key *= 0xBF58476D1CE4E5B9ull;
    key ^= key >> 27;
    key *= 0x94D049BB133111EBull;
    key ^= key >> 31;
    return static_cast<std::size_t>(key) & mask;
}

} // namespace

namespace {
/// The largest cell table find_pairs builds for n boxes: dense up to 4n + 1024 cells, hashed
/// with the smallest power of two ≥ 2n slots (< 4n).
std::size_t table_bound(std::size_t n) { return 4 * n + 1024; }
} // namespace

void UniformGrid::reserve(std::size_t boxes, std::size_t pairs) {
    found_.reserve(pairs);
    first_.reserve(boxes + 1);
    keys_.reserve(boxes);
    sorted_.reserve(boxes);
    by_cell_.reserve(boxes);
    scratch_.reserve(boxes);
    table_keys_.reserve(table_bound(boxes));
    table_begin_.reserve(table_bound(boxes));
    table_count_.reserve(table_bound(boxes));
}

void UniformGrid::find_pairs(std::span<const AABB> boxes, std::vector<CandidatePair>& out) {
    check_boxes(boxes);
    out.clear();
    const std::size_t n = boxes.size();
    if (n < 2) return;
    double largest = 0;
    Eigen::Vector3d origin = boxes[0].lo;
    for (const AABB& b : boxes) {
        largest = std::max(largest, b.extent().maxCoeff());
        origin = origin.cwiseMin(b.lo);
    }
    cell_ = std::max(requested_, largest);
    if (!(cell_ > 0)) cell_ = 1; // all boxes are points: any cell size works
    // Cell coordinates relative to the scene's lower corner, clamped to 21 bits. Clamping
    // merges far cells, never separates neighbours, so no intersecting pair is lost.
    auto coord = [&](double x, double o) {
        const double c = std::floor((x - o) / cell_);
        return static_cast<std::int64_t>(std::clamp(c, 0.0, static_cast<double>(kMaxCell)));
    };
    keys_.resize(n);
    std::int64_t ext[3] = {0, 0, 0};
    for (std::size_t i = 0; i < n; ++i) {
        const std::int64_t c[3] = {coord(boxes[i].lo.x(), origin.x()), coord(boxes[i].lo.y(), origin.y()),
                                   coord(boxes[i].lo.z(), origin.z())};
        for (int k = 0; k < 3; ++k) ext[k] = std::max(ext[k], c[k] + 1);
        keys_[i] = pack(c[0], c[1], c[2]);
    }
    const std::uint64_t m21 = static_cast<std::uint64_t>(kMaxCell);
    auto unpack = [&](std::uint64_t key, std::int64_t& x, std::int64_t& y, std::int64_t& z) {
        x = static_cast<std::int64_t>(key & m21);
        y = static_cast<std::int64_t>((key >> kBits) & m21);
        z = static_cast<std::int64_t>(key >> (2 * kBits));
    };
    // Cell table: dense (direct indexing) when the occupied box of cells is small next to n,
    // as in piles and gases; hashed (open addressing) when the scene is sparse.
    const double cells = static_cast<double>(ext[0]) * static_cast<double>(ext[1]) * static_cast<double>(ext[2]);
    const bool dense = cells <= static_cast<double>(table_bound(n));
    std::size_t cap = 16, mask = 0;
    if (dense) {
        cap = static_cast<std::size_t>(cells);
    } else {
        while (cap < 2 * n) cap *= 2;
        mask = cap - 1;
        table_keys_.assign(cap, kEmpty);
    }
    table_count_.assign(cap, 0);
    table_begin_.resize(cap);
    // The slot of a cell, or cap if the cell is empty (hashed) / outside the table (dense).
    auto find = [&](std::uint64_t key) {
        std::size_t s = slot_of(key, mask);
        while (table_keys_[s] != kEmpty && table_keys_[s] != key) s = (s + 1) & mask;
        return s;
    };
    auto dense_slot = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
        return static_cast<std::size_t>(x + ext[0] * (y + ext[1] * z));
    };
    auto slot_for_insert = [&](std::uint64_t key) {
        if (dense) {
            std::int64_t x, y, z;
            unpack(key, x, y, z);
            return dense_slot(x, y, z);
        }
        const std::size_t s = find(key);
        table_keys_[s] = key;
        return s;
    };
    for (std::size_t i = 0; i < n; ++i) ++table_count_[slot_for_insert(keys_[i])];
    std::uint32_t total = 0;
    for (std::size_t s = 0; s < cap; ++s) {
        table_begin_[s] = total;
        total += table_count_[s];
        table_count_[s] = 0;
    }
    sorted_.resize(n);
    for (std::size_t i = 0; i < n; ++i) { // stable: each cell lists its boxes in index order
        const std::size_t s = slot_for_insert(keys_[i]);
        sorted_[table_begin_[s] + table_count_[s]++] = static_cast<Index>(i);
    }
    if (dense) {
        // Cell by cell: the pairs within it and with its 13 neighbours ahead (each pair of
        // neighbouring cells once) — five runs of sorted_, as the table orders its cells x
        // fastest: the next cell along x, and the rows of three at (y + 1, z) and (y − 1..y + 1,
        // z + 1) — intersects' six comparisons without branches (most neighbours miss on one);
        // then the pairs in (a, b) order by a counting sort on a, each a's few b's by
        // insertion, as the 27-cell scan per box would list them.
        // The boxes copied in cell order: a cell's neighbours are then read in runs.
        found_.clear();
        by_cell_.resize(n);
        for (std::size_t k = 0; k < n; ++k) by_cell_[k] = boxes[sorted_[k]];
        // intersects(a, c) as two comparisons of four lanes: c's bytes from lo.x and from lo.z
        // (both within c) against a's hi with +∞ after it and a's lo with −∞ before it, the
        // infinities padding the lanes that read c's other corner. Boxes are finite (check_boxes).
        using V = double __attribute__((vector_size(32)));
        using Mask = long long __attribute__((vector_size(32)));
        static_assert(sizeof(AABB) == 6 * sizeof(double));
        constexpr double inf = std::numeric_limits<double>::infinity();
        struct Probe {
            V hi, lo;
        };
        auto probe = [](const AABB& a) { return Probe{V{a.hi.x(), a.hi.y(), a.hi.z(), inf}, V{-inf, a.lo.x(), a.lo.y(), a.lo.z()}}; };
        auto hit = [](const Probe& p, const AABB& c) {
            V from_lo, from_hi;
            std::memcpy(&from_lo, reinterpret_cast<const char*>(&c), sizeof(V));                      // lo.x lo.y lo.z hi.x
            std::memcpy(&from_hi, reinterpret_cast<const char*>(&c) + 2 * sizeof(double), sizeof(V)); // lo.z hi.x hi.y hi.z
            const Mask t = (p.hi >= from_lo) & (from_hi >= p.lo);
#ifdef __AVX__
            return _mm256_movemask_pd(reinterpret_cast<__m256d>(t)) == 0xF;
#else
            return (t[0] & t[1] & t[2] & t[3]) != 0;
#endif
        };
        static constexpr int kRows[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}}; // (dy, dz) of the rows of three
        for (std::int64_t z = 0; z < ext[2]; ++z)
            for (std::int64_t y = 0; y < ext[1]; ++y)
                for (std::int64_t x = 0; x < ext[0]; ++x) {
                    const std::size_t s = dense_slot(x, y, z);
                    const std::uint32_t b = table_begin_[s], e = b + table_count_[s];
                    if (b == e) continue;
                    for (std::uint32_t k = b; k < e; ++k) { // a cell lists its boxes in index order
                        const Probe pa = probe(by_cell_[k]);
                        for (std::uint32_t m = k + 1; m < e; ++m)
                            if (hit(pa, by_cell_[m])) found_.push_back({sorted_[k], sorted_[m]});
                    }
                    auto run = [&](std::uint32_t f, std::uint32_t g) {
                        for (std::uint32_t k = b; k < e; ++k) {
                            const Probe pa = probe(by_cell_[k]);
                            for (std::uint32_t m = f; m < g; ++m)
                                if (hit(pa, by_cell_[m])) {
                                    const Index i = sorted_[k], j = sorted_[m];
                                    found_.push_back({std::min(i, j), std::max(i, j)});
                                }
                        }
                    };
                    if (x + 1 < ext[0]) run(e, table_begin_[s + 1] + table_count_[s + 1]);
                    const std::int64_t x0 = std::max<std::int64_t>(x - 1, 0), x1 = std::min<std::int64_t>(x + 1, ext[0] - 1);
                    for (const auto& d : kRows) {
                        const std::int64_t ny = y + d[0], nz = z + d[1];
                        if (ny < 0 || ny >= ext[1] || nz >= ext[2]) continue;
                        const std::size_t first = dense_slot(x0, ny, nz), last = dense_slot(x1, ny, nz);
                        run(table_begin_[first], table_begin_[last] + table_count_[last]);
                    }
                }
        first_.assign(n + 1, 0);
        for (const CandidatePair& p : found_) ++first_[p.a + 1];
        for (std::size_t i = 0; i < n; ++i) first_[i + 1] += first_[i];
        out.resize(found_.size());
        for (const CandidatePair& p : found_) out[first_[p.a]++] = p;
        for (std::size_t i = 0, at = 0; i < n; ++i) { // first_[i]: now the end of a = i's pairs
            for (std::size_t k = at + 1; k < first_[i]; ++k)
                for (std::size_t m = k; m > at && out[m].b < out[m - 1].b; --m) std::swap(out[m], out[m - 1]);
            at = first_[i];
        }
        return;
    }
    for (std::size_t i = 0; i < n; ++i) {
        std::int64_t cx, cy, cz;
        unpack(keys_[i], cx, cy, cz);
        scratch_.clear();
        {
            for (std::int64_t dz = -1; dz <= 1; ++dz)
                for (std::int64_t dy = -1; dy <= 1; ++dy)
                    for (std::int64_t dx = -1; dx <= 1; ++dx) {
                        const std::int64_t x = cx + dx, y = cy + dy, z = cz + dz;
                        if (x < 0 || y < 0 || z < 0 || x > kMaxCell || y > kMaxCell || z > kMaxCell) continue;
                        const std::size_t s = find(pack(x, y, z));
                        if (table_keys_[s] == kEmpty) continue;
                        // A cell lists its boxes in index order: from the last down to the first
                        // beyond i (each pair once, as (i, j > i)).
                        const std::uint32_t b = table_begin_[s], e = b + table_count_[s];
                        for (std::uint32_t k = e; k-- > b;) {
                            const Index j = sorted_[k];
                            if (j <= i) break;
                            if (intersects(boxes[i], boxes[j])) scratch_.push_back(j);
                        }
                    }
        }
        std::sort(scratch_.begin(), scratch_.end());
        for (Index j : scratch_) out.push_back({static_cast<Index>(i), j});
    }
}

} // namespace phynjo::runtime
