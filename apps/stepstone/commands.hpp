#pragma once

#include <initializer_list>
#include <string>

#include <CLI/CLI.hpp>

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

}  // namespace stepstone::app
