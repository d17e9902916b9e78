#pragma once

// A knowledge base without an index: the observe rule of kb::KnowledgeBase
// (credit the nearest segment within delta, else insert) with every distance
// computed. Kept as the baseline of `stepstone bench kb` and `kb-uniform`.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "kb/knowledge_base.hpp"

namespace stepstone::reference {

class BruteKb {
public:
    /// A copy of `kb`'s segments, counts and cumulated rewards.
    explicit BruteKb(const kb::KnowledgeBase& kb);

    /// Back to the KB it was built from: its segments, counts and cumulated rewards.
    void reset();

    /// Observes one policy's `n_segs` segments (back to back, dim() values
    /// each) as the batched brute force does it: one distance matrix
    /// ||q||^2 + ||k||^2 - 2 q.k against the KB as it was before the policy
    /// (Eigen's product when its headers are found), then the segments this
    /// policy inserted checked one by one.
    void observe_batched(const float* segs, std::size_t n_segs, double reward);

    std::size_t size() const { return count_.size(); }
    std::size_t dim() const { return dim_; }
    double cum_reward(std::size_t i) const { return cum_reward_[i]; }
    std::uint64_t count(std::size_t i) const { return count_[i]; }

private:
    float squared_norm(const float* v) const;
    void credit_or_insert(const float* s, double reward, std::optional<std::size_t> best, double best_d2);

    std::size_t dim_;
    double delta_;
    std::vector<float> values_;
    std::vector<float> norms_;  // squared norms, for the batched form
    std::vector<double> cum_reward_;
    std::vector<std::uint64_t> count_;
    std::vector<double> initial_cum_reward_;
    std::vector<std::uint64_t> initial_count_;
    std::vector<float> distances_;
};

}  // namespace stepstone::reference
