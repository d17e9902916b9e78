// Request bodies: rows of numbers packed while parsing read back as the
// numbers a JSON DOM holds, and what cannot be packed is left for the errors.

#include "service/body.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "service/service.hpp"

using namespace stepstone::service;
using nlohmann::json;

namespace {

std::vector<float> rows_of(const json& rows, std::size_t width) {
    std::vector<float> out;
    read_rows(rows, width, "rows", out);
    return out;
}

std::string error_of(const json& rows, std::size_t width) {
    try {
        rows_of(rows, width);
    } catch (const HttpError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("rows of numbers are packed as float32 and read back as the unpacked DOM's values", "[service]") {
    const std::string text =
        R"({"m": [[0.1, 2, -3.5e-3], [1e30, 0, -0.0]], "uneven": [[1, 2], [3]], "mixed": [[1, "a"]]})";
    const json packed = parse_body(text);
    const json plain = json::parse(text);
    REQUIRE(packed["m"].is_binary());
    CHECK(packed["m"].get_binary().subtype() == 3);
    CHECK(row_count(packed["m"]) == 2);
    const auto values = rows_of(packed["m"], 3);
    // what a float32 cast of each parsed double gives, by hand from the text
    const std::vector<float> expected = {0.1f, 2.0f, -3.5e-3f, 1e30f, 0.0f, -0.0f};
    REQUIRE(values == expected);
    CHECK(std::signbit(values[5]));
    CHECK(rows_of(plain["m"], 3) == expected);
    // rows of unequal length: each row packed, the matrix not
    REQUIRE(packed["uneven"].is_array());
    CHECK(packed["uneven"][0].is_binary());
    CHECK(row_count(packed["uneven"]) == 2);
    CHECK(error_of(packed["uneven"], 2) == "rows[1] has 1 values, the knowledge base expects 2");
    // a string in a row: left as parsed, named in the error
    CHECK(packed["mixed"][0].is_array());
    CHECK(error_of(packed["mixed"], 2) == "rows[0][1] is not a number");
    CHECK(error_of(packed["m"], 4) == "rows[0] has 3 values, the knowledge base expects 4");
}

TEST_CASE("a number beyond float32's range is refused, not read as infinity", "[service]") {
    const json body = parse_body(R"({"m": [[1, 1e300]]})");
    REQUIRE(body["m"][0].is_array());  // not packed
    CHECK(error_of(body["m"], 2) == "rows[0][1] is not finite (as a 32-bit float)");
    CHECK_THROWS_AS(parse_body(R"({"m": [[1e400]]})"), HttpError);
    CHECK_THROWS_AS(parse_body(R"({"m": [[1, 2)"), HttpError);
}

TEST_CASE("a body nested deeper than the limit is refused at the limit, naming it", "[service]") {
    const auto nested = [](std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); };
    CHECK(parse_body(nested(kMaxDepth)).is_array());
    const auto error_at = [](const std::string& body) {
        try {
            parse_body(body);
        } catch (const HttpError& e) {
            return std::to_string(e.status()) + " " + e.what();
        }
        return std::string();
    };
    CHECK(error_at(nested(kMaxDepth + 1)) == "400 the body nests arrays and objects deeper than 64 levels");
    // refused at the 65th level, whatever follows (not even closed, here)
    CHECK(error_at("{\"a\": " + std::string(10 * 1000 * 1000, '[')) ==
          "400 the body nests arrays and objects deeper than 64 levels");
    std::string objects(40, '[');
    for (int i = 0; i < 40; ++i) objects += "{\"a\": ";
    CHECK(error_at(objects) == "400 the body nests arrays and objects deeper than 64 levels");
}

TEST_CASE("a body whose DOM would outgrow three times its size is refused, rows of numbers are not",
          "[service]") {
    // empty arrays: a JSON value each for 3 bytes of text
    std::string empties = "{\"segments\": [[]";
    for (int i = 0; i < 200000; ++i) empties += ",[]";
    empties += "]}";
    try {
        parse_body(empties);
        FAIL("parsed");
    } catch (const HttpError& e) {
        CHECK(e.status() == 413);
        CHECK(std::string(e.what()).rfind("the body's JSON would take more than " +
                                              std::to_string(dom_budget(empties.size())) + " bytes in memory",
                                          0) == 0);
    }
    // the densest rows of numbers: one digit a number, 4 bytes as float32 for 2 of text
    std::string dense = "{\"segments\": [[0";
    for (int i = 1; i < 15; ++i) dense += ",0";
    dense += "]";
    const std::string row = dense.substr(14);
    while (dense.size() < 4 * 1000 * 1000) dense += "," + row;
    dense += "]}";
    const auto packed = parse_body(dense);
    REQUIRE(packed["segments"].is_binary());
    CHECK(row_count(packed["segments"]) > 100000);
}
