#include "core/output_file.hpp"

#include <unistd.h>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone {

OutputFile::OutputFile(const std::filesystem::path& path, bool force) : path_(path) {
    if (std::filesystem::exists(path_) && !force) {
        throw ConfigError(concat(path_.string(), ": already exists (use --force to overwrite)"));
    }
    if (std::filesystem::is_directory(path_)) throw ConfigError(concat(path_.string(), ": is a directory"));
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
