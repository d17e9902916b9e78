#pragma once

#include <ostream>

#include "sim/episode.hpp"

namespace stepstone::sim {

/// An episode observer that writes one CSV row per step: start, step, x, y,
/// heading, the 12 inputs and 3 outputs (named by channel_names()), the
/// carrying flag after the step's action and the balls scored so far.
/// Doubles are written with 17 significant digits and floats with 9, so the
/// text round-trips and identical runs give identical files.
class StepCsvWriter {
public:
    /// Writes the header line. `out` must outlive the writer.
    explicit StepCsvWriter(std::ostream& out);
    void operator()(const StepView& view);

private:
    void write_float(float value);
    std::ostream& out_;
};

}  // namespace stepstone::sim
