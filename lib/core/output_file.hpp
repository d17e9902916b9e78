#pragma once

#include <filesystem>
#include <fstream>
#include <ostream>

namespace stepstone {

/// What an output path names, once symbolic links are followed.
enum class OutputKind {
    standard_output,  ///< "-"
    new_file,         ///< nothing there yet: created
    regular_file,     ///< an existing file: replaced whole (needs force)
    stream,           ///< an existing FIFO or character device: written through, never replaced
};

/// An output path resolved: its kind and the path to write (symbolic links
/// followed, so that a link keeps pointing where it did and gets the new file).
struct OutputTarget {
    OutputKind kind = OutputKind::new_file;
    std::filesystem::path path;
};

/// Checks an output path before anything is computed and says how it will be
/// written. "-" is standard output. Symbolic links are followed. An existing
/// regular file is refused unless `force`; a FIFO or character device is
/// written through (with or without `force`: nothing is replaced); a
/// directory, block device or socket is refused, and so is a path whose folder
/// does not exist (ConfigError naming `path` as given).
OutputTarget resolve_output_target(const std::filesystem::path& path, bool force);

/// resolve_output_target without the answer.
void check_output_target(const std::filesystem::path& path, bool force);

/// A text or binary output. A file is written under a temporary name in the
/// target's folder and renamed over the target by commit(): a crash or an
/// exception never leaves a partial file. "-" writes to standard output, and a
/// FIFO or character device is written straight through (resolve_output_target).
class OutputFile {
public:
    OutputFile(const std::filesystem::path& path, bool force);
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    std::ostream& stream() { return *sink_; }
    /// Flushes, closes and moves the file into place; throws Error on failure
    /// (a device that refuses the bytes, a full disk).
    void commit();

private:
    std::filesystem::path given_;
    OutputTarget target_;
    std::filesystem::path temp_;
    std::ofstream out_;
    std::ostream* sink_ = &out_;
    bool committed_ = false;
};

}  // namespace stepstone
