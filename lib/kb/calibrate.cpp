#include "kb/calibrate.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/text.hpp"
#include "kb/distance.hpp"

namespace stepstone::kb {

double calibrate_delta(Segments policy, std::size_t neighbours) {
    if (neighbours == 0) throw DataError("calibrate: neighbours must be >= 1, got 0");
    if (policy.dim == 0) throw DataError("calibrate: segment dimension must be >= 1, got 0");
    const std::size_t n = policy.size();
    if (n < 2) throw DataError(concat("calibrate: the policy has ", n, " segment(s), at least 2 are needed"));
    for (float v : policy.values.first(n * policy.dim)) {
        if (!std::isfinite(v)) throw DataError("calibrate: the policy has a non-finite value");
    }

    // every pairwise distance, then for each segment the mean of its k smallest
    const std::size_t k = std::min(neighbours, n - 1);
    std::vector<double> dist(n * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            const double d = std::sqrt(squared_distance(policy[i].data(), policy[j].data(), policy.dim));
            dist[i * n + j] = d;
            dist[j * n + i] = d;
        }
    }
    double total = 0.0;
    std::vector<double> row;
    for (std::size_t i = 0; i < n; ++i) {
        row.clear();
        for (std::size_t j = 0; j < n; ++j)
            if (j != i) row.push_back(dist[i * n + j]);
        std::partial_sort(row.begin(), row.begin() + static_cast<std::ptrdiff_t>(k), row.end());
        double sum = 0.0;
        for (std::size_t m = 0; m < k; ++m) sum += row[m];
        total += sum / static_cast<double>(k);
    }
    return total / static_cast<double>(n);
}

namespace {

// the k smallest values pushed so far (a max-heap of at most k)
class Smallest {
public:
    void push(double v, std::size_t k) {
        if (heap_.size() < k) {
            heap_.push_back(v);
            std::push_heap(heap_.begin(), heap_.end());
        } else if (v < heap_.front()) {
            std::pop_heap(heap_.begin(), heap_.end());
            heap_.back() = v;
            std::push_heap(heap_.begin(), heap_.end());
        }
    }
    // the mean of the square roots of the kept squared distances
    double mean_root() const {
        double sum = 0.0;
        for (double v : heap_) sum += std::sqrt(v);
        return heap_.empty() ? 0.0 : sum / static_cast<double>(heap_.size());
    }

private:
    std::vector<double> heap_;
};

}  // namespace

WindowDeltas calibrate_delta_windows(std::span<const float> behaviour, std::size_t channels,
                                     std::size_t width, std::size_t neighbours) {
    if (neighbours == 0) throw DataError("calibrate: neighbours must be >= 1, got 0");
    if (channels == 0 || width == 0) throw DataError("calibrate: channels and width must be >= 1");
    if (behaviour.size() % channels != 0) {
        throw DataError(
            concat("calibrate: ", behaviour.size(), " values are not rows of ", channels, " channels"));
    }
    for (float v : behaviour) {
        if (!std::isfinite(v)) throw DataError("calibrate: the policy has a non-finite value");
    }
    const std::size_t steps = behaviour.size() / channels;
    // every window needs a candidate sharing no row with it: 2 x width windows
    if (steps + 1 < 3 * width) {
        throw DataError(concat("calibrate: the windows reading needs at least ", 3 * width - 1,
                               " steps for windows of ", width, ", the policy has ", steps));
    }
    const std::size_t n = steps - width + 1;

    // by diagonals: for an offset k, e[a] is the squared distance of rows a and
    // a + k, and window i's squared distance to window i + k the sum of e over
    // its width rows
    std::vector<Smallest> all(n), apart(n);
    std::vector<double> e(steps);
    for (std::size_t k = 1; k < n; ++k) {
        for (std::size_t a = 0; a + k < steps; ++a) {
            const float* x = behaviour.data() + a * channels;
            const float* y = behaviour.data() + (a + k) * channels;
            double d2 = 0.0;
            for (std::size_t c = 0; c < channels; ++c) {
                const double d = static_cast<double>(x[c]) - static_cast<double>(y[c]);
                d2 += d * d;
            }
            e[a] = d2;
        }
        for (std::size_t i = 0; i + k < n; ++i) {
            double d2 = 0.0;
            for (std::size_t r = 0; r < width; ++r) d2 += e[i + r];
            all[i].push(d2, neighbours);
            all[i + k].push(d2, neighbours);
            if (k >= width) {
                apart[i].push(d2, neighbours);
                apart[i + k].push(d2, neighbours);
            }
        }
    }
    WindowDeltas out;
    out.windows = n;
    double sum_all = 0.0, sum_apart = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        sum_all += all[i].mean_root();
        sum_apart += apart[i].mean_root();
    }
    out.including_overlap = sum_all / static_cast<double>(n);
    out.excluding_overlap = sum_apart / static_cast<double>(n);
    return out;
}

std::vector<DeltaSize> kb_sizes(const KbParams& params, std::span<const Segments> policies,
                                std::span<const double> deltas) {
    std::vector<DeltaSize> sizes;
    sizes.reserve(deltas.size());
    for (const double delta : deltas) {
        KbParams p = params;
        p.delta = delta;
        KnowledgeBase kb(p);
        const std::uint32_t source = kb.add_source("calibrate");
        for (const Segments& policy : policies) kb.observe(policy, 0.0, Origin{source, 0});
        sizes.push_back(DeltaSize{delta, kb.size()});
    }
    return sizes;
}

}  // namespace stepstone::kb
