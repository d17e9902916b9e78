#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace stepstone::runs {

/// How a run uses a knowledge base to shape its reward (the paper, section III.D).
enum class Treatment {
    none,      ///< objectives (reward, diversity); r_max only recorded when a KB is given
    sum,       ///< objectives (reward + normalised r_max, diversity)
    mo,        ///< objectives (reward, diversity, r_max)
    sum_rand,  ///< `sum` with a randomized KB (a `kb randomize` output)
    mo_rand,   ///< `mo` with a randomized KB
};

/// "none", "sum", "mo", "sum-rand" or "mo-rand".
std::string_view to_string(Treatment treatment);
/// Parses a treatment name; throws ConfigError naming `what` and the accepted names otherwise.
Treatment parse_treatment(const std::string& text, const std::string& what = "treatment");
/// Every treatment, in the paper's order (none, sum, mo, sum-rand, mo-rand).
std::span<const Treatment> all_treatments();

/// True for sum and sum-rand: r_max is added to the first objective.
bool adds_shaping(Treatment treatment);
/// True for mo and mo-rand: r_max is a third objective.
bool shaping_objective(Treatment treatment);
/// True for sum-rand and mo-rand: the KB must be a randomized one.
bool needs_randomized_kb(Treatment treatment);
/// True for every treatment but none: a KB is required.
bool needs_kb(Treatment treatment);

/// The fraction of one ball's reward that the largest possible shaping term
/// stays below: the `sum` bonus is at most (1 - kSumMargin) x one ball.
inline constexpr double kSumMargin = 1.0 / 1024.0;

/// The `sum` treatment's first objective (the paper's footnote 3):
///
///     reward + (r_max / max_average) x ball_reward x (1 - kSumMargin)
///
/// where max_average is the KB's largest average reward and ball_reward the
/// reward of one ball (1 / 24 on the paper's task). r_max lies in
/// [0, max_average], so the bonus lies in [0, ball_reward) and a policy with n
/// balls always ranks below one with n + 1 balls. A KB whose largest average
/// is not positive gives no bonus.
double sum_fitness(double reward, double r_max, double max_average, double ball_reward);

/// The selection objectives of one policy under `treatment`: (reward,
/// diversity), (sum_fitness, diversity) or (reward, diversity, r_max).
/// `r_max` may be absent only for `none`.
std::vector<double> treatment_objectives(Treatment treatment, double reward, double diversity,
                                         std::optional<double> r_max, double max_average, double ball_reward);

}  // namespace stepstone::runs
