#pragma once
/// \file
/// Components (labels of physical entities, possibly with children), the registry that gives
/// them dense indices so that state lives in flat arrays, and sets of component indices.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace phynjo::runtime {

/// Dense index of a registered component.
using Index = std::uint32_t;

/// A label that identifies a physical entity (an atom, a rigid body, a sensor flag…). The
/// type is recursive: a component may have children (the links of a chain, the atoms of a
/// molecule). Compared by value.
class Component {
public:
    Component() = default;
    explicit Component(std::string label, std::vector<Component> children = {});

    [[nodiscard]] const std::string& label() const noexcept { return label_; }
    /// The immediate children.
    [[nodiscard]] std::span<const Component> children() const noexcept { return children_; }
    /// Number of immediate children.
    [[nodiscard]] std::size_t arity() const noexcept { return children_.size(); }
    /// The whole tree flattened in preorder: this component, then each child's subtree.
    [[nodiscard]] std::vector<Component> subcomponents() const;

    friend bool operator==(const Component&, const Component&) = default;

private:
    std::string label_;
    std::vector<Component> children_;
};

/// Maps components to dense indices 0, 1, 2, … in order of registration. Labels are unique.
class Registry {
public:
    /// Registers `c` (not its children) and returns its index; the index it already has if
    /// registered. Throws std::invalid_argument for an empty label.
    Index add(const Component& c);
    /// Registers `c` and all its subcomponents; returns the index of `c`.
    Index add_tree(const Component& c);
    /// Registers a fresh component with this label.
    Index add(std::string label) { return add(Component(std::move(label))); }

    /// The index of a registered component; throws UnknownComponent otherwise.
    [[nodiscard]] Index index(const Component& c) const;
    [[nodiscard]] Index index(std::string_view label) const;
    [[nodiscard]] std::optional<Index> find(std::string_view label) const;
    [[nodiscard]] const Component& component(Index i) const { return components_.at(i); }
    [[nodiscard]] const std::string& label(Index i) const { return components_.at(i).label(); }
    [[nodiscard]] std::size_t size() const noexcept { return components_.size(); }

private:
    std::vector<Component> components_;
    std::unordered_map<std::string, Index> by_label_;
};

/// A set of component indices: sorted, unique. Cheap to intersect.
class ComponentSet {
public:
    ComponentSet() = default;
    ComponentSet(std::initializer_list<Index> indices);
    explicit ComponentSet(std::vector<Index> indices);
    /// {begin, …, end − 1}.
    static ComponentSet range(Index begin, Index end);

    [[nodiscard]] std::span<const Index> indices() const noexcept { return indices_; }
    [[nodiscard]] std::size_t size() const noexcept { return indices_.size(); }
    [[nodiscard]] bool empty() const noexcept { return indices_.empty(); }
    [[nodiscard]] bool contains(Index i) const noexcept;

    friend ComponentSet operator|(const ComponentSet& a, const ComponentSet& b);
    friend ComponentSet operator&(const ComponentSet& a, const ComponentSet& b);
    friend bool operator==(const ComponentSet&, const ComponentSet&) = default;

private:
    std::vector<Index> indices_;
};

} // namespace phynjo::runtime
