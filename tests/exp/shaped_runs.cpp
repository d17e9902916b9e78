#include "exp/shaped_runs.hpp"

#include "db/database.hpp"
#include "db/kb_store.hpp"

namespace stepstone::exptest {

kb::KnowledgeBase two_segment_kb(double near, double far, kb::Match match, std::size_t channels,
                                 std::size_t width) {
    kb::KbParams params;
    params.segment_width = width;
    params.channels = channels;
    params.delta = 1.0;
    params.match = match;
    kb::KnowledgeBase base(params);
    const auto source = base.add_source("hand");
    const std::vector<float> zeros(params.dim(), 0.0f);
    const std::vector<float> fives(params.dim(), 5.0f);
    base.observe(kb::as_segments(zeros, params.dim()), near, {source, 0});
    base.observe(kb::as_segments(fives, params.dim()), far, {source, 0});
    return base;
}

void write_kb(const std::filesystem::path& path, const kb::KnowledgeBase& kb,
              std::optional<std::uint64_t> randomized_seed) {
    auto connection = db::open_database(path, db::OpenMode::create);
    db::Transaction transaction(connection);
    db::insert_kb(connection, "hand", kb, randomized_seed);
    transaction.commit();
}

test::CliResult evolve(const test::TempDir& dir, const std::string& db,
                       const std::vector<std::string>& extra) {
    std::vector<std::string> args{
        "evolve", "--config", (dir / "t.json").string(), "--db", (dir / db).string(), "--threads",
        "2",      "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_cli(args);
}

}  // namespace stepstone::exptest
