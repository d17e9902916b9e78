#include "core/output_file.hpp"

#include <unistd.h>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone {

void check_output_target(const std::filesystem::path& path, bool force) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw ConfigError(concat(path.string(), ": is a directory"));
    if (fs::exists(path, ec) && !force) {
        throw ConfigError(
            concat(path.string(), ": already exists (use ", option_name("force"), " to overwrite)"));
    }
    const fs::path folder = path.parent_path();
    if (!folder.empty() && !fs::is_directory(folder, ec)) {
        throw ConfigError(concat(path.string(), ": cannot create: ", folder.string(),
                                 fs::exists(folder, ec) ? " is not a directory" : " does not exist"));
    }
}

OutputFile::OutputFile(const std::filesystem::path& path, bool force) : path_(path) {
    check_output_target(path_, force);
    temp_ = path_.parent_path() / concat('.', path_.filename().string(), ".tmp-", ::getpid());
    out_.open(temp_, std::ios::binary | std::ios::trunc);
    if (!out_) throw Error(concat(path_.string(), ": cannot create file"));
}

OutputFile::~OutputFile() {
    if (committed_) return;
    out_.close();
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
}

void OutputFile::commit() {
    out_.close();
    if (!out_) throw Error(concat(path_.string(), ": write failed"));
    std::error_code ec;
    std::filesystem::rename(temp_, path_, ec);
    if (ec) throw Error(concat(path_.string(), ": cannot move the output into place: ", ec.message()));
    committed_ = true;
}

}  // namespace stepstone
