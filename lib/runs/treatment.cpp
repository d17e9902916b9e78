#include "runs/treatment.hpp"

#include <algorithm>
#include <array>

#include "core/assert.hpp"
#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::runs {

namespace {

constexpr std::array kTreatments = {Treatment::none, Treatment::sum, Treatment::mo, Treatment::sum_rand,
                                    Treatment::mo_rand};
constexpr std::array kSeeded = {Treatment::seed, Treatment::seed_sum, Treatment::seed_mo,
                                Treatment::seed_sum_rand, Treatment::seed_mo_rand};

}  // namespace

std::string_view to_string(Treatment treatment) {
    switch (treatment) {
        case Treatment::none:
            return "none";
        case Treatment::sum:
            return "sum";
        case Treatment::mo:
            return "mo";
        case Treatment::sum_rand:
            return "sum-rand";
        case Treatment::mo_rand:
            return "mo-rand";
        case Treatment::seed:
            return "seed";
        case Treatment::seed_sum:
            return "seed-sum";
        case Treatment::seed_mo:
            return "seed-mo";
        case Treatment::seed_sum_rand:
            return "seed-sum-rand";
        case Treatment::seed_mo_rand:
            return "seed-mo-rand";
    }
    return "none";
}

Treatment parse_treatment(const std::string& text, const std::string& what) {
    for (Treatment treatment : kTreatments) {
        if (text == to_string(treatment)) return treatment;
    }
    for (Treatment treatment : kSeeded) {
        if (text == to_string(treatment)) return treatment;
    }
    throw ConfigError(concat(what,
                             " must be one of none, sum, mo, sum-rand, mo-rand, seed, seed-sum, seed-mo, "
                             "seed-sum-rand, seed-mo-rand, got \"",
                             text, "\""));
}

Treatment parse_shaping_treatment(const std::string& text, const std::string& what) {
    for (Treatment treatment : kTreatments) {
        if (text == to_string(treatment)) return treatment;
    }
    for (Treatment treatment : kSeeded) {
        if (text == to_string(treatment)) {
            throw ConfigError(concat(what, " must be one of none, sum, mo, sum-rand, mo-rand, got \"", text,
                                     "\": a run is seeded by its seed source (", option_name("seed_from"),
                                     " or transfer.seed) with treatment ", to_string(shaping_of(treatment))));
        }
    }
    throw ConfigError(concat(what, " must be one of none, sum, mo, sum-rand, mo-rand, got \"", text, "\""));
}

std::span<const Treatment> all_treatments() { return kTreatments; }

bool is_seeded(Treatment treatment) {
    return std::find(kSeeded.begin(), kSeeded.end(), treatment) != kSeeded.end();
}

Treatment shaping_of(Treatment treatment) {
    for (std::size_t k = 0; k < kSeeded.size(); ++k) {
        if (kSeeded[k] == treatment) return kTreatments[k];
    }
    return treatment;
}

Treatment seeded(Treatment treatment) {
    const Treatment shaping = shaping_of(treatment);
    for (std::size_t k = 0; k < kTreatments.size(); ++k) {
        if (kTreatments[k] == shaping) return kSeeded[k];
    }
    return Treatment::seed;
}

bool adds_shaping(Treatment treatment) {
    const Treatment t = shaping_of(treatment);
    return t == Treatment::sum || t == Treatment::sum_rand;
}

bool shaping_objective(Treatment treatment) {
    const Treatment t = shaping_of(treatment);
    return t == Treatment::mo || t == Treatment::mo_rand;
}

bool needs_randomized_kb(Treatment treatment) {
    const Treatment t = shaping_of(treatment);
    return t == Treatment::sum_rand || t == Treatment::mo_rand;
}

bool needs_kb(Treatment treatment) { return shaping_of(treatment) != Treatment::none; }

double sum_fitness(double reward, double r_max, double max_average, double ball_reward) {
    if (!(max_average > 0)) return reward;
    return reward + (r_max / max_average) * ball_reward * (1.0 - kSumMargin);
}

std::vector<double> treatment_objectives(Treatment treatment, double reward, double diversity,
                                         std::optional<double> r_max, double max_average,
                                         double ball_reward) {
    STEPSTONE_ASSERT(r_max || !needs_kb(treatment));
    const double shaping = r_max.value_or(0.0);
    if (adds_shaping(treatment)) return {sum_fitness(reward, shaping, max_average, ball_reward), diversity};
    if (shaping_objective(treatment)) return {reward, diversity, shaping};
    return {reward, diversity};
}

}  // namespace stepstone::runs
