#include "phynjo/runtime/core/component.hpp"

#include "phynjo/runtime/core/errors.hpp"

#include <algorithm>
#include <stdexcept>

namespace phynjo::runtime {

Component::Component(std::string label, std::vector<Component> children)
    : label_(std::move(label)), children_(std::move(children)) {}

std::vector<Component> Component::subcomponents() const {
    std::vector<Component> out{*this};
    for (const Component& c : children_) {
        auto sub = c.subcomponents();
        out.insert(out.end(), std::make_move_iterator(sub.begin()), std::make_move_iterator(sub.end()));
    }
    return out;
}

Index Registry::add(const Component& c) {
    if (c.label().empty()) throw std::invalid_argument("a component needs a non-empty label");
    if (auto it = by_label_.find(c.label()); it != by_label_.end()) return it->second;
    const auto i = static_cast<Index>(components_.size());
    components_.push_back(c);
    by_label_.emplace(c.label(), i);
    return i;
}

Index Registry::add_tree(const Component& c) {
    const Index root = add(c);
    for (const Component& s : c.subcomponents()) add(s);
    return root;
}

std::optional<Index> Registry::find(std::string_view label) const {
    if (auto it = by_label_.find(std::string(label)); it != by_label_.end()) return it->second;
    return std::nullopt;
}

Index Registry::index(std::string_view label) const {
    if (auto i = find(label)) return *i;
    throw UnknownComponent("unknown component '" + std::string(label) + "'");
}
Index Registry::index(const Component& c) const { return index(c.label()); }

ComponentSet::ComponentSet(std::initializer_list<Index> indices) : ComponentSet(std::vector<Index>(indices)) {}
ComponentSet::ComponentSet(std::vector<Index> indices) : indices_(std::move(indices)) {
    std::sort(indices_.begin(), indices_.end());
    indices_.erase(std::unique(indices_.begin(), indices_.end()), indices_.end());
}
ComponentSet ComponentSet::range(Index begin, Index end) {
    ComponentSet s;
    for (Index i = begin; i < end; ++i) s.indices_.push_back(i);
    return s;
}
bool ComponentSet::contains(Index i) const noexcept { return std::binary_search(indices_.begin(), indices_.end(), i); }

ComponentSet operator|(const ComponentSet& a, const ComponentSet& b) {
    ComponentSet r;
    std::set_union(a.indices_.begin(), a.indices_.end(), b.indices_.begin(), b.indices_.end(),
                   std::back_inserter(r.indices_));
    return r;
}
ComponentSet operator&(const ComponentSet& a, const ComponentSet& b) {
    ComponentSet r;
    std::set_intersection(a.indices_.begin(), a.indices_.end(), b.indices_.begin(), b.indices_.end(),
                          std::back_inserter(r.indices_));
    return r;
}

} // namespace phynjo::runtime
