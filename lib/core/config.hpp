#pragma once

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <set>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace stepstone {

/// Reads a JSON file; throws ConfigError naming the file and the parse
/// position on a missing file or invalid JSON.
nlohmann::json load_json_file(const std::filesystem::path& path);

/// Strict reader of one JSON object of a config. Each read_* call consumes a
/// key; a missing key leaves the caller's default untouched. finish() throws if
/// the object has a key nobody read, so misspelt keys never pass silently.
/// Every error is a ConfigError whose message starts with the key path
/// (e.g. "ea.population_size must be >= 4, got 2").
class JsonReader {
public:
    /// `path` is the object's own key path ("" for the root).
    JsonReader(const nlohmann::json& object, std::string path);

    void read(std::string_view key, bool& out);
    void read(std::string_view key, std::string& out);
    /// A number within [lo, hi]; NaN and infinities are refused.
    void read(std::string_view key, double& out, double lo, double hi);
    /// An integer within [lo, hi]; 2.5 or "3" are refused.
    void read(std::string_view key, std::int64_t& out, std::int64_t lo, std::int64_t hi);
    void read(std::string_view key, int& out, int lo, int hi);
    /// A string that must be one of `choices`.
    void read_choice(std::string_view key, std::string& out, std::initializer_list<std::string_view> choices);

    /// True when the object has `key`.
    bool has(std::string_view key) const;
    /// A reader for the nested object at `key` (an empty object if absent).
    JsonReader child(std::string_view key);
    /// The raw JSON at `key` (marked as read); null when absent.
    const nlohmann::json& raw(std::string_view key);

    /// Throws ConfigError on the first key that was never read.
    void finish() const;

    /// The full path of `key` in this object, e.g. "kb.delta".
    std::string path_of(std::string_view key) const;

private:
    const nlohmann::json* find(std::string_view key);

    const nlohmann::json& object_;
    std::string path_;
    std::set<std::string, std::less<>> used_;
};

/// The first key path ("ea.population_size") at which two JSON values
/// differ, "" if they are equal; `path` prefixes the keys.
std::string first_difference(const nlohmann::json& a, const nlohmann::json& b, const std::string& path = "");

/// Short rendering of a JSON value for error messages (at most ~40 chars).
std::string describe(const nlohmann::json& value);

}  // namespace stepstone
