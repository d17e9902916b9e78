#include "runs.hpp"

#include <algorithm>
#include <regex>
#include <stdexcept>

#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace stepstone::reporttest {

namespace fs = std::filesystem;

namespace {

constexpr const char* kSourceConfig = R"({
  "task": {"kind": "source", "steps_per_start": 200, "starts": 1},
  "ea": {"population_size": 8, "generations": 4},
  "kb": {"segment_width": 10, "delta": 1.0, "period": 1},
  "seed": 5
})";

void run(const std::vector<std::string>& args) {
    const auto result = test::run_cli(args);
    if (result.exit_code != 0) throw std::runtime_error(args[0] + " failed: " + result.err);
}

}  // namespace

void make_run(const fs::path& path, bool retain_all) {
    const auto config = path.parent_path() / (path.stem().string() + ".json");
    test::write_file(config, kSourceConfig);
    std::vector<std::string> args{"evolve", "--config", config.string(), "--db", path.string(), "--threads", "1",
                                  "--quiet"};
    if (retain_all) args.insert(args.end(), {"--retain", "all"});
    run(args);
}

void make_campaign(const fs::path& dir) {
    const auto config = dir.parent_path() / (dir.filename().string() + ".json");
    test::write_file(config, std::string(R"({
  "source": {"config": )") + kSourceConfig + R"(, "seeds": [1], "generations": 3},
  "kb": {"from": "best"},
  "randomize_seed": 1,
  "target": {
    "config": {"task": {"kind": "target", "steps_per_start": 200, "starts": 1}, "ea": {"population_size": 8}},
    "seeds": [1, 2],
    "generations": 2,
    "treatments": ["none", "sum", "sum-rand"]
  }
})");
    run({"campaign", config.string(), "--dir", dir.string(), "--jobs", "2", "--threads", "1"});
}

std::vector<std::string> references(const std::string& html) {
    static const std::regex attribute(R"re((?:src|data|href)="([^"]*)")re");
    std::vector<std::string> out;
    for (auto it = std::sregex_iterator(html.begin(), html.end(), attribute); it != std::sregex_iterator(); ++it) {
        out.push_back((*it)[1].str());
    }
    return out;
}

std::vector<std::string> entries(const fs::path& dir) {
    std::vector<std::string> out;
    if (!fs::exists(dir)) return out;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const auto name = entry.path().filename().string();
        if (!name.ends_with("-wal") && !name.ends_with("-shm")) out.push_back(name);
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace stepstone::reporttest
