#pragma once

#include <filesystem>
#include <fstream>

namespace stepstone {

/// Checks an output path before anything is computed: an existing `path` is
/// refused unless `force`, and so are a directory and a path whose folder does
/// not exist (ConfigError naming `path` as given).
void check_output_target(const std::filesystem::path& path, bool force);

/// A text or binary output written under a temporary name in the target's
/// folder and renamed over the target by commit(): a crash or an exception
/// never leaves a partial file. An existing target is refused (ConfigError)
/// unless `force`.
class OutputFile {
public:
    OutputFile(const std::filesystem::path& path, bool force);
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    std::ostream& stream() { return out_; }
    /// Flushes, closes and moves the file into place; throws Error on failure.
    void commit();

private:
    std::filesystem::path path_;
    std::filesystem::path temp_;
    std::ofstream out_;
    bool committed_ = false;
};

}  // namespace stepstone
