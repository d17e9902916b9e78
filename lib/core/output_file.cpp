#include "core/output_file.hpp"

#include <unistd.h>

#include <iostream>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone {

namespace fs = std::filesystem;

namespace {

// the path a chain of symbolic links ends at (relative links read from their folder)
fs::path follow_links(const fs::path& path) {
    fs::path at = path;
    for (int hops = 0; hops < 40; ++hops) {
        std::error_code ec;
        if (!fs::is_symlink(fs::symlink_status(at, ec))) return at;
        const fs::path next = fs::read_symlink(at, ec);
        if (ec) return at;
        at = next.is_absolute() ? next : at.parent_path() / next;
    }
    throw ConfigError(concat(path.string(), ": too many levels of symbolic links"));
}

}  // namespace

OutputTarget resolve_output_target(const fs::path& path, bool force) {
    if (path == "-") return {OutputKind::standard_output, path};
    if (path.empty()) throw ConfigError("an output path is empty");
    const fs::path target = follow_links(path);
    const std::string via = target == path ? std::string() : concat(" (a link to ", target.string(), ")");
    std::error_code ec;
    const fs::file_status status = fs::status(target, ec);
    switch (status.type()) {
        case fs::file_type::directory:
            throw ConfigError(concat(path.string(), via, ": is a directory"));
        case fs::file_type::fifo:
        case fs::file_type::character:
            return {OutputKind::stream, target};
        case fs::file_type::block:
            throw ConfigError(concat(path.string(), via, ": is a block device; not written"));
        case fs::file_type::socket:
            throw ConfigError(concat(path.string(), via, ": is a socket; not written"));
        case fs::file_type::regular:
            if (!force) {
                throw ConfigError(concat(path.string(), via, ": already exists (use ", option_name("force"),
                                         " to overwrite)"));
            }
            return {OutputKind::regular_file, target};
        case fs::file_type::not_found:
            break;
        default:
            throw ConfigError(concat(path.string(), via, ": is not a regular file; not written"));
    }
    const fs::path folder = target.parent_path();
    if (!folder.empty() && !fs::is_directory(folder, ec)) {
        throw ConfigError(concat(path.string(), via, ": cannot create: ", folder.string(),
                                 fs::exists(folder, ec) ? " is not a directory" : " does not exist"));
    }
    return {OutputKind::new_file, target};
}

void check_output_target(const fs::path& path, bool force) { resolve_output_target(path, force); }

OutputFile::OutputFile(const fs::path& path, bool force)
    : given_(path), target_(resolve_output_target(path, force)) {
    switch (target_.kind) {
        case OutputKind::standard_output:
            sink_ = &std::cout;
            return;
        case OutputKind::stream:
            out_.open(target_.path, std::ios::binary);
            if (!out_) throw Error(concat(given_.string(), ": cannot open for writing"));
            return;
        case OutputKind::new_file:
        case OutputKind::regular_file:
            break;
    }
    temp_ = target_.path.parent_path() / concat('.', target_.path.filename().string(), ".tmp-", ::getpid());
    out_.open(temp_, std::ios::binary | std::ios::trunc);
    if (!out_) throw Error(concat(given_.string(), ": cannot create file"));
}

OutputFile::~OutputFile() {
    if (committed_ || temp_.empty()) return;
    out_.close();
    std::error_code ec;
    fs::remove(temp_, ec);
}

void OutputFile::commit() {
    if (target_.kind == OutputKind::standard_output) {
        std::cout.flush();
        if (!std::cout) throw Error("standard output: write failed");
        committed_ = true;
        return;
    }
    out_.close();
    if (!out_) throw Error(concat(given_.string(), ": write failed"));
    if (target_.kind == OutputKind::stream) {
        committed_ = true;
        return;
    }
    std::error_code ec;
    fs::rename(temp_, target_.path, ec);
    if (ec) throw Error(concat(given_.string(), ": cannot move the output into place: ", ec.message()));
    committed_ = true;
}

}  // namespace stepstone
