#include "core/rng.hpp"

#include <random>

namespace stepstone {

namespace {

__extension__ typedef unsigned __int128 uint128;

constexpr std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

}  // namespace

std::uint64_t derive_seed(std::uint64_t run_seed, std::uint64_t generation, std::uint64_t individual,
                          Purpose purpose) {
    // chained mixing: each coordinate is folded into a fully mixed state, so
    // neighbouring coordinates give unrelated seeds
    std::uint64_t h = mix64(run_seed);
    h = mix64(h ^ generation);
    h = mix64(h ^ individual);
    return mix64(h ^ static_cast<std::uint64_t>(purpose));
}

Rng::Rng(std::uint64_t seed) {
    // splitmix64 sequence fills the state; it is never all zero
    std::uint64_t x = seed;
    for (auto& word : s_) {
        word = mix64(x);
        x += 0x9e3779b97f4a7c15ULL;
    }
}

Rng::Rng(std::uint64_t run_seed, std::uint64_t generation, std::uint64_t individual, Purpose purpose)
    : Rng(derive_seed(run_seed, generation, individual, purpose)) {}

std::uint64_t Rng::next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
}

double Rng::uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

std::uint64_t Rng::below(std::uint64_t n) {
    // multiply-shift with rejection of the biased low products
    uint128 m = static_cast<uint128>(next()) * n;
    auto low = static_cast<std::uint64_t>(m);
    if (low < n) {
        const std::uint64_t threshold = (0 - n) % n;
        while (low < threshold) {
            m = static_cast<uint128>(next()) * n;
            low = static_cast<std::uint64_t>(m);
        }
    }
    return static_cast<std::uint64_t>(m >> 64);
}

std::uint64_t fresh_seed() {
    std::random_device device;
    return (static_cast<std::uint64_t>(device()) << 32) ^ device();
}

}  // namespace stepstone
