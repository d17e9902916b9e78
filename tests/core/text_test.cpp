#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include "core/text.hpp"

using namespace stepstone;

TEST_CASE("shortest gives the shortest text that reads back as the same double", "[core][text]") {
    // hand-picked: what a user typed comes back as typed
    CHECK(shortest(1.83) == "1.83");
    CHECK(shortest(0.7) == "0.7");
    CHECK(shortest(2.0) == "2");
    CHECK(shortest(-0.25) == "-0.25");
    CHECK(shortest(1e-300) == "1e-300");
    CHECK(shortest(0.1 + 0.2) == "0.30000000000000004");
    // every text reads back as the value, and %.17g is never shorter
    for (const double v : {1.0 / 3.0, 1.83, 123456.789, 5e-324, std::numeric_limits<double>::max(), -7.0e22}) {
        const std::string text = shortest(v);
        CHECK(std::strtod(text.c_str(), nullptr) == v);
        char longest[40];
        std::snprintf(longest, sizeof longest, "%.17g", v);
        CHECK(text.size() <= std::string(longest).size());
    }
}

TEST_CASE("one_line turns line breaks into separators", "[core][text]") {
    CHECK(one_line("a\nb\r\nc\n") == "a; b; c");
    CHECK(one_line("plain") == "plain");
}

TEST_CASE("exact prints 17 significant digits, which read back bit for bit", "[core][text]") {
    // %.17g by hand: 1.83 is stored as 1.8300000000000000710542735760100185871124267578125
    CHECK(exact(1.83) == "1.8300000000000001");
    CHECK(exact(0.5) == "0.5");
    CHECK(exact(1e-300) == "1e-300");
    for (const double v : {0.1, 2.0 / 3.0, 1e300, -123.456}) CHECK(std::stod(exact(v)) == v);
}

TEST_CASE("options named in a message are spelled by the front end, other backquotes kept", "[core]") {
    CHECK(option_name("token_file") == "`token_file`");
    const auto flags = [](std::string_view name) { return "--" + std::string(name); };
    CHECK(spell_options("run.db: already exists; continue it with `resume` (or replace it with `force`)",
                        flags) ==
          "run.db: already exists; continue it with --resume (or replace it with --force)");
    CHECK(spell_options("`start` must be within 1 to 3, got 5", flags) ==
          "--start must be within 1 to 3, got 5");
    // not option names: capitals, spaces, a leading digit or underscore, an empty pair, one lone mark
    CHECK(spell_options("query `SELECT 1` failed", flags) == "query `SELECT 1` failed");
    CHECK(spell_options("`2x` and `_a` and `` stay", flags) == "`2x` and `_a` and `` stay");
    CHECK(spell_options("a lone ` mark and `kb_name`", flags) == "a lone ` mark and --kb_name");
    CHECK(spell_options("no marks at all", flags) == "no marks at all");
    CHECK(spell_options("`unclosed", flags) == "`unclosed");
}
