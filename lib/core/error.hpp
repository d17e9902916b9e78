#pragma once

#include <stdexcept>
#include <string>

namespace stepstone {

/// Base of every error reported to users. what() is a single line that names
/// the offending value, key or file, with no trailing period.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A config key, CLI flag or argument has an unusable value (exit code 2).
class ConfigError : public Error {
public:
    using Error::Error;
};

/// A database is missing, foreign, corrupt, of an unknown schema version, or
/// an SQLite call failed (exit code 1).
class DatabaseError : public Error {
public:
    using Error::Error;
};

/// Data is unusable: NaN, wrong dimensions, inconsistent sizes (exit code 1).
class DataError : public Error {
public:
    using Error::Error;
};

}  // namespace stepstone

namespace stepstone {

/// The user stopped a long command (SIGINT or SIGTERM) at a safe point; what()
/// says how to continue. Exit code 130.
class Interrupted : public Error {
public:
    using Error::Error;
};

}  // namespace stepstone
