#include "support/campaigns.hpp"

#include <chrono>
#include <memory>
#include <stdexcept>
#include <thread>

#include "db/database.hpp"

namespace stepstone::test {

std::string tiny_campaign_json(int target_generations, int steps) {
    return R"({
  "source": {
    "config": {
      "task": {"kind": "source", "steps_per_start": 200, "starts": 1},
      "ea": {"population_size": 8},
      "kb": {"segment_width": 20, "delta": 1.83, "period": 1}
    },
    "seeds": [4],
    "generations": 3
  },
  "kb": {"from": "best"},
  "randomize_seed": 9,
  "target": {
    "config": {"task": {"kind": "target", "steps_per_start": )" +
           std::to_string(steps) + R"(, "starts": 1}, "ea": {"population_size": 8}},
    "runs": 2,
    "generations": )" +
           std::to_string(target_generations) + R"(
  }
})";
}

CliResult run_campaign(const TempDir& dir, const std::string& name, const std::vector<std::string>& extra) {
    std::vector<std::string> args{"campaign", (dir / "c.json").string(), "--dir", (dir / name).string(),
                                  "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_cli(args);
}

void copy_tiny_campaign(const std::filesystem::path& to, int target_generations) {
    // one finished campaign per config for the life of the test process (its folder is
    // removed at exit with the TempDir)
    static std::map<int, std::unique_ptr<TempDir>> finished;
    auto& dir = finished[target_generations];
    if (!dir) {
        auto made = std::make_unique<TempDir>();
        write_file(*made / "c.json", tiny_campaign_json(target_generations));
        const auto result = run_campaign(*made, "camp", {"--jobs", "2"});
        if (result.exit_code != 0) throw std::runtime_error("the tiny campaign failed: " + result.err);
        dir = std::move(made);
    }
    std::filesystem::copy(*dir / "camp", to, std::filesystem::copy_options::recursive);
}

std::map<std::int64_t, std::string> finished_digests(const std::filesystem::path& dir) {
    auto connection = db::open_database(dir / "campaign.db", db::OpenMode::read_only);
    auto rows =
        connection.prepare("SELECT id, digest FROM campaign_run WHERE status = 'finished' ORDER BY id");
    std::map<std::int64_t, std::string> out;
    while (rows.step()) out[rows.column_int(0)] = rows.column_text(1);
    return out;
}

namespace {

// the count, or the error of a file that cannot be read
std::int64_t count_finished(const std::filesystem::path& dir) {
    auto connection = db::open_database(dir / "campaign.db", db::OpenMode::read_only);
    return connection.query_int("SELECT count(*) FROM campaign_run WHERE status = 'finished'").value_or(0);
}

}  // namespace

std::int64_t finished_runs(const std::filesystem::path& dir) {
    try {
        return count_finished(dir);
    } catch (const std::exception&) {
        return 0;
    }
}

std::int64_t finished_runs_after_exit(const std::filesystem::path& dir) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (true) {
        try {
            return count_finished(dir);
        } catch (const std::exception&) {
            if (std::chrono::steady_clock::now() >= deadline) throw;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
    }
}

}  // namespace stepstone::test
