#pragma once

#include <CLI/CLI.hpp>
#include <initializer_list>
#include <ostream>
#include <string>

#include "core/output_file.hpp"

namespace stepstone::app {

/// Adds one subcommand (and its children) to the app. Each cmd_*.cpp file
/// defines one or more and registers them with a static CommandRegistrar, so
/// adding a command touches no other file.
using CommandAdder = void (*)(CLI::App& app);

/// Registers `adder`; commands appear in --help in increasing `order`.
struct CommandRegistrar {
    CommandRegistrar(int order, CommandAdder adder);
};

/// Calls every registered adder, in order.
void add_registered_commands(CLI::App& app);

/// Formats the "Example:" footer shown by --help.
std::string example(std::initializer_list<const char*> lines);

/// Checks an --individual value ('best' or an individual id), so that a bad one
/// is a usage error naming the flag before any file is opened.
const CLI::Validator& individual_check();

/// Writes `path` (nothing when empty) through `writer(std::ostream&)`, all or
/// nothing: an existing file is replaced only with `force`, and only once the
/// whole output is written.
template <typename Writer>
void write_output(const std::string& path, bool force, Writer writer) {
    if (path.empty()) return;
    OutputFile out(path, force);
    writer(out.stream());
    out.commit();
}

}  // namespace stepstone::app
