// NSGA-II on ZDT1 (Zitzler, Deb, Thiele 2000) with a real-vector genome, SBX
// crossover and polynomial mutation: lib/evo's selection steps, which also evolve
// the DNN controllers, driven by this example's nsga2.hpp, on a problem with a
// known front.
//
// usage: zdt1 [--generations G] [--seed S] [--min-hypervolume H]
// prints the hypervolume of the final first front w.r.t. (1, 1); the true
// front f2 = 1 - sqrt(f1) has hypervolume 1 - 1/3 = 2/3. Exit 1 if the value
// is below --min-hypervolume.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/rng.hpp"
#include "evo/pareto.hpp"
#include "nsga2.hpp"

namespace {

using stepstone::Rng;

constexpr std::size_t kVariables = 30;

// Deb's SBX and bounded polynomial mutation on [0, 1]^30 (Deb & Agrawal 1995,
// as in the NSGA-II reference code); ZDT1 is minimised, NSGA-II maximises, so
// the objectives are negated
struct Zdt1 {
    using Genome = std::vector<double>;

    double crossover_rate = 0.9;
    double crossover_eta = 15.0;
    double mutation_eta = 20.0;

    Genome random_genome(Rng& rng) const {
        Genome genome(kVariables);
        for (auto& x : genome) x = rng.uniform();
        return genome;
    }

    std::vector<double> evaluate(const Genome& x) const {
        const double f1 = x[0];
        double rest = 0.0;
        for (std::size_t i = 1; i < x.size(); ++i) rest += x[i];
        const double g = 1.0 + 9.0 * rest / static_cast<double>(x.size() - 1);
        const double f2 = g * (1.0 - std::sqrt(f1 / g));
        return {-f1, -f2};
    }

    void crossover(const Genome& a, const Genome& b, Genome& c, Genome& d, Rng& rng) const {
        c = a;
        d = b;
        if (!rng.bernoulli(crossover_rate)) return;
        for (std::size_t i = 0; i < a.size(); ++i) {
            if (!rng.bernoulli(0.5) || std::abs(a[i] - b[i]) < 1e-14) continue;
            const double y1 = std::min(a[i], b[i]), y2 = std::max(a[i], b[i]);
            const double u = rng.uniform();
            // spread factor for each child, bounded so it stays in [0, 1]
            const auto beta_q = [&](double beta) {
                const double alpha = 2.0 - std::pow(beta, -(crossover_eta + 1.0));
                return u <= 1.0 / alpha ? std::pow(u * alpha, 1.0 / (crossover_eta + 1.0))
                                        : std::pow(1.0 / (2.0 - u * alpha), 1.0 / (crossover_eta + 1.0));
            };
            const double low = 0.5 * (y1 + y2 - beta_q(1.0 + 2.0 * y1 / (y2 - y1)) * (y2 - y1));
            const double high = 0.5 * (y1 + y2 + beta_q(1.0 + 2.0 * (1.0 - y2) / (y2 - y1)) * (y2 - y1));
            c[i] = std::clamp(low, 0.0, 1.0);
            d[i] = std::clamp(high, 0.0, 1.0);
            if (rng.bernoulli(0.5)) std::swap(c[i], d[i]);
        }
    }

    void mutate(Genome& x, Rng& rng) const {
        const double rate = 1.0 / static_cast<double>(x.size());
        const double power = 1.0 / (mutation_eta + 1.0);
        for (auto& v : x) {
            if (!rng.bernoulli(rate)) continue;
            const double u = rng.uniform();
            const double delta = u < 0.5 ? std::pow(2.0 * u + (1.0 - 2.0 * u) * std::pow(1.0 - v, mutation_eta + 1.0), power) - 1.0
                                         : 1.0 - std::pow(2.0 * (1.0 - u) + 2.0 * (u - 0.5) * std::pow(v, mutation_eta + 1.0), power);
            v = std::clamp(v + delta, 0.0, 1.0);
        }
    }
};

// area dominated by the minimisation points (f1, f2) inside the box up to (1, 1)
double hypervolume(std::vector<std::pair<double, double>> points) {
    std::sort(points.begin(), points.end());
    double area = 0.0, ceiling = 1.0;
    for (const auto& [f1, f2] : points) {
        if (f1 >= 1.0 || f2 >= ceiling) continue;
        area += (1.0 - f1) * (ceiling - f2);
        ceiling = f2;
    }
    return area;
}

}  // namespace

int main(int argc, char** argv) {
    long generations = 250;
    unsigned long long seed = 1;
    double min_hypervolume = 0.0;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string flag = argv[i];
        if (flag == "--generations") generations = std::strtol(argv[i + 1], nullptr, 10);
        else if (flag == "--seed") seed = std::strtoull(argv[i + 1], nullptr, 10);
        else if (flag == "--min-hypervolume") min_hypervolume = std::strtod(argv[i + 1], nullptr);
        else {
            std::fprintf(stderr, "zdt1: unknown flag %s\n", flag.c_str());
            return 2;
        }
    }

    const example::Nsga2<Zdt1> ea(Zdt1{}, 100, seed);
    auto population = ea.initialise();
    for (long g = 0; g < generations; ++g) ea.epoch(population);

    std::vector<std::pair<double, double>> front;
    const auto fronts = stepstone::evo::non_dominated_fronts(population.objectives);
    for (std::size_t i : fronts[0]) {
        front.emplace_back(-population.objectives[i][0], -population.objectives[i][1]);
    }
    const double hv = hypervolume(front);
    std::printf("generations %ld, evaluations %llu, first front %zu points, hypervolume %.6f (true front 0.666667)\n",
                generations, static_cast<unsigned long long>(population.evaluations), front.size(), hv);
    return hv >= min_hypervolume ? 0 : 1;
}
