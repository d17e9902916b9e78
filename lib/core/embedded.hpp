#pragma once

#include <span>
#include <string_view>

namespace stepstone {

/// A text file embedded into the binary at build time (cmake/embed.cmake).
struct EmbeddedFile {
    std::string_view path;  ///< relative to its source folder, e.g. "0001_init.sql"
    std::string_view text;
};

/// The numbered migrations of schema/, sorted by file name.
std::span<const EmbeddedFile> schema_files();

/// The statements of sql/, sorted by path (e.g. "db/meta_get.sql").
std::span<const EmbeddedFile> sql_files();

/// The queries of queries/, sorted by file name.
std::span<const EmbeddedFile> query_files();

}  // namespace stepstone
