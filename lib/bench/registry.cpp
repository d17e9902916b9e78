#include "bench/registry.hpp"

#include <algorithm>
#include <stdexcept>

#include "bench/cases.hpp"

namespace stepstone::bench {

void Registry::add(Case c) {
    if (c.name.empty()) throw std::invalid_argument("bench case without a name");
    if (find(c.name) != nullptr) throw std::invalid_argument("bench case registered twice: " + c.name);
    cases_.push_back(std::move(c));
}

const Case* Registry::find(std::string_view name) const {
    auto it = std::find_if(cases_.begin(), cases_.end(), [&](const Case& c) { return c.name == name; });
    return it == cases_.end() ? nullptr : &*it;
}

std::vector<std::string> Registry::names() const {
    std::vector<std::string> out;
    out.reserve(cases_.size());
    for (const auto& c : cases_) out.push_back(c.name);
    return out;
}

Registry default_registry() {
    Registry registry;
    add_builtin_cases(registry);
    return registry;
}

}  // namespace stepstone::bench
