#include "sim/step_csv.hpp"

#include <cstdio>

namespace stepstone::sim {

StepCsvWriter::StepCsvWriter(std::ostream& out) : out_(out) {
    out_ << "start,step,x,y,heading";
    for (const char* name : channel_names()) out_ << ',' << name;
    out_ << ",carrying_after,balls\n";
}

void StepCsvWriter::operator()(const StepView& view) {
    char buffer[64];
    out_ << view.start + 1 << ',' << view.step;  // starts 1 to K, as render --start numbers them
    for (double v : {view.pose.x, view.pose.y, view.pose.heading}) {
        std::snprintf(buffer, sizeof buffer, ",%.17g", v);
        out_ << buffer;
    }
    for (int i = 0; i < kInputs; ++i) write_float(view.inputs[i]);
    for (int i = 0; i < kOutputs; ++i) write_float(view.outputs[i]);
    out_ << ',' << (view.carrying ? 1 : 0) << ',' << view.balls << '\n';
}

void StepCsvWriter::write_float(float value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, ",%.9g", static_cast<double>(value));
    out_ << buffer;
}

}  // namespace stepstone::sim
