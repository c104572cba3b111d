#include "phynjo/runtime/core/world.hpp"

#include "phynjo/runtime/core/errors.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <new>

namespace phynjo::runtime {

FieldId Layout::field(std::string_view name) const {
    for (std::size_t i = 0; i < fields.size(); ++i)
        if (fields[i] == name) return static_cast<FieldId>(i);
    throw UnknownField("unknown field '" + std::string(name) + "'");
}

std::string Layout::describe(FieldId f, Index c) const {
    const std::string field_name = f < fields.size() ? fields[f] : "?";
    const std::string comp = c < components.size() ? components.label(c) : "#" + std::to_string(c);
    return fields.size() == 1 ? comp : field_name + ":" + comp;
}

Domain::Domain(FieldId f, ComponentSet components) {
    if (!components.empty()) parts_.emplace_back(f, std::move(components));
}

Domain Domain::all(const Layout& layout, std::initializer_list<std::string_view> fields) {
    return of(layout, fields, ComponentSet::range(0, static_cast<Index>(layout.components.size())));
}

Domain Domain::of(const Layout& layout, std::initializer_list<std::string_view> fields, const ComponentSet& components) {
    Domain d;
    for (std::string_view f : fields) d = d | Domain(layout.field(f), components);
    return d;
}

bool Domain::contains(FieldId f, Index c) const noexcept { return components(f).contains(c); }

const ComponentSet& Domain::components(FieldId f) const noexcept {
    static const ComponentSet none;
    for (const auto& [field, set] : parts_)
        if (field == f) return set;
    return none;
}

Domain operator|(const Domain& a, const Domain& b) {
    Domain r;
    auto ia = a.parts_.begin(), ib = b.parts_.begin();
    while (ia != a.parts_.end() || ib != b.parts_.end()) {
        if (ib == b.parts_.end() || (ia != a.parts_.end() && ia->first < ib->first)) r.parts_.push_back(*ia++);
        else if (ia == a.parts_.end() || ib->first < ia->first) r.parts_.push_back(*ib++);
        else {
            r.parts_.emplace_back(ia->first, ia->second | ib->second);
            ++ia;
            ++ib;
        }
    }
    return r;
}

std::vector<std::pair<FieldId, Index>> overlap(const Domain& a, const Domain& b) {
    std::vector<std::pair<FieldId, Index>> out;
    for (const auto& [f, set] : a.parts_) {
        const ComponentSet shared = set & b.components(f); // keep it alive while iterating
        for (Index i : shared.indices()) out.emplace_back(f, i);
    }
    return out;
}

void World::Free::operator()(double* p) const noexcept { std::free(p); }

World::World(std::shared_ptr<const Layout> layout) : layout_(std::move(layout)) {
    n_ = layout_->components.size();
    stride_ = (n_ + 7) / 8 * 8;
    const std::size_t bytes = std::max<std::size_t>(64, stride_ * layout_->fields.size() * sizeof(double));
    void* p = std::aligned_alloc(64, (bytes + 63) / 64 * 64);
    if (!p) throw std::bad_alloc();
    data_.reset(static_cast<double*>(p));
    std::memset(p, 0, bytes);
}

World::World(const World& o) : World(o.layout_) {
    std::memcpy(data_.get(), o.data_.get(), stride_ * layout_->fields.size() * sizeof(double));
    time = o.time;
    tick = o.tick;
}

World& World::operator=(const World& o) {
    if (this == &o) return *this;
    if (layout_ != o.layout_ || n_ != o.n_) {
        World copy(o);
        *this = std::move(copy);
        return *this;
    }
    std::memcpy(data_.get(), o.data_.get(), stride_ * layout_->fields.size() * sizeof(double));
    time = o.time;
    tick = o.tick;
    return *this;
}

bool operator==(const World& a, const World& b) noexcept {
    if (a.n_ != b.n_ || a.field_count() != b.field_count() || a.tick != b.tick ||
        std::memcmp(&a.time, &b.time, sizeof a.time) != 0)
        return false;
    for (std::size_t f = 0; f < a.field_count(); ++f)
        if (std::memcmp(a.data_.get() + f * a.stride_, b.data_.get() + f * b.stride_, a.n_ * sizeof(double)) != 0)
            return false;
    return true;
}

std::uint64_t World::hash() const noexcept {
    std::uint64_t h = 0xCBF29CE484222325ULL;
    auto bytes = [&](const void* p, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001B3ULL;
    };
    for (std::size_t f = 0; f < field_count(); ++f) bytes(data_.get() + f * stride_, n_ * sizeof(double));
    bytes(&time, sizeof time);
    return h;
}

} // namespace phynjo::runtime

#include "phynjo/runtime/core/process.hpp"

namespace phynjo::runtime {
std::optional<std::string> first_change_outside(const World& before, const World& after, const Domain& writes) {
    for (FieldId f = 0; f < before.field_count(); ++f) {
        const auto a = before.field(f), b = after.field(f);
        for (Index i = 0; i < a.size(); ++i)
            if (std::memcmp(&a[i], &b[i], sizeof(double)) != 0 && !writes.contains(f, i))
                return before.layout().describe(f, i);
    }
    return std::nullopt;
}
} // namespace phynjo::runtime
