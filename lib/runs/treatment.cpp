#include "runs/treatment.hpp"

#include <array>

#include "core/assert.hpp"
#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::runs {

namespace {

constexpr std::array kTreatments = {Treatment::none, Treatment::sum, Treatment::mo, Treatment::sum_rand,
                                    Treatment::mo_rand};

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
    }
    return "none";
}

Treatment parse_treatment(const std::string& text, const std::string& what) {
    for (Treatment treatment : kTreatments) {
        if (text == to_string(treatment)) return treatment;
    }
    throw ConfigError(concat(what, " must be one of none, sum, mo, sum-rand, mo-rand, got \"", text, "\""));
}

std::span<const Treatment> all_treatments() { return kTreatments; }

bool adds_shaping(Treatment treatment) {
    return treatment == Treatment::sum || treatment == Treatment::sum_rand;
}

bool shaping_objective(Treatment treatment) {
    return treatment == Treatment::mo || treatment == Treatment::mo_rand;
}

bool needs_randomized_kb(Treatment treatment) {
    return treatment == Treatment::sum_rand || treatment == Treatment::mo_rand;
}

bool needs_kb(Treatment treatment) { return treatment != Treatment::none; }

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
