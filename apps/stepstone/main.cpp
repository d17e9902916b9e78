// stepstone: one binary, one subcommand per file; this file parses, dispatches
// and maps every escaped exception to one stderr line and an exit code.

#include <algorithm>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "core/cpu.hpp"
#include "core/error.hpp"
#include "core/math_fingerprint.hpp"
#include "core/text.hpp"
#include "core/version.hpp"
#include "evo/edit_distance.hpp"
#include "kb/detail/simd.hpp"
#include "nn/network.hpp"
#include "number_checks.hpp"
#include "sim/arena.hpp"

namespace stepstone::app {

namespace {

std::vector<std::pair<int, CommandAdder>>& registry() {
    static std::vector<std::pair<int, CommandAdder>> adders;
    return adders;
}

}  // namespace

CommandRegistrar::CommandRegistrar(int order, CommandAdder adder) { registry().emplace_back(order, adder); }

void add_registered_commands(CLI::App& app) {
    auto adders = registry();
    std::stable_sort(adders.begin(), adders.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& entry : adders) entry.second(app);
}

const CLI::Validator& individual_check() {
    static const CLI::Validator check(
        [](std::string& value) -> std::string {
            if (value == "best" || (!value.empty() && value.size() < 19 &&
                                    value.find_first_not_of("0123456789") == std::string::npos)) {
                return "";
            }
            return "must be 'best' or an individual id, got \"" + value + "\"";
        },
        "best|ID");
    return check;
}

std::string example(std::initializer_list<const char*> lines) {
    std::string text = "\nExample:";
    for (const char* line : lines) text += std::string("\n  ") + line;
    return text + "\n";
}

}  // namespace stepstone::app

namespace {

// exit codes: 0 ok, 1 runtime/data/database, 2 usage/config, 70 internal
constexpr int kExitRuntime = 1;
constexpr int kExitUsage = 2;
constexpr int kExitInternal = 70;
constexpr int kExitInterrupted = 130;

// the library names the options of its calls (`force`, `token_file`); the CLI
// spells them as its flags: --force, --token-file, and the few whose flag is
// not the option's name with dashes
std::string as_flags(const std::string& message) {
    return stepstone::spell_options(message, [](std::string_view name) {
        static const std::pair<std::string_view, std::string_view> renamed[] = {
            {"timeout_seconds", "--timeout"},
            {"config_path", "--config"},
            {"runs_files", "--runs"},
            {"events_files", "--events"}};
        for (const auto& [option, flag] : renamed) {
            if (name == option) return std::string(flag);
        }
        std::string flag = "--" + std::string(name);
        std::replace(flag.begin(), flag.end(), '_', '-');
        return flag;
    });
}

int fail(const std::string& message, int code) {
    std::cerr << "stepstone: error: " << stepstone::one_line(as_flags(message)) << std::endl;
    return code;
}

// optimal-string-alignment distance, for "did you mean"
std::size_t typo_distance(const std::string& a, const std::string& b) {
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
            }
        }
    }
    return d[a.size()][b.size()];
}

// "unknown command 'evolv' (did you mean 'evolve'?)" when the first word that
// is not a known subcommand (at the top level or under kb, db) is close to one
std::string unknown_command(const CLI::App& app, int argc, char** argv) {
    const CLI::App* level = &app;
    std::string path = "stepstone";
    for (int k = 1; k < argc; ++k) {
        const std::string word = argv[k];
        if (word.empty() || word[0] == '-') return "";
        const auto subcommands = level->get_subcommands([](const CLI::App*) { return true; });
        if (subcommands.empty()) return "";
        const CLI::App* next = nullptr;
        std::string best;
        std::size_t best_distance = 3;
        for (const auto* sub : subcommands) {
            if (sub->get_name() == word) next = sub;
            const std::size_t distance = typo_distance(word, sub->get_name());
            const bool prefix = sub->get_name().rfind(word, 0) == 0;
            if (distance < best_distance || (prefix && best.empty())) {
                best = sub->get_name();
                best_distance = prefix ? std::min<std::size_t>(distance, 2) : distance;
            }
        }
        if (!next) {
            return "unknown command '" + word + "' for " + path +
                   (best.empty() ? " (see " + path + " --help)" : " (did you mean '" + best + "'?)");
        }
        level = next;
        path += " " + word;
    }
    return "";
}

// "unknown option '--generatoins' for stepstone evolve (did you mean
// '--generations'?)" for the first argument starting with '-' that the chosen
// command does not know; "" when every one is known
// the subcommand the leading words of argv name, and its path ("stepstone kb stats")
std::pair<const CLI::App*, std::string> command_of(const CLI::App& app, int argc, char** argv) {
    const CLI::App* level = &app;
    std::string path = "stepstone";
    for (int k = 1; k < argc; ++k) {
        const std::string word = argv[k];
        if (word.empty() || word[0] == '-') break;
        const CLI::App* next = nullptr;
        for (const auto* sub : level->get_subcommands([](const CLI::App*) { return true; })) {
            if (sub->get_name() == word) next = sub;
        }
        if (!next) break;
        level = next;
        path += " " + word;
    }
    return {level, path};
}

// CLI11 lists extra arguments last first: "unexpected arguments for stepstone
// evolve: 10 extra", in the order given
std::string unexpected_arguments(const std::string& message, const std::string& path) {
    const auto colon = message.find(": ");
    if (message.rfind("The following argument", 0) != 0 || colon == std::string::npos) return message;
    std::vector<std::string> words;
    std::string word;
    for (const char c : message.substr(colon + 2) + " ") {
        if (c != ' ') {
            word += c;
        } else if (!word.empty()) {
            words.push_back(word);
            word.clear();
        }
    }
    std::string listed;
    for (auto it = words.rbegin(); it != words.rend(); ++it) listed += (listed.empty() ? "" : " ") + *it;
    return stepstone::concat(words.size() == 1 ? "unexpected argument for " : "unexpected arguments for ",
                             path, ": ", listed, " (see ", path, " --help)");
}

std::string unknown_option(const CLI::App& app, int argc, char** argv) {
    const auto [level, path] = command_of(app, argc, argv);
    std::vector<std::string> known;
    for (const auto* option : level->get_options()) {
        for (const auto& name : option->get_lnames()) known.push_back("--" + name);
        for (const auto& name : option->get_snames()) known.push_back("-" + name);
    }
    for (int k = 1; k < argc; ++k) {
        std::string word = argv[k];
        if (word == "--") break;
        if (word.size() < 2 || word[0] != '-' || (word[1] >= '0' && word[1] <= '9') || word[1] == '.')
            continue;
        if (const auto equals = word.find('='); equals != std::string::npos) word.resize(equals);
        if (std::find(known.begin(), known.end(), word) != known.end()) continue;
        std::string best;
        std::size_t best_distance = 3;
        for (const auto& name : known) {
            const std::size_t distance = typo_distance(word, name);
            if (distance < best_distance) best = name, best_distance = distance;
        }
        return "unknown option '" + word + "' for " + path +
               (best.empty() ? " (see " + path + " --help)" : " (did you mean '" + best + "'?)");
    }
    return "";
}

// which builds of the hand-written kernels this process runs: "avx2", "generic" (a CPU without
// AVX2, or STEPSTONE_NO_AVX2 set: core/cpu.hpp), or the modules that differ; then the modules
// whose AVX-512 builds run (a CPU with AVX-512, STEPSTONE_NO_AVX512 unset)
std::string kernels() {
    const std::vector<std::pair<const char*, bool>> modules{
        {"sim", stepstone::sim::avx2_kernels()},
        {"nn", stepstone::nn::cpu_has_avx2()},
        {"evo", stepstone::evo::EditDistanceBatch().uses_avx2()},
        {"kb", stepstone::kb::detail::use_avx2()}};
    std::string avx2;
    std::string generic;
    for (const auto& [name, on] : modules) {
        std::string& list = on ? avx2 : generic;
        list += (list.empty() ? "" : " ") + std::string(name);
    }
    // the modules with AVX-512 builds: the lanes' sine and cosine (core), the networks' sigmoids in
    // lanes (nn)
    const std::string avx512 = stepstone::avx512_kernels_allowed() ? ", avx-512 in core nn" : "";
    if (generic.empty()) return "avx2" + avx512;
    if (avx2.empty()) return "generic";
    return "avx2 in " + avx2 + ", generic in " + generic + avx512;
}

}  // namespace

// CLI11's own wording of an option given more times than it takes, in the
// project's words ("" when `what` is another message)
static std::string plain_parse_error(const std::string& what) {
    // "--seed: At Most 1 required but received 2"
    if (const auto at = what.find(": At Most 1 required but received "); at != std::string::npos)
        return what.substr(0, at) + ": given " + what.substr(at + 34) + " times; give it once";
    // "Could not convert: --threshold = abc"
    if (what.rfind("Could not convert: ", 0) == 0) {
        const auto eq = what.find(" = ");
        if (eq != std::string::npos)
            return what.substr(19, eq - 19) + ": '" + what.substr(eq + 3) +
                   "' is not a value of its kind (a number?)";
    }
    // "--runs: 1 required TEXT missing"
    if (const auto at = what.find(": 1 required "); at != std::string::npos && what.ends_with(" missing"))
        return what.substr(0, at) + ": needs a value after it";
    // "--reading: strides not in {segments,windows}"
    if (const auto at = what.find(" not in {"); at != std::string::npos && what.ends_with("}")) {
        const auto colon = what.find(": ");
        if (colon != std::string::npos && colon < at) {
            std::string choices = what.substr(at + 9, what.size() - at - 10);
            for (auto& c : choices)
                if (c == ',') c = '|';
            return what.substr(0, colon) + " must be one of " + choices + ", got '" +
                   what.substr(colon + 2, at - colon - 2) + "'";
        }
    }
    return "";
}

int main(int argc, char** argv) {
    CLI::App app{"stepstone: transfer learning for evolutionary robotics by reward shaping"};
    // the math library's fingerprint (core/math_fingerprint.hpp), computed only when asked
    app.set_version_flag("--version", [] {
        return "stepstone " + std::string(stepstone::program_version()) + " (commit " +
               std::string(stepstone::build_commit()) + ", math fingerprint " +
               stepstone::math_fingerprint() + ", kernels " + kernels() + ")";
    });
    app.require_subcommand(1);
    app.footer(stepstone::app::example({"stepstone db info run.db", "stepstone demo"}));
    stepstone::app::add_registered_commands(app);
    stepstone::app::check_whole_numbers(app);

    try {
        app.parse(argc, argv);  // runs the chosen command's callback
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        std::string unknown = unknown_command(app, argc, argv);
        if (unknown.empty() && dynamic_cast<const CLI::ExtrasError*>(&e)) {
            unknown = unknown_option(app, argc, argv);
            if (unknown.empty()) unknown = unexpected_arguments(e.what(), command_of(app, argc, argv).second);
        }
        if (unknown.empty()) unknown = plain_parse_error(e.what());
        return fail(unknown.empty() ? std::string(e.what()) : unknown, kExitUsage);
    } catch (const stepstone::Interrupted& e) {
        std::cerr << "stepstone: interrupted: " << stepstone::one_line(as_flags(e.what())) << std::endl;
        return kExitInterrupted;
    } catch (const stepstone::ConfigError& e) {
        return fail(e.what(), kExitUsage);
    } catch (const stepstone::Error& e) {
        return fail(e.what(), kExitRuntime);
    } catch (const std::filesystem::filesystem_error& e) {
        // a path the user gave cannot be used (a file where a folder is expected, no permission)
        return fail(e.path1().string() + ": " + e.code().message(), kExitRuntime);
    } catch (const std::exception& e) {
        return fail(std::string("internal error: ") + e.what(), kExitInternal);
    } catch (...) {
        return fail("internal error: unknown exception", kExitInternal);
    }
    return 0;
}
