#include "bench/registry.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "bench/cases.hpp"

namespace stepstone::bench {

namespace {

// "serve" of "serve/2"; the whole name of a case without a parameter
std::string_view case_of(std::string_view name) { return name.substr(0, name.find('/')); }

}  // namespace

void Registry::add(Case c) {
    if (c.name.empty()) throw std::invalid_argument("bench case without a name");
    if (find(c.name) != nullptr) throw std::invalid_argument("bench case registered twice: " + c.name);
    for (const auto& other : cases_) {
        if (other.name == case_of(c.name) || case_of(other.name) == c.name)
            throw std::invalid_argument("bench case " + c.name + " is ambiguous beside " + other.name);
    }
    cases_.push_back(std::move(c));
}

std::vector<const Case*> Registry::select(std::string_view name) const {
    if (const Case* exact = find(name)) return {exact};
    // every other case whose name starts with `name/` is a row of it
    std::vector<const Case*> rows;
    for (const auto& c : cases_) {
        if (case_of(c.name) == name) rows.push_back(&c);
    }
    return rows;
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
