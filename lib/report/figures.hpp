#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "kb/knowledge_base.hpp"
#include "report/canvas.hpp"
#include "runs/campaign_stats.hpp"
#include "runs/run_series.hpp"
#include "runs/treatment.hpp"

namespace stepstone::report {

/// One generation of a run, as its figures read it (runs::load_generations).
using runs::GenerationPoint;

/// The colour of a treatment in every campaign figure.
Colour treatment_colour(runs::Treatment treatment);

/// Best and median task reward per generation of one run.
void draw_run_rewards(Canvas& canvas, std::span<const GenerationPoint> generations, const std::string& title);
/// Mean and largest r_max of the policies evaluated in each generation of one
/// run (a run shaped by, or recording, a knowledge base).
void draw_run_shaping(Canvas& canvas, std::span<const GenerationPoint> generations, const std::string& title);

/// The paper's Fig. 3: segments per average-reward bin (`bins` bins of equal
/// width over [0, largest average]; [0, 1] when that is 0). With
/// `nonzero_only`, segments whose average is 0 are left out, so the salient
/// ones are not dwarfed by the many seen only in policies that scored nothing.
void draw_kb_histogram(Canvas& canvas, const kb::KnowledgeBase& kb, const std::string& title, int bins = 25,
                       bool nonzero_only = false);
/// The KB's size after each observed generation (by the generation whose
/// observation inserted each segment; sources one after another).
void draw_kb_growth(Canvas& canvas, const kb::KnowledgeBase& kb, const std::string& title);

/// Per treatment, the median over seeds of the best-so-far task reward along
/// generations, with the band between the first and third quartiles.
void draw_treatment_rewards(Canvas& canvas, const runs::CampaignStats& stats);
/// The paper's Fig. 6: successful runs per treatment along generations.
void draw_successes(Canvas& canvas, const runs::CampaignStats& stats);
/// The paper's Fig. 7: each run's best-of-run reward at the chosen generation,
/// jittered by treatment, with medians and the success threshold.
void draw_best_of_run(Canvas& canvas, const runs::CampaignStats& stats);
/// Per treatment, the median over seeds of each run's mean r_max per
/// generation: `series[t][r]` is run r of treatment t's generations.
void draw_treatment_shaping(Canvas& canvas, std::span<const runs::Treatment> treatments,
                            std::span<const std::vector<std::vector<GenerationPoint>>> series);

/// Per treatment, the median over seeds of each run's median survivor reward
/// per generation, with the quartile band (`series` as draw_treatment_shaping).
void draw_treatment_medians(Canvas& canvas, std::span<const runs::Treatment> treatments,
                            std::span<const std::vector<std::vector<GenerationPoint>>> series);

}  // namespace stepstone::report
