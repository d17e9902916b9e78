#include "runs/kb_duplicates.hpp"

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/digest.hpp"

namespace stepstone::runs {

namespace fs = std::filesystem;

namespace {

std::string display(const fs::path& path) { return path.string(); }

}  // namespace

// the same KB merged twice counts its policies twice: the same file, the same
// content, or a source run observed in both
void refuse_duplicate_kbs(std::span<const fs::path> inputs, const std::vector<db::StoredKb>& loaded) {
    const auto same_source = [](const kb::Source& a, const kb::Source& b) {
        return a.run == b.run && a.first_generation == b.first_generation &&
               a.last_generation == b.last_generation && a.policies == b.policies;
    };
    for (std::size_t i = 0; i < loaded.size(); ++i) {
        for (std::size_t j = i + 1; j < loaded.size(); ++j) {
            std::error_code ec;
            std::string why;
            if (fs::equivalent(inputs[i], inputs[j], ec)) {
                why = "they are the same file";
            } else if (db::kb_digest(loaded[i].kb, loaded[i].randomized_seed) ==
                       db::kb_digest(loaded[j].kb, loaded[j].randomized_seed)) {
                why = "they hold the same knowledge base";
            } else {
                for (const auto& a : loaded[i].kb.sources()) {
                    for (const auto& b : loaded[j].kb.sources()) {
                        if (why.empty() && same_source(a, b))
                            why = concat("both observed run \"", a.run, '"');
                    }
                }
            }
            if (!why.empty()) {
                throw DuplicateKbs(concat("cannot merge ", display(inputs[j]), " with ", display(inputs[i]),
                                          ": ", why, ", so its policies would count twice"));
            }
        }
    }
}

}  // namespace stepstone::runs
