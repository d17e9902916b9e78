#pragma once

// A plain knowledge base written straight from the paper's rule (section II.B)
// with a linear scan, and the data sets the kb tests feed to both.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "core/rng.hpp"
#include "kb/knowledge_base.hpp"

namespace kboracle {

/// KB parameters of segments of `width` x `channels` values matched within `delta` (or by `match`).
inline stepstone::kb::KbParams params_of(std::size_t width, std::size_t channels, double delta,
                                         stepstone::kb::Match match = stepstone::kb::Match::within_delta) {
    stepstone::kb::KbParams p;
    p.segment_width = width;
    p.channels = channels;
    p.delta = delta;
    p.match = match;
    return p;
}

/// The documented distance order (kb/distance.hpp): value k goes to lane
/// k % 8, lanes summed as ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)).
inline double oracle_squared_distance(const float* a, const float* b, std::size_t dim) {
    double lane[8] = {};
    for (std::size_t k = 0; k < dim; ++k) {
        const double d = static_cast<double>(a[k]) - static_cast<double>(b[k]);
        lane[k % 8] += d * d;
    }
    return ((lane[0] + lane[1]) + (lane[2] + lane[3])) + ((lane[4] + lane[5]) + (lane[6] + lane[7]));
}

/// Linear-scan nearest: smallest squared distance, the first (lowest id) on ties.
inline std::optional<std::pair<std::size_t, double>> oracle_nearest(const std::vector<float>& values,
                                                                    std::size_t dim, const float* query) {
    std::optional<std::pair<std::size_t, double>> best;
    for (std::size_t id = 0; id * dim < values.size(); ++id) {
        const double d2 = oracle_squared_distance(query, values.data() + id * dim, dim);
        if (!best || d2 < best->second) best = std::make_pair(id, d2);
    }
    return best;
}

/// The paper's knowledge base, one segment at a time, by linear scan.
struct OracleKb {
    std::size_t dim = 0;
    double delta = 0;
    std::vector<float> values;
    std::vector<double> cum_reward;
    std::vector<std::uint64_t> count;

    std::size_t size() const { return count.size(); }

    /// The nearest within delta: squared distance < delta * delta.
    std::optional<std::pair<std::size_t, double>> within(const float* q) const {
        auto best = oracle_nearest(values, dim, q);
        if (best && best->second < delta * delta) return best;
        return std::nullopt;
    }

    void add(const float* s, double cum, std::uint64_t n) {
        if (auto m = within(s)) {
            cum_reward[m->first] += cum;
            count[m->first] += n;
        } else {
            values.insert(values.end(), s, s + dim);
            cum_reward.push_back(cum);
            count.push_back(n);
        }
    }

    void observe(const std::vector<float>& segments, double reward) {
        for (std::size_t i = 0; i * dim < segments.size(); ++i) add(segments.data() + i * dim, reward, 1);
    }

    /// The paper's footnote 1: each KB segment counts the policy once. A KB
    /// segment that the policy already credited, or inserted, is left alone.
    void observe_per_policy(const std::vector<float>& segments, double reward) {
        std::vector<bool> touched(size(), false);
        for (std::size_t i = 0; i * dim < segments.size(); ++i) {
            const float* s = segments.data() + i * dim;
            if (auto m = within(s)) {
                if (touched[m->first]) continue;
                touched[m->first] = true;
                cum_reward[m->first] += reward;
                count[m->first] += 1;
            } else {
                values.insert(values.end(), s, s + dim);
                cum_reward.push_back(reward);
                count.push_back(1);
                touched.push_back(true);
            }
        }
    }
};

/// `n` segments of `dim` values uniform in [0, 1).
inline std::vector<float> uniform_segments(stepstone::Rng& rng, std::size_t n, std::size_t dim) {
    std::vector<float> v(n * dim);
    for (float& x : v) x = static_cast<float>(rng.uniform());
    return v;
}

/// `n` segments of `dim` values scattered with per-value spread `spread`
/// around `centres` random centres in [0, 1)^dim (a few distinct behaviours
/// with noise).
inline std::vector<float> clustered_segments(stepstone::Rng& rng, std::size_t n, std::size_t dim,
                                             std::size_t centres, double spread) {
    std::vector<float> c = uniform_segments(rng, centres, dim);
    std::vector<float> v(n * dim);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k = static_cast<std::size_t>(rng.below(centres));
        for (std::size_t d = 0; d < dim; ++d)
            v[i * dim + d] = c[k * dim + d] + static_cast<float>(rng.uniform(-spread, spread));
    }
    return v;
}

/// Values on a coarse grid (multiples of 1/4): many exact ties and distances
/// exactly equal to a delta of the same grid.
inline std::vector<float> grid_segments(stepstone::Rng& rng, std::size_t n, std::size_t dim, int levels) {
    std::vector<float> v(n * dim);
    for (float& x : v) x = static_cast<float>(rng.below(static_cast<std::uint64_t>(levels))) * 0.25f;
    return v;
}

/// Segments of `width` rows x `channels` shaped like the paper's behaviours:
/// the channels of `binary` hold 0 or 1, the others floats in [0, 1). They
/// come from `centres` prototypes, each copy flipping a binary value with
/// probability `flip` and moving the others by up to +-`spread`; so many
/// pairs differ in a few bits only, as a policy's and a KB's segments do.
inline std::vector<float> binary_segments(stepstone::Rng& rng, std::size_t n, std::size_t width,
                                          std::size_t channels, const std::vector<std::size_t>& binary,
                                          std::size_t centres, double flip, double spread) {
    const std::size_t dim = width * channels;
    std::vector<bool> is_binary(channels, false);
    for (const std::size_t c : binary) is_binary[c] = true;
    std::vector<float> c(centres * dim);
    for (std::size_t i = 0; i < c.size(); ++i)
        c[i] = is_binary[i % channels] ? static_cast<float>(rng.below(4) == 0)
                                       : static_cast<float>(rng.uniform());
    std::vector<float> v(n * dim);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k = static_cast<std::size_t>(rng.below(centres));
        for (std::size_t d = 0; d < dim; ++d) {
            const float x = c[k * dim + d];
            v[i * dim + d] = is_binary[d % channels] ? (rng.uniform() < flip ? 1.0f - x : x)
                                                     : x + static_cast<float>(rng.uniform(-spread, spread));
        }
    }
    return v;
}

}  // namespace kboracle
