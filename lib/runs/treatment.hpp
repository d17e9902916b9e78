#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace stepstone::runs {

/// How a run transfers from the source task: how a knowledge base shapes its
/// reward (the paper, section III.D), and whether its generation 0 is seeded
/// with a source run's policies (docs/transfer.md: seeding). The five shaping
/// treatments are the paper's; each has a seeded twin, named with "seed-"
/// before it ("seed" alone for none), which a campaign lists as a treatment of
/// its own and a seeded run records in its `run.treatment`. A run config says
/// the same with transfer.treatment (the shaping) and transfer.seed.
enum class Treatment {
    none,           ///< objectives (reward, diversity); r_max only recorded when a KB is given
    sum,            ///< objectives (reward + normalised r_max, diversity)
    mo,             ///< objectives (reward, diversity, r_max)
    sum_rand,       ///< `sum` with a randomized KB (a `kb randomize` output)
    mo_rand,        ///< `mo` with a randomized KB
    seed,           ///< `none`, seeded
    seed_sum,       ///< `sum`, seeded
    seed_mo,        ///< `mo`, seeded
    seed_sum_rand,  ///< `sum-rand`, seeded
    seed_mo_rand,   ///< `mo-rand`, seeded
};

/// "none", "sum", "mo", "sum-rand", "mo-rand", "seed", "seed-sum", "seed-mo",
/// "seed-sum-rand" or "seed-mo-rand".
std::string_view to_string(Treatment treatment);
/// Parses a treatment name, seeded ones included; throws ConfigError naming
/// `what` and the accepted names otherwise.
Treatment parse_treatment(const std::string& text, const std::string& what = "treatment");
/// Parses the name of a shaping treatment (none, sum, mo, sum-rand, mo-rand),
/// as a run config's transfer.treatment and evolve's `treatment` take it; a
/// seeded name is refused with a pointer to the run's seed settings.
Treatment parse_shaping_treatment(const std::string& text, const std::string& what = "treatment");
/// The paper's five treatments, in its order (none, sum, mo, sum-rand,
/// mo-rand): a campaign's default.
std::span<const Treatment> all_treatments();

/// True for the seeded treatments (seed, seed-sum, ...).
bool is_seeded(Treatment treatment);
/// The shaping of `treatment`: itself for the paper's five, the unseeded twin
/// of a seeded one (seed-sum gives sum, seed gives none).
Treatment shaping_of(Treatment treatment);
/// The seeded twin of `treatment`'s shaping (sum gives seed-sum, none gives seed).
Treatment seeded(Treatment treatment);

/// True for sum and sum-rand (and their seeded twins): r_max is added to the first objective.
bool adds_shaping(Treatment treatment);
/// True for mo and mo-rand (and their seeded twins): r_max is a third objective.
bool shaping_objective(Treatment treatment);
/// True for sum-rand and mo-rand (and their seeded twins): the KB must be a randomized one.
bool needs_randomized_kb(Treatment treatment);
/// True for every treatment but none and seed: a KB is required.
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
