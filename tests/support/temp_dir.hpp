#pragma once

#include <filesystem>
#include <string>

namespace stepstone::test {

/// A fresh directory under the system temp folder, removed with its contents
/// when the object goes out of scope.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

/// Whole content of a file, as bytes in a string.
std::string read_file(const std::filesystem::path& path);
/// Writes `bytes` to `path`, replacing it.
void write_file(const std::filesystem::path& path, const std::string& bytes);

}  // namespace stepstone::test
