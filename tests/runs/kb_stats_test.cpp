// The figures of `kb stats` (lib/runs/kb_stats.cpp) on hand-made KBs, worked
// out by hand: the average-reward histogram, the counts, and the file's size
// per segment. The command's output: tests/cli/kb/randomize_stats_test.cpp.
#include "runs/kb_stats.hpp"

#include <catch2/catch.hpp>

#include "support/kb_fixtures.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;

namespace {

// width-1, 1-channel segments 0, 1, 2, ... (1 apart, distinct under delta
// 0.5) with the given averages and counts, all from one source
kb::KnowledgeBase averages_kb(const std::vector<double>& averages, const std::vector<std::uint64_t>& counts) {
    kb::KbParams params;
    params.segment_width = 1;
    params.channels = 1;
    params.delta = 0.5;
    std::vector<float> values;
    std::vector<kb::SegmentRecord> records;
    for (std::size_t i = 0; i < averages.size(); ++i) {
        values.push_back(static_cast<float>(i));
        kb::SegmentRecord record;
        record.count = counts[i];
        record.cum_reward = averages[i] * static_cast<double>(counts[i]);
        record.first = record.last = {0, 0};
        records.push_back(record);
    }
    return kb::KnowledgeBase::from_segments(params, {{"hand", 0, 0, 9}}, values, records);
}

}  // namespace

TEST_CASE("kb stats of a hand-made KB: its size, histogram bins and counts by hand", "[runs][kb][stats]") {
    // averages 0, 0.1, 0.35, 0.35, 0.8 seen 2, 1, 1, 3, 1 times
    const auto base = averages_kb({0.0, 0.1, 0.35, 0.35, 0.8}, {2, 1, 1, 3, 1});
    const auto stats = runs::compute_kb_stats(base, 4);
    CHECK(stats.segments == 5);
    CHECK(stats.max_average == Approx(0.8));
    // 4 bins of 0.2 over [0, 0.8]: 0 and 0.1 -> bin 0; 0.35 twice -> bin 1; none in bin 2; the
    // maximum 0.8 closes the last bin
    REQUIRE(stats.histogram.size() == 4);
    const std::vector<std::size_t> segments{2, 2, 0, 1};
    for (std::size_t b = 0; b < 4; ++b) {
        INFO("bin " << b);
        CHECK(stats.histogram[b].low == Approx(0.2 * static_cast<double>(b)));
        CHECK(stats.histogram[b].high == Approx(0.2 * static_cast<double>(b + 1)));
        CHECK(stats.histogram[b].segments == segments[b]);
    }
    // counts 2 1 1 3 1: 8 observations, sorted 1 1 1 2 3
    CHECK(stats.observations == 8);
    CHECK(stats.count_min == 1);
    CHECK(stats.count_max == 3);
    CHECK(stats.count_mean == 1.6);
    CHECK(stats.count_median == 1.0);
    CHECK(stats.count_one == 3);
    REQUIRE(stats.sources.size() == 1);
    CHECK(stats.sources[0].run == "hand");

    // every average 0: the bins cover [0, 1] and every segment falls in the first
    const auto zeros = runs::compute_kb_stats(averages_kb({0.0, 0.0, 0.0}, {1, 4, 1}));
    REQUIRE(zeros.histogram.size() == 10);
    CHECK(zeros.histogram.back().high == 1.0);
    CHECK(zeros.histogram[0].segments == 3);
    CHECK(zeros.count_median == 1.0);
    CHECK(zeros.count_one == 2);
}

TEST_CASE("kb stats of a KB file names it and divides the file's size by its segments", "[runs][kb][stats]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "h.db", "hand", averages_kb({0.25, 0.5}, {1, 2}), 7);
    const auto stats = runs::kb_file_stats(dir / "h.db");
    CHECK(stats.file == (dir / "h.db").string());
    CHECK(stats.name == "hand");
    CHECK(stats.randomized_seed == std::optional<std::uint64_t>(7));
    CHECK(stats.segments == 2);
    CHECK(stats.file_bytes_per_segment == static_cast<double>(std::filesystem::file_size(dir / "h.db")) / 2);
}
