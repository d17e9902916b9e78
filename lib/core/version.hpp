#pragma once

#include <string>
#include <string_view>

namespace stepstone {

/// The release number, e.g. "0.1.0" (the project's VERSION in CMakeLists.txt).
std::string_view program_version();

/// The git commit the binary was built from: 12 hex digits, with "-dirty" when
/// the tree had uncommitted changes, or "unknown" when built outside a git
/// checkout (e.g. from a release tarball). Refreshed at every build.
std::string_view build_commit();

/// "0.1.0+<commit>": the release and the commit together (SemVer build
/// metadata), as `--version` prints it and as each run stores it.
inline std::string full_version() {
    return std::string(program_version()) + "+" + std::string(build_commit());
}

}  // namespace stepstone
