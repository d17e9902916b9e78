#include "core/config.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone {

namespace {

const nlohmann::json& empty_object() {
    static const nlohmann::json empty = nlohmann::json::object();
    return empty;
}

}  // namespace

nlohmann::json load_json_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw ConfigError(concat(path.string(), ": cannot open config file"));
    }
    std::ostringstream text;
    text << in.rdbuf();
    try {
        return nlohmann::json::parse(text.str());
    } catch (const nlohmann::json::parse_error& e) {
        // nlohmann prefixes "[json.exception.parse_error.101] "; keep the useful part
        std::string what = e.what();
        if (auto pos = what.find("] "); pos != std::string::npos) {
            what = what.substr(pos + 2);
        }
        throw ConfigError(concat(path.string(), ": invalid JSON: ", one_line(what)));
    } catch (const nlohmann::json::exception& e) {
        // e.g. a number too large for a double (1e400)
        std::string what = e.what();
        if (auto pos = what.find("] "); pos != std::string::npos) what = what.substr(pos + 2);
        throw ConfigError(concat(path.string(), ": invalid JSON: ", one_line(what)));
    }
}

std::string describe(const nlohmann::json& value) {
    std::string text = value.dump();
    if (text.size() > 40) {
        text = text.substr(0, 37) + "...";
    }
    return text;
}

JsonReader::JsonReader(const nlohmann::json& object, std::string path)
    : object_(object), path_(std::move(path)) {
    if (!object_.is_object()) {
        throw ConfigError(concat(path_.empty() ? std::string("config") : path_,
                                 " must be a JSON object, got ", describe(object_)));
    }
}

std::string JsonReader::path_of(std::string_view key) const {
    return path_.empty() ? std::string(key) : concat(path_, '.', key);
}

bool JsonReader::has(std::string_view key) const { return object_.contains(key); }

const nlohmann::json* JsonReader::find(std::string_view key) {
    used_.emplace(key);
    auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
}

const nlohmann::json& JsonReader::raw(std::string_view key) {
    static const nlohmann::json null_value;
    const auto* value = find(key);
    return value ? *value : null_value;
}

void JsonReader::read(std::string_view key, bool& out) {
    const auto* value = find(key);
    if (!value) return;
    if (!value->is_boolean()) {
        throw ConfigError(concat(path_of(key), " must be true or false, got ", describe(*value)));
    }
    out = value->get<bool>();
}

void JsonReader::read(std::string_view key, std::string& out) {
    const auto* value = find(key);
    if (!value) return;
    if (!value->is_string()) {
        throw ConfigError(concat(path_of(key), " must be a string, got ", describe(*value)));
    }
    out = value->get<std::string>();
}

void JsonReader::read(std::string_view key, double& out, double lo, double hi) {
    const auto* value = find(key);
    if (!value) return;
    if (!value->is_number()) {
        throw ConfigError(concat(path_of(key), " must be a number, got ", describe(*value)));
    }
    const double x = value->get<double>();
    if (!std::isfinite(x) || x < lo || x > hi) {
        throw ConfigError(concat(path_of(key), " must be in [", lo, ", ", hi, "], got ", describe(*value)));
    }
    out = x;
}

void JsonReader::read(std::string_view key, std::int64_t& out, std::int64_t lo, std::int64_t hi) {
    const auto* value = find(key);
    if (!value) return;
    if (!value->is_number_integer()) {
        throw ConfigError(concat(path_of(key), " must be an integer, got ", describe(*value)));
    }
    // unsigned values above INT64_MAX are out of every range we accept
    if (value->is_number_unsigned() && value->get<std::uint64_t>() > static_cast<std::uint64_t>(hi)) {
        throw ConfigError(concat(path_of(key), " must be in [", lo, ", ", hi, "], got ", describe(*value)));
    }
    const auto x = value->get<std::int64_t>();
    if (x < lo || x > hi) {
        throw ConfigError(concat(path_of(key), " must be in [", lo, ", ", hi, "], got ", describe(*value)));
    }
    out = x;
}

void JsonReader::read(std::string_view key, int& out, int lo, int hi) {
    std::int64_t wide = out;
    read(key, wide, lo, hi);
    out = static_cast<int>(wide);
}

void JsonReader::read_choice(std::string_view key, std::string& out,
                             std::initializer_list<std::string_view> choices) {
    std::string value = out;
    read(key, value);
    for (auto choice : choices) {
        if (value == choice) {
            out = value;
            return;
        }
    }
    std::string list;
    for (auto choice : choices) {
        list += list.empty() ? "" : "|";
        list += choice;
    }
    throw ConfigError(concat(path_of(key), " must be one of ", list, ", got \"", value, '"'));
}

JsonReader JsonReader::child(std::string_view key) {
    const auto* value = find(key);
    return JsonReader(value ? *value : empty_object(), path_of(key));
}

void JsonReader::finish() const {
    for (const auto& [key, value] : object_.items()) {
        if (!used_.contains(key)) {
            throw ConfigError(concat(path_of(key), ": unknown key"));
        }
    }
}

std::string first_difference(const nlohmann::json& a, const nlohmann::json& b, const std::string& path) {
    if (a.is_object() && b.is_object()) {
        for (const auto& [key, value] : a.items()) {
            const std::string child = path.empty() ? key : path + "." + key;
            if (!b.contains(key)) return child;
            auto diff = first_difference(value, b.at(key), child);
            if (!diff.empty()) return diff;
        }
        for (const auto& [key, value] : b.items()) {
            if (!a.contains(key)) return path.empty() ? key : path + "." + key;
        }
        return "";
    }
    return a == b ? "" : (path.empty() ? std::string("config") : path);
}

}  // namespace stepstone
