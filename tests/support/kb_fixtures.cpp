#include "support/kb_fixtures.hpp"

#include <algorithm>
#include <stdexcept>

#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace stepstone::kbtest {

void make_run(const std::filesystem::path& path, bool retain_all) {
    const auto config = path.parent_path() / (path.stem().string() + ".json");
    test::write_file(config, R"({
  "task": {"kind": "source", "steps_per_start": 200, "starts": 1},
  "ea": {"population_size": 8, "generations": 3},
  "kb": {"segment_width": 10, "delta": 1.0, "period": 1},
  "seed": 3
})");
    std::vector<std::string> args{"evolve",    "--config", config.string(), "--db", path.string(),
                                  "--threads", "1",        "--quiet"};
    if (retain_all) {
        args.push_back("--retain");
        args.push_back("all");
    }
    const auto result = test::run_cli(args);
    if (result.exit_code != 0) throw std::runtime_error("evolve failed: " + result.err);
}

void write_kb(const std::filesystem::path& path, const std::string& name, const kb::KnowledgeBase& kb,
              std::optional<std::uint64_t> randomized_seed) {
    auto connection = db::open_database(path, db::OpenMode::create);
    db::Transaction transaction(connection);
    db::insert_kb(connection, name, kb, randomized_seed);
    transaction.commit();
}

kb::KnowledgeBase load_kb(const std::filesystem::path& path, const std::string& name) {
    auto connection = db::open_database(path, db::OpenMode::read_only);
    return db::load_kb(connection, name).kb;
}

kb::KnowledgeBase point_kb(const std::string& run, const std::vector<Policy>& policies, double delta,
                           std::size_t channels) {
    kb::KbParams params;
    params.segment_width = 1;
    params.channels = channels;
    params.delta = delta;
    kb::KnowledgeBase base(params);
    const auto source = base.add_source(run);
    for (const auto& policy : policies) {
        std::vector<float> values(channels, 0.0f);
        values[0] = policy.x;
        if (channels > 1) values[1] = policy.y;
        base.observe(kb::as_segments(values, channels), policy.reward, {source, policy.generation});
    }
    return base;
}

// eight 1-value segments with chosen averages and counts (cum_reward = average x count)
// and two sources; first origins: ids 0-2 alpha gen 0, ids 3-5 alpha gen 3, ids 6-7 beta gen 5
kb::KnowledgeBase histogram_kb() {
    kb::KbParams params;
    params.segment_width = 1;
    params.channels = 1;
    params.delta = 0.5;
    const std::vector<double> averages{0, 0, 0, 0.15, 0.55, 0.55, 0.95, 1.0};
    const std::vector<std::uint64_t> counts{1, 2, 3, 1, 4, 1, 1, 2};
    std::vector<float> values;
    std::vector<kb::SegmentRecord> records;
    for (std::size_t i = 0; i < averages.size(); ++i) {
        values.push_back(static_cast<float>(i));  // 1 apart: all distinct under delta 0.5
        kb::SegmentRecord record;
        record.cum_reward = averages[i] * static_cast<double>(counts[i]);
        record.count = counts[i];
        const std::uint32_t source = i < 6 ? 0 : 1;
        const std::int64_t generation = i < 3 ? 0 : (i < 6 ? 3 : 5);
        record.first = {source, generation};
        record.last = {i == 0 ? 1u : source, i == 0 ? 7 : generation};  // segment 0 last credited by beta
        records.push_back(record);
    }
    std::vector<kb::Source> sources{{"alpha", 0, 10, 30}, {"beta", 5, 7, 4}};
    return kb::KnowledgeBase::from_segments(params, sources, values, records);
}

std::vector<std::string> segment_rows(const std::filesystem::path& path) {
    auto connection = db::open_database(path, db::OpenMode::read_only);
    auto select = connection.prepare(
        "SELECT id || '|' || cum_reward || '|' || count || '|' || first_source || '|' || first_generation || "
        "'|' || "
        "last_source || '|' || last_generation || '|' || hex(segment_values) FROM kb_segment ORDER BY kb_id, "
        "id");
    std::vector<std::string> rows;
    while (select.step()) rows.push_back(select.column_text(0));
    return rows;
}

std::vector<std::string> files_in(const std::filesystem::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        const auto ends_with = [&](const std::string& suffix) {
            return name.size() > suffix.size() &&
                   name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
        };
        if (!ends_with("-wal") && !ends_with("-shm")) names.push_back(name);
    }
    std::sort(names.begin(), names.end());
    return names;
}

}  // namespace stepstone::kbtest
