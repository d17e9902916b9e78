#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace stepstone::stats {

/// How the p-value of a Mann-Whitney U test was obtained.
enum class Method {
    exact,       ///< from the exact null distribution of U (no ties assumed)
    asymptotic,  ///< from the normal approximation with tie and continuity corrections
};

/// The result of mann_whitney_u.
struct MannWhitney {
    double u = 0;                   ///< U statistic of the first sample: #(a_i > b_j) + 0.5 #(a_i == b_j)
    double p = 1;                   ///< two-sided p-value
    Method method = Method::exact;  ///< how p was obtained
};

/// Two-sided Mann-Whitney U test with SciPy's `mannwhitneyu(x, y,
/// alternative="two-sided", method="auto", use_continuity=True)` conventions.
///
/// U_a = #(a_i > b_j) + 0.5 #(a_i == b_j), U_b = n_a n_b - U_a, U = max(U_a, U_b).
///
/// Method (SciPy's `_mwu_choose_method`, the same in SciPy 1.10.1 and the
/// current main branch): exact when min(n_a, n_b) <= 8 and no two values of the
/// pooled sample are equal (ties within one sample count); asymptotic otherwise.
///
/// Exact: p = min(1, 2 P(U' >= U)), U' following the null distribution of U for
/// sizes n_a, n_b without ties (every assignment of the pooled ranks to the two
/// samples equally likely); see mann_whitney_exact_cdf.
///
/// Asymptotic: mu = n_a n_b / 2, n = n_a + n_b,
/// sigma^2 = n_a n_b / 12 ((n + 1) - sum(t^3 - t) / (n (n - 1))), t running over
/// the sizes of the groups of equal values in the pooled sample,
/// z = (U - mu - 0.5) / sigma and p = min(1, 2 (1 - Phi(z))) = min(1, erfc(z / sqrt 2)).
/// p = 1 when U - mu <= 0.5 and when sigma = 0 (every value equal).
///
/// Infinities are ordinary values. Throws DataError if a or b is empty or holds a NaN.
MannWhitney mann_whitney_u(std::span<const double> a, std::span<const double> b);

/// P(U' <= k) for U' the Mann-Whitney U statistic of a sample of n_a values
/// against one of n_b values under the null hypothesis without ties: each of the
/// C(n_a + n_b, n_a) assignments of the pooled ranks is equally likely. Computed
/// with the recurrence P_{i,j}(u) = i/(i+j) P_{i-1,j}(u-j) + j/(i+j) P_{i,j-1}(u)
/// (the largest pooled value belongs to the first sample with probability
/// i/(i+j) and then beats all j values of the second), which adds non-negative
/// terms only, in double: no overflow, a relative error of a few ulps per step.
/// Time O(n_a n_b min(k, n_a n_b)), memory O(min(n_a, n_b) k). The
/// distribution is symmetric: P(U' >= u) = P(U' <= n_a n_b - u).
/// Throws DataError if n_a or n_b is 0.
double mann_whitney_exact_cdf(std::size_t n_a, std::size_t n_b, std::size_t k);

/// Vargha-Delaney A12 = P(A > B) + 0.5 P(A = B) = U_a / (n_a n_b), A and B drawn
/// uniformly from a and b. 0.5 means no effect, 1 that every a beats every b.
/// Throws DataError if a or b is empty or holds a NaN.
double vargha_delaney_a12(std::span<const double> a, std::span<const double> b);

/// Holm-Bonferroni step-down adjusted p-values, in the input order, monotone,
/// capped at 1 (as R's p.adjust(method="holm")): with p_(1) <= ... <= p_(m) the
/// sorted values, adjusted p_(i) = min(1, max_{j <= i} (m - j + 1) p_(j)).
/// Equal p-values get equal adjusted values. Empty input gives an empty result.
/// Throws DataError if a value is NaN or outside [0, 1].
std::vector<double> holm(std::span<const double> p);

}  // namespace stepstone::stats
