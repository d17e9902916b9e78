#pragma once

namespace stepstone::sim {

/// cos and sin of an angle, as std::cos and std::sin give them.
struct CosSin {
    double c = 1.0;
    double s = 0.0;
};

/// std::cos and std::sin of `angle`, remembering the last angle asked on the
/// calling thread: the odometry of a straight move and the sensors at the
/// pose it reaches ask for the same heading. The memo holds the exact values
/// (the angle is compared bit for bit), so results never depend on it, and
/// each thread has its own.
CosSin cos_sin(double angle);

}  // namespace stepstone::sim
