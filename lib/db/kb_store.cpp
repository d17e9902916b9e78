#include "db/kb_store.hpp"

#include <cmath>
#include <cstring>

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/segment_codec.hpp"

namespace stepstone::db {

namespace {

// the schema version that added kb.counting (schema/0007_kb_counting.sql)
constexpr int kFirstVersionWithCounting = 7;

void write_sources(Connection& connection, std::int64_t kb_id, const kb::KnowledgeBase& kb) {
    auto upsert = connection.prepare(sql("kb/upsert_source.sql"));
    const auto sources = kb.sources();
    for (std::size_t i = 0; i < sources.size(); ++i) {
        upsert.reset();
        upsert.bind(":kb_id", kb_id)
            .bind(":source", static_cast<std::int64_t>(i))
            .bind(":run", sources[i].run)
            .bind(":first_generation", sources[i].first_generation)
            .bind(":last_generation", sources[i].last_generation)
            .bind(":policies", static_cast<std::int64_t>(sources[i].policies))
            .run();
    }
}

void write_segment(Statement& upsert, std::int64_t kb_id, const kb::KnowledgeBase& kb, std::size_t id) {
    const auto& record = kb.record(id);
    const auto& params = kb.params();
    const std::vector<std::byte> stored = pack_segment(kb.segment(id), params.segment_width, params.channels);
    upsert.reset();
    upsert.bind(":kb_id", kb_id)
        .bind(":id", static_cast<std::int64_t>(id))
        .bind(":cum_reward", record.cum_reward)
        .bind(":count", static_cast<std::int64_t>(record.count))
        .bind(":first_source", static_cast<std::int64_t>(record.first.source))
        .bind(":first_generation", record.first.generation)
        .bind(":last_source", static_cast<std::int64_t>(record.last.source))
        .bind(":last_generation", record.last.generation)
        .bind_blob(":segment_values", stored)
        .run();
}

}  // namespace

const char* to_string(kb::Match match) { return match == kb::Match::nearest ? "nearest" : "within_delta"; }

kb::Match parse_match(const std::string& text, const std::string& what) {
    if (text == "within_delta") return kb::Match::within_delta;
    if (text == "nearest") return kb::Match::nearest;
    throw ConfigError(concat(what, " must be one of within_delta|nearest, got \"", text, '"'));
}

std::int64_t insert_kb(Connection& connection, const std::string& name, const kb::KnowledgeBase& kb,
                       std::optional<std::uint64_t> randomized_seed) {
    const auto& params = kb.params();
    auto insert = connection.prepare(sql("kb/insert_kb.sql"));
    std::optional<std::int64_t> seed;
    if (randomized_seed) seed = static_cast<std::int64_t>(*randomized_seed);
    insert.bind(":name", name)
        .bind(":segment_width", static_cast<std::int64_t>(params.segment_width))
        .bind(":channels", static_cast<std::int64_t>(params.channels))
        .bind(":delta", params.delta)
        .bind(":match", to_string(params.match))
        .bind(":counting", kb::to_string(params.counting))
        .bind(":randomized_seed", seed)
        .run();
    const std::int64_t kb_id = connection.last_insert_rowid();
    update_kb(connection, kb_id, kb, 0, 0);
    return kb_id;
}

void update_kb(Connection& connection, std::int64_t kb_id, const kb::KnowledgeBase& kb, std::size_t previous_size,
               std::int64_t generation) {
    write_sources(connection, kb_id, kb);
    auto upsert = connection.prepare(sql("kb/upsert_segment.sql"));
    // older segments change only when credited, which sets their last generation
    for (std::size_t id = 0; id < previous_size && id < kb.size(); ++id) {
        if (kb.record(id).last.generation == generation) write_segment(upsert, kb_id, kb, id);
    }
    for (std::size_t id = previous_size; id < kb.size(); ++id) write_segment(upsert, kb_id, kb, id);
}

std::vector<KbSummary> list_kbs(Connection& connection) {
    std::vector<KbSummary> list;
    const bool has_counting = database_info(connection).schema_version >= kFirstVersionWithCounting;
    auto select =
        connection.prepare(sql(has_counting ? "kb/select_kbs.sql" : "kb/select_kbs_before_counting.sql"));
    const int id = select.column("id"), name = select.column("name"), width = select.column("segment_width"),
              channels = select.column("channels"), delta = select.column("delta"),
              match = select.column("match"), counting = select.column("counting"),
              seed = select.column("randomized_seed");
    while (select.step()) {
        KbSummary summary;
        summary.id = select.column_int(id);
        summary.name = select.column_text(name);
        summary.params.segment_width = static_cast<std::size_t>(select.column_int(width));
        summary.params.channels = static_cast<std::size_t>(select.column_int(channels));
        summary.params.delta = select.column_double(delta);
        summary.params.match = parse_match(select.column_text(match), connection.name() + ": kb.match");
        summary.params.counting =
            kb::parse_counting(select.column_text(counting), connection.name() + ": kb.counting");
        if (!select.is_null(seed))
            summary.randomized_seed = static_cast<std::uint64_t>(select.column_int(seed));
        list.push_back(summary);
    }
    auto count = connection.prepare(sql("kb/count_segments.sql"));
    for (auto& summary : list) {
        count.reset();
        count.bind(":kb_id", summary.id);
        summary.segments = count.step() ? count.column_int(0) : 0;
    }
    return list;
}

StoredKb load_kb(Connection& connection, const std::string& name) {
    const auto all = list_kbs(connection);
    const KbSummary* chosen = nullptr;
    if (name.empty()) {
        if (all.empty()) throw DataError(concat(connection.name(), ": holds no knowledge base"));
        if (all.size() > 1) {
            throw DataError(concat(connection.name(), ": holds ", all.size(), " knowledge bases; name one"));
        }
        chosen = &all.front();
    } else {
        for (const auto& summary : all) {
            if (summary.name == name) chosen = &summary;
        }
        if (!chosen) throw DataError(concat(connection.name(), ": no knowledge base named \"", name, '"'));
    }
    const kb::KbParams params = chosen->params;
    const std::size_t dim = params.dim();

    // sources
    std::vector<kb::Source> sources;
    auto select_sources = connection.prepare(sql("kb/select_sources.sql"));
    select_sources.bind(":kb_id", chosen->id);
    while (select_sources.step()) {
        kb::Source source;
        source.run = select_sources.column_text(1);
        source.first_generation = select_sources.column_int(2);
        source.last_generation = select_sources.column_int(3);
        source.policies = static_cast<std::uint64_t>(select_sources.column_int(4));
        sources.push_back(source);
    }

    // segments, checked before the KB sees them
    std::vector<float> values;
    std::vector<kb::SegmentRecord> records;
    values.reserve(static_cast<std::size_t>(chosen->segments) * dim);
    records.reserve(static_cast<std::size_t>(chosen->segments));
    auto select = connection.prepare(sql("kb/select_segments.sql"));
    select.bind(":kb_id", chosen->id);
    while (select.step()) {
        const auto id = select.column_int(0);
        if (id != static_cast<std::int64_t>(records.size())) {
            throw DatabaseError(concat(connection.name(), ": knowledge base \"", chosen->name, "\" misses segment ",
                                       records.size()));
        }
        kb::SegmentRecord record;
        record.cum_reward = select.column_double(1);
        const auto count = select.column_int(2);
        record.first = {static_cast<std::uint32_t>(select.column_int(3)), select.column_int(4)};
        record.last = {static_cast<std::uint32_t>(select.column_int(5)), select.column_int(6)};
        const auto blob = select.column_blob(7);
        const auto bad = [&](const std::string& problem) {
            return DatabaseError(concat(connection.name(), ": knowledge base \"", chosen->name, "\" segment ",
                                        id, " ", problem));
        };
        if (count < 1) throw bad(concat("has count ", count, " (at least 1 expected)"));
        if (!std::isfinite(record.cum_reward)) {
            throw bad(concat("has a non-finite cum_reward (", shortest(record.cum_reward), ")"));
        }
        record.count = static_cast<std::uint64_t>(count);
        const std::size_t offset = values.size();
        values.resize(offset + dim);
        if (!unpack_segment(blob, params.segment_width, params.channels,
                            std::span<float>(values).subspan(offset))) {
            throw bad(concat("holds ", blob.size(), " value bytes: neither ", dim * sizeof(float),
                             " bytes of float32 nor a packed segment"));
        }
        records.push_back(record);
    }

    StoredKb stored;
    stored.id = chosen->id;
    stored.name = chosen->name;
    stored.randomized_seed = chosen->randomized_seed;
    try {
        stored.kb = kb::KnowledgeBase::from_segments(params, std::move(sources), values, records);
    } catch (const Error& e) {
        throw DatabaseError(concat(connection.name(), ": knowledge base \"", chosen->name, "\": ", e.what()));
    }
    return stored;
}

}  // namespace stepstone::db
