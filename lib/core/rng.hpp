#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace stepstone {

/// What a random stream is used for. Each purpose gets an independent stream
/// for the same (run seed, generation, individual); new purposes are appended.
enum class Purpose : std::uint64_t {
    initial_genome = 1,
    mutation = 2,
    selection = 3,
    evaluation = 4,
    kb_randomize = 5,
    campaign_seed = 6,
    controller = 7,
    test = 8,
};

/// splitmix64's finaliser: a bijective 64-bit mixer with full avalanche.
constexpr std::uint64_t mix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

/// Seed of the stream for (run_seed, generation, individual, purpose).
/// Counter-based: any stream is computed directly, so results never depend on
/// which thread or MPI rank draws it, nor on what was drawn before.
std::uint64_t derive_seed(std::uint64_t run_seed, std::uint64_t generation,
                          std::uint64_t individual, Purpose purpose);

/// xoshiro256** generator seeded through splitmix64. The distributions below
/// are written out (not std::uniform_*_distribution) so a stream gives the
/// same numbers with any standard library.
class Rng {
public:
    using result_type = std::uint64_t;

    explicit Rng(std::uint64_t seed);
    /// The stream of derive_seed(run_seed, generation, individual, purpose).
    Rng(std::uint64_t run_seed, std::uint64_t generation, std::uint64_t individual, Purpose purpose);

    static constexpr result_type min() { return 0; }
    static constexpr result_type max() { return ~result_type{0}; }
    result_type operator()() { return next(); }

    /// 64 uniform random bits.
    std::uint64_t next();
    /// Uniform on [0, 1) with 53 random bits.
    double uniform();
    /// Uniform on [lo, hi).
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    /// Uniform integer in [0, n); n must be > 0. Unbiased (Lemire's method).
    std::uint64_t below(std::uint64_t n);
    /// True with probability p.
    bool bernoulli(double p) { return uniform() < p; }
    /// Fisher-Yates shuffle of indices or values.
    template <class T>
    void shuffle(std::span<T> values) {
        for (std::size_t i = values.size(); i > 1; --i) {
            std::size_t j = static_cast<std::size_t>(below(i));
            std::swap(values[i - 1], values[j]);
        }
    }

private:
    std::uint64_t s_[4];
};

/// A seed from the operating system's entropy, for runs given no seed (the
/// seed is then printed and stored with the run).
std::uint64_t fresh_seed();

}  // namespace stepstone
