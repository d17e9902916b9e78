#include <catch2/catch.hpp>

#include <cstdio>
#include <string>

#include "core/progress.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

std::string drain(std::FILE* file) {
    std::rewind(file);
    std::string text;
    char buffer[256];
    while (std::fgets(buffer, sizeof buffer, file)) text += buffer;
    return text;
}

}  // namespace

TEST_CASE("format_duration picks hours, minutes or seconds", "[core][progress]") {
    CHECK(format_duration(12) == "12s");
    CHECK(format_duration(185) == "3m05s");
    CHECK(format_duration(3720) == "1h02m");
}

TEST_CASE("plain lines show done/total, a rate, an ETA and the status", "[core][progress]") {
    std::FILE* file = std::tmpfile();
    {
        Progress progress("generation", 10, ProgressMode::lines, file);
        progress.set_line_interval(std::chrono::milliseconds(0));
        progress.update(0);
        progress.update(3, "best 0.25");
        progress.finish("best 0.5");
    }
    const std::string text = drain(file);
    std::fclose(file);
    CHECK_THAT(text, Contains("generation 3/10"));
    CHECK_THAT(text, Contains("/s"));
    CHECK_THAT(text, Contains("best 0.25"));
    CHECK_THAT(text, Contains("best 0.5"));
    CHECK(text.find('\r') == std::string::npos);
}

TEST_CASE("quiet mode prints nothing", "[core][progress]") {
    std::FILE* file = std::tmpfile();
    {
        Progress progress("generation", 10, ProgressMode::quiet, file);
        progress.update(5);
        progress.finish();
    }
    CHECK(drain(file).empty());
    std::fclose(file);
}
