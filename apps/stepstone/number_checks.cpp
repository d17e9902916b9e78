#include "number_checks.hpp"

#include <charconv>
#include <cstdint>
#include <string>

namespace stepstone::app {

namespace {

bool all_digits(const std::string& text, std::size_t from) {
    if (from >= text.size()) return false;
    for (std::size_t i = from; i < text.size(); ++i)
        if (text[i] < '0' || text[i] > '9') return false;
    return true;
}

// "" when `text` is a whole number an unsigned (or signed) 64-bit option can hold
std::string whole_number_problem(const std::string& text, bool is_unsigned) {
    const std::size_t from = !text.empty() && (text[0] == '+' || (!is_unsigned && text[0] == '-')) ? 1 : 0;
    if (is_unsigned && !text.empty() && text[0] == '-' && all_digits(text, 1))
        return "must be a whole number >= 0, got " + text;
    if (!all_digits(text, from)) return "must be a whole number in digits, got '" + text + "'";
    const char* begin = text.data() + (text[0] == '+' ? 1 : 0);
    const char* end = text.data() + text.size();
    bool fits = false;
    if (is_unsigned) {
        std::uint64_t value = 0;
        fits = std::from_chars(begin, end, value).ec == std::errc();
    } else {
        std::int64_t value = 0;
        fits = std::from_chars(begin, end, value).ec == std::errc();
    }
    if (!fits) return "is out of range, got " + text;
    return "";
}

void add_checks(CLI::App& app) {
    for (CLI::Option* option : app.get_options()) {
        const std::string type = option->get_type_name();
        const bool is_unsigned = type.rfind("UINT", 0) == 0;
        if (!is_unsigned && type.rfind("INT", 0) != 0) continue;
        option->check(CLI::Validator(
            [is_unsigned](std::string& text) { return whole_number_problem(text, is_unsigned); }, "", ""));
    }
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) add_checks(*sub);
}

}  // namespace

void check_whole_numbers(CLI::App& app) { add_checks(app); }

}  // namespace stepstone::app
