#include "nn/activation.hpp"

#include <cmath>

namespace stepstone::nn {

double sigmoid_exact(double scaled_bias, double sum) { return 1.0 / (1.0 + std::exp(scaled_bias - sum)); }

}  // namespace stepstone::nn
