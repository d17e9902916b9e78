#include "runs/run_series.hpp"

#include "db/database.hpp"

namespace stepstone::runs {

std::vector<GenerationPoint> load_generations(db::Connection& connection, std::int64_t run_id) {
    auto rows = connection.prepare(db::sql("run/select_generation_series.sql"));
    rows.bind(":run_id", run_id);
    std::vector<GenerationPoint> out;
    while (rows.step()) {
        GenerationPoint p;
        p.generation = static_cast<int>(rows.column_int(0));
        p.best = rows.column_double(1);
        p.median = rows.column_double(2);
        if (!rows.is_null(4)) p.mean_r_max = rows.column_double(4);
        if (!rows.is_null(5)) p.max_r_max = rows.column_double(5);
        out.push_back(p);
    }
    return out;
}

double MilestoneCounts::share(std::size_t m) const {
    return policies > 0 ? static_cast<double>(reached[m]) / static_cast<double>(policies) : 0.0;
}

std::vector<MilestoneCounts> load_milestone_counts(db::Connection& connection, std::int64_t run_id) {
    auto rows = connection.prepare(db::sql("run/select_milestone_counts.sql"));
    rows.bind(":run_id", run_id);
    std::vector<MilestoneCounts> out;
    while (rows.step()) {
        MilestoneCounts c;
        c.generation = static_cast<int>(rows.column_int(0));
        c.policies = rows.column_int(1);
        for (std::size_t m = 0; m < kMilestones; ++m) c.reached[m] = rows.column_int(static_cast<int>(m) + 2);
        out.push_back(c);
    }
    return out;
}

}  // namespace stepstone::runs
