#include "db/digest.hpp"

#include <xxhash.h>

#include <cstdio>
#include <string_view>

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"

namespace stepstone::db {

namespace {

// each field enters the hash as a type tag then its bytes (text with its
// length), so ("ab", "c") and ("a", "bc"), or 1 and "1", never collide
class Hasher {
public:
    Hasher() : state_(XXH3_createState()) { XXH3_128bits_reset(state_); }
    ~Hasher() { XXH3_freeState(state_); }
    Hasher(const Hasher&) = delete;
    Hasher& operator=(const Hasher&) = delete;

    void bytes(const void* data, std::size_t size) { XXH3_128bits_update(state_, data, size); }
    void tag(char t) { bytes(&t, 1); }
    void text(std::string_view s) {
        const std::uint64_t size = s.size();
        bytes(&size, sizeof size);
        bytes(s.data(), s.size());
    }

    void row(const Statement& statement) {
        tag('R');
        for (int c = 0; c < statement.column_count(); ++c) {
            switch (statement.column_type(c)) {
                case Statement::Type::integer: {
                    tag('I');
                    const std::int64_t v = statement.column_int(c);
                    bytes(&v, sizeof v);
                    break;
                }
                case Statement::Type::real: {
                    tag('F');
                    const double v = statement.column_double(c);
                    bytes(&v, sizeof v);
                    break;
                }
                case Statement::Type::blob: {
                    tag('B');
                    const auto blob = statement.column_blob(c);
                    text(std::string_view(reinterpret_cast<const char*>(blob.data()), blob.size()));
                    break;
                }
                case Statement::Type::text:
                    tag('T');
                    text(statement.column_text(c));
                    break;
                case Statement::Type::null:
                    tag('N');
                    break;
            }
        }
    }

    std::string hex() const {
        const XXH128_hash_t h = XXH3_128bits_digest(state_);
        char buffer[33];
        std::snprintf(buffer, sizeof buffer, "%016llx%016llx", static_cast<unsigned long long>(h.high64),
                      static_cast<unsigned long long>(h.low64));
        return buffer;
    }

private:
    XXH3_state_t* state_;
};

}  // namespace

std::string run_digest(Connection& connection) {
    // the digest reads the milestone columns of schema 5; later migrations add nothing it
    // reads (6: a second form of the segment values, read as float32; 7: kb.counting;
    // 8: the individual column shaping renamed r_max, shown under both names read-only)
    constexpr int kOldestDigestable = 5;
    const int version = database_info(connection).schema_version;
    if (version < kOldestDigestable) {
        throw DatabaseError(concat(connection.name(), ": schema version ", version,
                                   " is older than this program (", latest_schema_version(),
                                   "); its digest covers columns the file lacks; run: "
                                   "stepstone db migrate ",
                                   connection.name()));
    }
    Hasher hasher;
    // every query names its columns and a total order, so the digest does
    // not depend on how SQLite laid the rows out
    for (auto& statement : connection.prepare_all(sql("run/digest_queries.sql"))) {
        hasher.tag('Q');
        while (statement.step()) hasher.row(statement);
    }
    return hasher.hex();
}

std::string kb_digest(const kb::KnowledgeBase& kb, std::optional<std::uint64_t> randomized_seed) {
    Hasher hasher;
    const auto& params = kb.params();
    const std::uint64_t shape[2] = {params.segment_width, params.channels};
    hasher.tag('P');
    hasher.bytes(shape, sizeof shape);
    hasher.bytes(&params.delta, sizeof params.delta);
    hasher.text(to_string(params.match));
    // occurrence, the rule of every KB before schema 7, leaves older digests as they were
    if (params.counting != kb::Counting::occurrence) {
        hasher.tag('C');
        hasher.text(kb::to_string(params.counting));
    }
    if (randomized_seed) {
        hasher.tag('S');
        hasher.bytes(&*randomized_seed, sizeof *randomized_seed);
    }
    hasher.tag('V');
    const auto values = kb.values();
    hasher.bytes(values.data(), values.size_bytes());
    for (const auto& record : kb.records()) {
        hasher.tag('R');
        hasher.bytes(&record.cum_reward, sizeof record.cum_reward);
        hasher.bytes(&record.count, sizeof record.count);
    }
    return hasher.hex();
}

}  // namespace stepstone::db
