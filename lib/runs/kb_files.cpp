#include "runs/kb_files.hpp"

#include <vector>

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "runs/kb_duplicates.hpp"

namespace stepstone::runs {

namespace fs = std::filesystem;

namespace {

std::string file_name(const fs::path& path) { return path.string(); }

KbWritten written(const std::string& name, const kb::KnowledgeBase& kb, std::optional<std::uint64_t> seed) {
    return {name, kb.params(), kb.size(), seed, kb.max_average()};
}

// the first parameter in which two KBs differ, named as the config does
std::optional<std::string> params_mismatch(const kb::KbParams& a, const kb::KbParams& b,
                                           const std::string& a_name, const std::string& b_name) {
    if (a.segment_width != b.segment_width) {
        return concat("segment_width is ", b.segment_width, " in ", b_name, ", ", a.segment_width, " in ",
                      a_name);
    }
    if (a.channels != b.channels) {
        return concat("channels is ", b.channels, " in ", b_name, ", ", a.channels, " in ", a_name);
    }
    if (a.delta != b.delta) {
        return concat("delta is ", shortest(b.delta), " in ", b_name, ", ", shortest(a.delta), " in ",
                      a_name);
    }
    return std::nullopt;
}

}  // namespace

void save_kb_file(const fs::path& out, bool force, const std::string& name, const kb::KnowledgeBase& kb,
                  std::optional<std::uint64_t> seed) {
    db::OutputDatabase output(out, force);
    {
        db::Transaction transaction(output.connection());
        db::insert_kb(output.connection(), name, kb, seed);
        transaction.commit();
    }
    output.commit();
}

db::StoredKb load_kb_file(const fs::path& path, const std::string& name) {
    auto connection = db::open_database(path, db::OpenMode::read_only);
    return db::load_kb(connection, name);
}

KbWritten export_kb(const fs::path& run_db, const std::string& name, const fs::path& out, bool force,
                    std::optional<double> delta, const std::string& out_name) {
    db::check_output_path(out, force);
    const auto stored = load_kb_file(run_db, name);
    const std::string written_name = out_name.empty() ? stored.name : out_name;
    if (!delta) {
        save_kb_file(out, force, written_name, stored.kb, stored.randomized_seed);
        return written(written_name, stored.kb, stored.randomized_seed);
    }
    if (stored.randomized_seed) {
        throw DataError(concat(file_name(run_db), ": \"", stored.name,
                               "\" is randomized; coarsen the real KB, then randomize it"));
    }
    const kb::KnowledgeBase coarse = stored.kb.coarsened(*delta);
    save_kb_file(out, force, written_name, coarse, std::nullopt);
    return written(written_name, coarse, std::nullopt);
}

KbWritten merge_kb_files(std::span<const fs::path> inputs, const fs::path& out, const std::string& name,
                         bool force, const std::string& input_name, bool allow_duplicates) {
    if (inputs.size() < 2)
        throw ConfigError(concat("kb merge needs at least two KB files, got ", inputs.size()));
    db::check_output_path(out, force);
    // every input is loaded and checked before the output is created
    std::vector<db::StoredKb> loaded;
    for (const auto& path : inputs) loaded.push_back(load_kb_file(path, input_name));
    const std::string first = file_name(inputs[0]);
    for (std::size_t i = 1; i < loaded.size(); ++i) {
        if (auto mismatch =
                params_mismatch(loaded[0].kb.params(), loaded[i].kb.params(), first, file_name(inputs[i]))) {
            throw DataError(concat("cannot merge ", file_name(inputs[i]), " into ", first, ": ", *mismatch));
        }
    }
    if (!allow_duplicates) refuse_duplicate_kbs(inputs, loaded);
    kb::KnowledgeBase merged = std::move(loaded[0].kb);
    for (std::size_t i = 1; i < loaded.size(); ++i) merged.merge(loaded[i].kb);
    const std::string out_name = name.empty() ? loaded[0].name : name;
    save_kb_file(out, force, out_name, merged, std::nullopt);
    return written(out_name, merged, std::nullopt);
}

KbWritten randomize_kb_file(const fs::path& in, const fs::path& out, std::uint64_t seed,
                            const std::string& name, bool force, const std::string& input_name) {
    db::check_output_path(out, force);
    const auto stored = load_kb_file(in, input_name);
    const kb::KnowledgeBase randomized = stored.kb.randomized(seed);
    const std::string out_name = name.empty() ? stored.name + "-rand" : name;
    save_kb_file(out, force, out_name, randomized, seed);
    return written(out_name, randomized, seed);
}

}  // namespace stepstone::runs
