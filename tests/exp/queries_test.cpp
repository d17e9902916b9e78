#include <catch2/catch.hpp>

#include "core/embedded.hpp"
#include "db/database.hpp"
#include "exp/evolution.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;

TEST_CASE("generation_times.sql sums the phases of a real run", "[exp][queries]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", R"({"task": {"steps_per_start": 200, "starts": 1},
                                          "ea": {"population_size": 8, "generations": 3}, "seed": 2})");
    exp::EvolveOptions options;
    options.config_path = dir / "c.json";
    options.db_path = dir / "run.db";
    options.progress = ProgressMode::quiet;
    exp::run_evolve(options);

    std::string_view text;
    for (const auto& file : query_files()) {
        if (file.path == "generation_times.sql") text = file.text;
    }
    REQUIRE(!text.empty());
    auto connection = db::open_database(dir / "run.db", db::OpenMode::read_only);
    auto query = connection.prepare(text);
    REQUIRE(query.step());
    // generations 1 to 3, 8 children each; the phases fit inside the wall time
    CHECK(query.column_int(1) == 3);
    const double phases = query.column_double(3) + query.column_double(4) + query.column_double(5) +
                          query.column_double(6) + query.column_double(7);
    CHECK(phases <= query.column_double(8) * 1.000001);
    CHECK(query.column_double(2) > 0);
    CHECK(!query.step());
}
