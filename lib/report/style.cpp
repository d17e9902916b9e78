#include "report/style.hpp"

#include <algorithm>
#include <array>

namespace stepstone::report {

Colour series_colour(int index) {
    static constexpr std::array<Colour, 7> palette{kBlue, kVermillion, kGreen, kOrange, kSkyBlue, kPurple, kBlack};
    const auto n = static_cast<int>(palette.size());
    return palette[static_cast<std::size_t>(((index % n) + n) % n)];
}

Colour saliency_colour(double t) {
    t = std::clamp(t, 0.0, 1.0);
    if (!(t == t)) t = 0.0;  // NaN
    return {1.0 + (kSaliencyHigh.r - 1.0) * t, 1.0 + (kSaliencyHigh.g - 1.0) * t, 1.0 + (kSaliencyHigh.b - 1.0) * t};
}

}  // namespace stepstone::report
