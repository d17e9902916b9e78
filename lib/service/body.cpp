#include "service/body.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>

#include "core/text.hpp"
#include "service/service.hpp"

namespace stepstone::service {

namespace {

using nlohmann::json;

bool is_packed_row(const json& value) { return value.is_binary() && !value.get_binary().has_subtype(); }

bool is_packed_matrix(const json& value) { return value.is_binary() && value.get_binary().has_subtype(); }

// the float32 of a JSON number, if it is one and finite as float32
std::optional<float> finite_float(const json& value) {
    if (!value.is_number()) return std::nullopt;
    const double d = value.get<double>();
    const auto f = static_cast<float>(d);
    if (!std::isfinite(d) || !std::isfinite(f)) return std::nullopt;
    return f;
}

// the parser's callback: packs each array as it ends, if it can (body.hpp)
bool pack(int /*depth*/, json::parse_event_t event, json& parsed) {
    if (event != json::parse_event_t::array_end || !parsed.is_array() || parsed.empty()) return true;
    if (parsed[0].is_number()) {
        json::binary_t::container_type bytes(parsed.size() * sizeof(float));
        std::size_t k = 0;
        for (const auto& value : parsed) {
            const auto f = finite_float(value);
            if (!f) return true;
            std::memcpy(bytes.data() + k++ * sizeof(float), &*f, sizeof(float));
        }
        parsed = json::binary(std::move(bytes));
    } else if (is_packed_row(parsed[0])) {
        const std::size_t row_bytes = parsed[0].get_binary().size();
        for (const auto& row : parsed) {
            if (!is_packed_row(row) || row.get_binary().size() != row_bytes) return true;
        }
        json::binary_t::container_type bytes;
        bytes.reserve(parsed.size() * row_bytes);
        for (const auto& row : parsed)
            bytes.insert(bytes.end(), row.get_binary().begin(), row.get_binary().end());
        parsed = json::binary(std::move(bytes), row_bytes / sizeof(float));
    }
    return true;
}

void append_floats(const json::binary_t& bytes, std::vector<float>& out) {
    const std::size_t start = out.size();
    out.resize(start + bytes.size() / sizeof(float));
    std::memcpy(out.data() + start, bytes.data(), bytes.size());
}

}  // namespace

json parse_body(const std::string& body) {
    try {
        return json::parse(body, pack);
    } catch (const json::parse_error& e) {
        throw HttpError(400, concat("malformed JSON: ", e.what()));
    } catch (const json::exception& e) {
        // a number beyond double's range (1e400) and the like
        throw HttpError(400, concat("unreadable JSON: ", e.what()));
    }
}

std::size_t row_count(const json& rows) {
    if (is_packed_matrix(rows)) return rows.get_binary().size() / sizeof(float) / rows.get_binary().subtype();
    return rows.is_array() ? rows.size() : 0;
}

void read_row(const json& row, std::size_t expected, const std::string& what, std::vector<float>& out) {
    const bool packed = is_packed_row(row);
    if (!packed && !row.is_array()) throw HttpError(400, what + " must be an array of numbers");
    const std::size_t size = packed ? row.get_binary().size() / sizeof(float) : row.size();
    if (size != expected) {
        throw HttpError(400, concat(what, " has ", size, " values, the knowledge base expects ", expected));
    }
    if (packed) return append_floats(row.get_binary(), out);
    for (std::size_t k = 0; k < row.size(); ++k) {
        if (!row[k].is_number()) throw HttpError(400, concat(what, "[", k, "] is not a number"));
        const auto f = finite_float(row[k]);
        if (!f) throw HttpError(400, concat(what, "[", k, "] is not finite (as a 32-bit float)"));
        out.push_back(*f);
    }
}

void read_rows(const json& rows, std::size_t width, const std::string& what, std::vector<float>& out) {
    if (is_packed_matrix(rows)) {
        const auto row_width = static_cast<std::size_t>(rows.get_binary().subtype());
        if (row_width != width) {
            throw HttpError(
                400, concat(what, "[0] has ", row_width, " values, the knowledge base expects ", width));
        }
        return append_floats(rows.get_binary(), out);
    }
    for (std::size_t r = 0; r < rows.size(); ++r) read_row(rows[r], width, concat(what, "[", r, "]"), out);
}

}  // namespace stepstone::service
