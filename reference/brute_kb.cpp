#include "reference/brute_kb.hpp"

#include <algorithm>

#if __has_include(<Eigen/Dense>)
#include <Eigen/Dense>
#define STEPSTONE_BRUTE_KB_EIGEN 1
#elif __has_include(<eigen3/Eigen/Dense>)
#include <eigen3/Eigen/Dense>
#define STEPSTONE_BRUTE_KB_EIGEN 1
#endif

#include "kb/distance.hpp"

namespace stepstone::reference {

BruteKb::BruteKb(const kb::KnowledgeBase& kb)
    : dim_(kb.params().dim()), delta_(kb.params().delta), values_(kb.values().begin(), kb.values().end()) {
    for (const auto& r : kb.records()) {
        cum_reward_.push_back(r.cum_reward);
        count_.push_back(r.count);
    }
    initial_cum_reward_ = cum_reward_;
    initial_count_ = count_;
    for (std::size_t i = 0; i < count_.size(); ++i) norms_.push_back(squared_norm(values_.data() + i * dim_));
}

float BruteKb::squared_norm(const float* v) const {
    float s = 0;
    for (std::size_t k = 0; k < dim_; ++k) s += v[k] * v[k];
    return s;
}

void BruteKb::reset() {
    values_.resize(initial_count_.size() * dim_);
    norms_.resize(initial_count_.size());
    cum_reward_ = initial_cum_reward_;
    count_ = initial_count_;
}

void BruteKb::credit_or_insert(const float* s, double reward, std::optional<std::size_t> best,
                               double best_d2) {
    if (best && best_d2 < delta_ * delta_) {
        cum_reward_[*best] += reward;
        count_[*best] += 1;
    } else {
        values_.insert(values_.end(), s, s + dim_);
        norms_.push_back(squared_norm(s));
        cum_reward_.push_back(reward);
        count_.push_back(1);
    }
}

void BruteKb::observe_batched(const float* segs, std::size_t n_segs, double reward) {
    const std::size_t n = count_.size();
    distances_.resize(n_segs * n);
#if STEPSTONE_BRUTE_KB_EIGEN
    using Rows = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const Eigen::Map<const Rows> k(values_.data(), static_cast<Eigen::Index>(n),
                                   static_cast<Eigen::Index>(dim_));
    const Eigen::Map<const Rows> q(segs, static_cast<Eigen::Index>(n_segs), static_cast<Eigen::Index>(dim_));
    Eigen::Map<Rows> d(distances_.data(), static_cast<Eigen::Index>(n_segs), static_cast<Eigen::Index>(n));
    d.noalias() = q * k.transpose();
#else
    // blocked dot products with 8 float lanes
    for (std::size_t j0 = 0; j0 < n; j0 += 64) {
        const std::size_t j1 = std::min(n, j0 + 64);
        for (std::size_t i = 0; i < n_segs; ++i) {
            const float* a = segs + i * dim_;
            for (std::size_t j = j0; j < j1; ++j) {
                const float* b = values_.data() + j * dim_;
                float lane[8] = {};
                for (std::size_t c = 0; c < dim_; c += 8)
                    for (std::size_t l = 0; l < 8 && c + l < dim_; ++l) lane[l] += a[c + l] * b[c + l];
                distances_[i * n + j] =
                    ((lane[0] + lane[1]) + (lane[2] + lane[3])) + ((lane[4] + lane[5]) + (lane[6] + lane[7]));
            }
        }
    }
#endif
    for (std::size_t i = 0; i < n_segs; ++i) {
        const float* s = segs + i * dim_;
        const float qn = squared_norm(s);
        std::optional<std::size_t> best;
        double best_d2 = 0;
        const float* row = distances_.data() + i * n;
        for (std::size_t j = 0; j < n; ++j) {
            const double d2 = static_cast<double>(qn + norms_[j] - 2 * row[j]);
            if (!best || d2 < best_d2) {
                best = j;
                best_d2 = d2;
            }
        }
        for (std::size_t j = n; j < count_.size(); ++j) {
            const double d2 = kb::squared_distance(s, values_.data() + j * dim_, dim_);
            if (!best || d2 < best_d2) {
                best = j;
                best_d2 = d2;
            }
        }
        credit_or_insert(s, reward, best, best_d2);
    }
}

}  // namespace stepstone::reference
