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
#include <string>
#include <vector>

namespace stepstone::service {

/// Parses a body with its rows packed. Throws HttpError(400) for JSON that is
/// malformed or holds a number beyond double's range.
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

}  // namespace stepstone::service
