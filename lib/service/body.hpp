#pragma once

// Request bodies. The service's bodies are mostly rows of numbers (segments,
// behaviour matrices), which a JSON DOM holds in 16 bytes a number plus an
// allocation a row: 13 times the body's size for a behaviour matrix. So rows
// are packed while the body is parsed, and a request's memory stays within a
// few times its body.
//
// Packed forms (JSON binary values, which no client can send, since a body
// is JSON text):
// - a row: an array whose elements are all numbers finite as float32 becomes
//   a binary value of their float32 bytes, without subtype;
// - a matrix: an array whose elements are all packed rows of one length
//   becomes one binary value of every row's bytes, its subtype the row length.
// Anything else (a string in a row, rows of unequal length, 1e300) is left as
// parsed, for the readers below to name in their errors.

#include <cstddef>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

namespace stepstone::service {

/// Arrays and objects nest at most this deep in a body.
inline constexpr std::size_t kMaxDepth = 64;
/// The DOM of a body of B bytes may take about kDomPerBodyByte * B + kDomSlack bytes (dom_budget):
/// rows of numbers take 4 bytes a number (at least 2 bytes of text), other values more (a value
/// 32 bytes or so, a string or an object's member about 130 plus its text).
inline constexpr std::size_t kDomPerBodyByte = 3;
inline constexpr std::size_t kDomSlack = std::size_t{1} << 20;
std::size_t dom_budget(std::size_t body_bytes);

/// Parses a body with its rows packed, as a stream of SAX events: nothing but
/// the packed DOM is built. Throws HttpError(400) for JSON that is malformed,
/// holds a number beyond double's range or nests deeper than kMaxDepth (as
/// soon as the parser reaches that depth), and HttpError(413) as soon as the
/// DOM would take more than dom_budget(body.size()).
nlohmann::json parse_body(const std::string& body);

/// How many rows `rows` has: a packed matrix's, or the array's size. 0 for anything else.
std::size_t row_count(const nlohmann::json& rows);

/// Appends a row of `expected` numbers, packed or not, to `out`; `what` names
/// it in errors (HttpError 400: not an array, wrong length, not a number, not
/// finite as float32).
void read_row(const nlohmann::json& row, std::size_t expected, const std::string& what,
              std::vector<float>& out);

/// Appends every row of `rows` (a matrix, packed or not), each of `width`
/// numbers; errors name row k as what[k].
void read_rows(const nlohmann::json& rows, std::size_t width, const std::string& what,
               std::vector<float>& out);

/// The numbers of `rows`, checked as read_rows does: a packed matrix is seen
/// where it lies (no copy: valid while `rows` is), anything else is read into
/// `storage` (cleared first) and seen there.
std::span<const float> rows_view(const nlohmann::json& rows, std::size_t width, const std::string& what,
                                 std::vector<float>& storage);

}  // namespace stepstone::service
