#include "core/text.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>

namespace stepstone {

std::string shortest(double value) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

std::string exact(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", value);
    return buffer;
}

std::string one_line(std::string text) {
    // trailing newlines vanish; inner ones become separators
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) {
        text.pop_back();
    }
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        if (c == '\n') {
            out += "; ";
        } else if (c != '\r') {
            out += c;
        }
    }
    return out;
}

std::string spell_options(std::string_view message,
                          const std::function<std::string(std::string_view)>& spell) {
    auto is_name_char = [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; };
    std::string out;
    out.reserve(message.size());
    std::size_t k = 0;
    while (k < message.size()) {
        const std::size_t open = message.find('`', k);
        if (open == std::string_view::npos) break;
        const std::size_t close = message.find('`', open + 1);
        if (close == std::string_view::npos) break;
        const std::string_view name = message.substr(open + 1, close - open - 1);
        const bool is_name = !name.empty() && name[0] >= 'a' && name[0] <= 'z' &&
                             std::all_of(name.begin(), name.end(), is_name_char);
        out.append(message.substr(k, open - k));
        if (is_name) {
            out += spell(name);
            k = close + 1;
        } else {
            out += '`';  // not an option: keep the backquote, look again from the next character
            k = open + 1;
        }
    }
    out.append(message.substr(k));
    return out;
}

}  // namespace stepstone
