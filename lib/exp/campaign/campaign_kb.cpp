#include "exp/campaign/campaign_kb.hpp"

#include <zlib.h>

#include <fstream>

#include "core/error.hpp"
#include "core/text.hpp"
#include "runs/kb_files.hpp"
#include "runs/run_store.hpp"

namespace stepstone::exp {

namespace fs = std::filesystem;

void gunzip_file(const fs::path& in, const fs::path& out) {
    gzFile file = gzopen(in.c_str(), "rb");
    if (file == nullptr) throw DataError(concat(in.string(), ": cannot be opened"));
    if (gzdirect(file) == 1) {  // zlib would pass plain bytes through
        gzclose(file);
        throw DataError(concat(in.string(), ": not whole gzip data"));
    }
    std::ofstream target(out, std::ios::binary | std::ios::trunc);
    if (!target) {
        gzclose(file);
        throw Error(concat("cannot write ", out.string()));
    }
    char buffer[1 << 16];
    int read = 0;
    while ((read = gzread(file, buffer, sizeof buffer)) > 0) target.write(buffer, read);
    int code = Z_OK;
    const bool failed = read < 0 || (gzerror(file, &code), code != Z_OK && code != Z_STREAM_END);
    gzclose(file);
    target.close();
    if (failed || !target) {
        fs::remove(out);
        throw DataError(concat(in.string(), ": not whole gzip data"));
    }
}

const runs::CampaignRun& best_source_run(const std::vector<runs::CampaignRun>& runs) {
    const runs::CampaignRun* best = nullptr;
    for (const auto& state : runs) {
        if (state.run.step != runs::CampaignStep::source) continue;
        if (best == nullptr) {
            best = &state;
            continue;
        }
        const double r = state.best_reward.value_or(0), b = best->best_reward.value_or(0);
        if (r > b || (r == b && state.run.seed < best->run.seed)) best = &state;
    }
    if (best == nullptr) throw Error("the campaign has no source run");
    return *best;
}

fs::path campaign_seed_source(const fs::path& dir, const runs::CampaignConfig& config,
                              const std::vector<runs::CampaignRun>& runs) {
    if (config.seed && config.seed->from_file) {
        if (config.seed->file.extension() != ".gz") return config.seed->file;
        // a compressed run file (the demo's fixture): uncompressed once into the campaign
        const fs::path plain = dir / "seed" / "source.db";
        if (!fs::exists(plain)) {
            fs::create_directories(plain.parent_path());
            const fs::path partial = plain.string() + ".partial";
            gunzip_file(config.seed->file, partial);
            fs::rename(partial, plain);
        }
        return plain;
    }
    return dir / best_source_run(runs).run.file;
}

void make_campaign_kbs(const fs::path& dir, const runs::CampaignConfig& config, db::Connection& connection,
                       const std::vector<runs::CampaignRun>& runs) {
    const fs::path kb_path = dir / runs::kKbFile;
    fs::create_directories(kb_path.parent_path());
    std::string made_from;
    if (config.kb_from == runs::KbFrom::file) {
        if (config.kb_file.extension() == ".gz") {
            // a compressed KB (the demo's fixture): copied from its uncompressed form
            const fs::path plain = kb_path.parent_path() / ".kb-file-uncompressed.db";
            gunzip_file(config.kb_file, plain);
            try {
                runs::export_kb(plain, "", kb_path, true);
            } catch (...) {
                fs::remove(plain);
                throw;
            }
            fs::remove(plain);
        } else {
            runs::export_kb(config.kb_file, "", kb_path, true);
        }
        made_from = concat("copy of ", config.kb_file_given);
    } else {
        std::vector<const runs::CampaignRun*> sources;
        for (const auto& state : runs) {
            if (state.run.step == runs::CampaignStep::source) sources.push_back(&state);
        }
        if (config.kb_from == runs::KbFrom::best || sources.size() == 1) {
            const runs::CampaignRun* best = &best_source_run(runs);
            runs::export_kb(dir / best->run.file, runs::kRunKbName, kb_path, true);
            made_from =
                concat("best source run ", best->run.file, " (reward ", best->best_reward.value_or(0), ")");
        } else {
            std::vector<fs::path> inputs;
            for (const runs::CampaignRun* state : sources) inputs.push_back(dir / state->run.file);
            runs::merge_kb_files(inputs, kb_path, "kb", true, runs::kRunKbName);
            made_from = concat("merge of ", inputs.size(), " source runs");
        }
    }
    if (config.kb_delta) {
        // re-observed under the larger delta (kb export --delta), then put in place
        const fs::path coarse = dir / (std::string(runs::kKbFile) + ".coarse");
        runs::export_kb(kb_path, "", coarse, true, config.kb_delta);
        fs::rename(coarse, kb_path);
        made_from += concat(", coarsened to delta ", shortest(*config.kb_delta));
    }
    runs::record_kb(connection, "kb", runs::kKbFile, made_from, kb_path);
    if (config.needs_randomized_kb()) {
        runs::randomize_kb_file(kb_path, dir / runs::kRandomKbFile, config.randomize_seed, "", true);
        runs::record_kb(connection, "kb-rand", runs::kRandomKbFile,
                        concat("randomize ", runs::kKbFile, " seed ", config.randomize_seed),
                        dir / runs::kRandomKbFile);
    }
}

}  // namespace stepstone::exp
