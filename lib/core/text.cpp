#include "core/text.hpp"

namespace stepstone {

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

}  // namespace stepstone
