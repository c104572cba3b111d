#pragma once
/// \file
/// Where state lives: a Layout (components × named scalar fields) and a World holding one
/// contiguous, 64-byte-aligned array of doubles per field (structure of arrays), and the
/// Domain of a rule: which (field, components) entries it touches.
#include "phynjo/runtime/core/component.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace phynjo::runtime {

using FieldId = std::uint16_t;

/// The shape of a world: its components and its fields (one double per component each).
struct Layout {
    Registry components;
    std::vector<std::string> fields;

    Layout() = default;
    Layout(Registry r, std::vector<std::string> f) : components(std::move(r)), fields(std::move(f)) {}
    /// The id of a field; throws UnknownField.
    [[nodiscard]] FieldId field(std::string_view name) const;
    /// `field:component`, for messages.
    [[nodiscard]] std::string describe(FieldId f, Index c) const;
};

/// A set of (field, component) entries. Built once per rule; compared when workflows are built.
class Domain {
public:
    Domain() = default;
    /// `components` of field `f`.
    Domain(FieldId f, ComponentSet components);
    /// Every component of each of the `fields`.
    static Domain all(const Layout& layout, std::initializer_list<std::string_view> fields);
    /// The same components in each of the `fields`.
    static Domain of(const Layout& layout, std::initializer_list<std::string_view> fields, const ComponentSet& components);

    [[nodiscard]] const std::vector<std::pair<FieldId, ComponentSet>>& parts() const noexcept { return parts_; }
    [[nodiscard]] bool empty() const noexcept { return parts_.empty(); }
    [[nodiscard]] bool contains(FieldId f, Index c) const noexcept;
    /// The components of field `f` in this domain (empty if none).
    [[nodiscard]] const ComponentSet& components(FieldId f) const noexcept;

    friend Domain operator|(const Domain& a, const Domain& b);
    /// The entries both domains contain.
    friend std::vector<std::pair<FieldId, Index>> overlap(const Domain& a, const Domain& b);

private:
    std::vector<std::pair<FieldId, ComponentSet>> parts_; // sorted by field, no empty sets
};

/// State as flat arrays: field f of component i is `field(f)[i]`. Copyable (a world is a
/// value); a step mutates it in place, which is the pure function (dt, world) → world
/// implemented without allocation.
class World {
public:
    explicit World(std::shared_ptr<const Layout> layout);
    World(const World& other);
    World& operator=(const World& other);
    World(World&&) noexcept = default;
    World& operator=(World&&) noexcept = default;

    [[nodiscard]] const Layout& layout() const noexcept { return *layout_; }
    [[nodiscard]] const std::shared_ptr<const Layout>& layout_ptr() const noexcept { return layout_; }
    [[nodiscard]] std::size_t size() const noexcept { return n_; }
    [[nodiscard]] std::size_t field_count() const noexcept { return layout_->fields.size(); }

    [[nodiscard]] std::span<double> field(FieldId f) noexcept { return {data_.get() + f * stride_, n_}; }
    [[nodiscard]] std::span<const double> field(FieldId f) const noexcept { return {data_.get() + f * stride_, n_}; }
    [[nodiscard]] std::span<double> field(std::string_view name) { return field(layout_->field(name)); }
    [[nodiscard]] std::span<const double> field(std::string_view name) const { return field(layout_->field(name)); }
    [[nodiscard]] double& at(FieldId f, Index i) noexcept { return data_[f * stride_ + i]; }
    [[nodiscard]] double at(FieldId f, Index i) const noexcept { return data_[f * stride_ + i]; }

    double time = 0;        ///< simulated time, s
    std::uint64_t tick = 0; ///< interpreter ticks (one per executed action along the longest branch)

    /// Bitwise equality of every field, time and tick.
    friend bool operator==(const World& a, const World& b) noexcept;
    /// FNV-1a over the bytes of every field: a determinism fingerprint.
    [[nodiscard]] std::uint64_t hash() const noexcept;

private:
    struct Free {
        void operator()(double* p) const noexcept;
    };
    std::shared_ptr<const Layout> layout_;
    std::size_t n_ = 0, stride_ = 0; // stride: n rounded up to 8 doubles (64 bytes)
    std::unique_ptr<double[], Free> data_;
};

/// For the checked interpreter: the first entry outside `writes` that differs, described.
std::optional<std::string> first_change_outside(const World& before, const World& after, const Domain& writes);

} // namespace phynjo::runtime
