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

// What the DOM of a body may take, roughly, in bytes: a number in a row (float32), and the JSON
// values that are not rows of numbers (a value in an array, an object's member, a string, an
// array or object itself)
constexpr std::size_t kFloatCost = sizeof(float);
constexpr std::size_t kSlotCost = 32;
constexpr std::size_t kMemberCost = 128;
constexpr std::size_t kStringCost = 96;
constexpr std::size_t kNodeCost = 80;
constexpr std::size_t kPackedCost = 48;  // a packed row's or matrix's container, beside its bytes
// a body this large reserves its matrices' room (pages the system gives only once written)
constexpr std::size_t kReserveFrom = std::size_t{1} << 20;

void append_bytes(json::binary_t::container_type& out, const std::vector<float>& floats) {
    const std::size_t start = out.size();
    out.resize(start + floats.size() * sizeof(float));
    std::memcpy(out.data() + start, floats.data(), floats.size() * sizeof(float));
}

// nlohmann::json's SAX events built into a DOM whose rows of numbers are packed as they end
// (body.hpp), refusing a body that nests too deep (400) or whose DOM would outgrow its budget
// (413) as soon as the parser reaches that point
class Builder {
public:
    Builder(std::size_t body_bytes, std::size_t budget) : body_bytes_(body_bytes), budget_(budget) {}

    json take() { return std::move(root_); }

    bool null() { return add(json(nullptr)); }
    bool boolean(bool value) { return add(json(value)); }
    bool number_integer(json::number_integer_t value) {
        return number(json(value), static_cast<double>(value));
    }
    bool number_unsigned(json::number_unsigned_t value) {
        return number(json(value), static_cast<double>(value));
    }
    bool number_float(json::number_float_t value, const std::string&) { return number(json(value), value); }
    bool string(std::string& value) {
        charge(kStringCost + value.size());
        return add(json(std::move(value)));
    }
    bool binary(json::binary_t& value) {
        charge(kNodeCost + value.size());
        return add(json(std::move(value)));
    }
    bool start_object(std::size_t) { return open(true); }
    bool key(std::string& name) {
        charge(kMemberCost + name.size());
        stack_.back().key = std::move(name);
        return true;
    }
    bool end_object() {
        Frame frame = std::move(stack_.back());
        stack_.pop_back();
        charge(kNodeCost);
        return add(std::move(frame.value));
    }
    bool start_array(std::size_t) { return open(false); }
    bool end_array() {
        Frame frame = std::move(stack_.back());
        stack_.pop_back();
        switch (frame.mode) {
            case Mode::empty:
                charge(kNodeCost);
                return add(json::array());
            case Mode::row: {
                // a row: into its parent's matrix if the parent is one (or may become one)
                if (!stack_.empty() && !stack_.back().object) {
                    Frame& parent = stack_.back();
                    if (parent.mode == Mode::empty ||
                        (parent.mode == Mode::matrix && parent.width == frame.row.size())) {
                        // a matrix's first row: room for every number the body may still hold (two
                        // bytes of text a number), taken from the system as it is written, so that
                        // the matrix grows without copies
                        if (parent.mode == Mode::empty && body_bytes_ >= kReserveFrom) {
                            parent.matrix.reserve(std::min(2 * body_bytes_, budget_ - used_));
                        }
                        parent.mode = Mode::matrix;
                        parent.width = frame.row.size();
                        append_bytes(parent.matrix, frame.row);
                        return true;
                    }
                }
                json::binary_t::container_type bytes;
                append_bytes(bytes, frame.row);
                charge(kNodeCost + kPackedCost);
                return add(json::binary(std::move(bytes)));
            }
            case Mode::matrix:
                charge(kNodeCost + kPackedCost);
                return add(json::binary(std::move(frame.matrix), frame.width));
            case Mode::generic:
                break;
        }
        charge(kNodeCost);
        return add(std::move(frame.value));
    }
    bool parse_error(std::size_t, const std::string&, const json::exception& error) {
        if (dynamic_cast<const json::parse_error*>(&error))
            throw HttpError(400, concat("malformed JSON: ", error.what()));
        // a number beyond double's range (1e400) and the like
        throw HttpError(400, concat("unreadable JSON: ", error.what()));
    }

private:
    // an array is empty, a row (numbers finite as float32 so far), a matrix (rows of one width so
    // far, packed), or anything else (generic: a JSON array)
    enum class Mode { empty, row, matrix, generic };
    struct Frame {
        bool object = false;
        json value;
        std::string key;
        Mode mode = Mode::empty;
        std::vector<float> row;
        json::binary_t::container_type matrix;
        std::size_t width = 0;
    };

    bool open(bool object) {
        if (stack_.size() >= kMaxDepth) {
            throw HttpError(400,
                            concat("the body nests arrays and objects deeper than ", kMaxDepth, " levels"));
        }
        Frame frame;
        frame.object = object;
        frame.value = object ? json::object() : json::array();
        frame.mode = object ? Mode::generic : Mode::empty;
        stack_.push_back(std::move(frame));
        return true;
    }

    bool number(json value, double d) {
        if (!stack_.empty() && (stack_.back().mode == Mode::empty || stack_.back().mode == Mode::row)) {
            Frame& frame = stack_.back();
            const auto f = static_cast<float>(d);
            if (!frame.object && std::isfinite(d) && std::isfinite(f)) {
                charge(kFloatCost);
                frame.mode = Mode::row;
                frame.row.push_back(f);
                return true;
            }
        }
        return add(std::move(value));
    }

    bool add(json value) {
        if (stack_.empty()) {
            root_ = std::move(value);
            return true;
        }
        Frame& frame = stack_.back();
        if (frame.object) {
            frame.value[frame.key] = std::move(value);
            return true;
        }
        unpack(frame);
        charge(kSlotCost);
        frame.value.push_back(std::move(value));
        return true;
    }

    // an array that turns out to be neither a row nor a matrix: what was packed becomes JSON
    // values again (a row's numbers as their float32 values; a matrix's rows as packed rows)
    void unpack(Frame& frame) {
        if (frame.mode == Mode::row) {
            for (const float f : frame.row) {
                charge(kSlotCost);
                frame.value.push_back(static_cast<double>(f));
            }
            std::vector<float>().swap(frame.row);
        } else if (frame.mode == Mode::matrix) {
            const std::size_t row_bytes = frame.width * sizeof(float);
            for (std::size_t at = 0; at < frame.matrix.size(); at += row_bytes) {
                charge(kNodeCost + kPackedCost + kSlotCost);
                frame.value.push_back(json::binary(json::binary_t::container_type(
                    frame.matrix.begin() + static_cast<std::ptrdiff_t>(at),
                    frame.matrix.begin() + static_cast<std::ptrdiff_t>(at + row_bytes))));
            }
            json::binary_t::container_type().swap(frame.matrix);
        }
        frame.mode = Mode::generic;
    }

    void charge(std::size_t bytes) {
        used_ += bytes;
        if (used_ > budget_) {
            throw HttpError(413, concat("the body's JSON would take more than ", budget_,
                                        " bytes in memory (rows of numbers take about their text's size; "
                                        "other values more)"));
        }
    }

    std::size_t body_bytes_, budget_, used_ = 0;
    std::vector<Frame> stack_;
    json root_;
};

void append_floats(const json::binary_t& bytes, std::vector<float>& out) {
    const std::size_t start = out.size();
    out.resize(start + bytes.size() / sizeof(float));
    std::memcpy(out.data() + start, bytes.data(), bytes.size());
}

}  // namespace

json parse_body(const std::string& body) {
    Builder builder(body.size(), dom_budget(body.size()));
    json::sax_parse(body, &builder);
    return builder.take();
}

std::size_t dom_budget(std::size_t body_bytes) { return kDomPerBodyByte * body_bytes + kDomSlack; }

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

namespace stepstone::service {

std::span<const float> rows_view(const json& rows, std::size_t width, const std::string& what,
                                 std::vector<float>& storage) {
    storage.clear();
    if (!is_packed_matrix(rows)) {
        read_rows(rows, width, what, storage);
        return storage;
    }
    const auto& bytes = rows.get_binary();
    if (static_cast<std::size_t>(bytes.subtype()) != width) {
        throw HttpError(
            400, concat(what, "[0] has ", bytes.subtype(), " values, the knowledge base expects ", width));
    }
    // float32 values memcpy'd into the binary's bytes (std::vector storage: aligned for any scalar)
    return {reinterpret_cast<const float*>(bytes.data()), bytes.size() / sizeof(float)};
}

}  // namespace stepstone::service
