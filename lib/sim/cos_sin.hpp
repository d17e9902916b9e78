#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include "core/portable_math.hpp"

namespace stepstone::sim {

/// cos and sin of an angle, as std::cos and std::sin give them (or
/// portable::sincos, in a run whose config says "math": "portable").
struct CosSin {
    double c = 1.0;
    double s = 0.0;
};

/// std::cos and std::sin of the last angle asked, compared bit for bit;
/// starts with those of +0.
struct CosSinMemo {
    std::uint64_t bits = 0;
    CosSin value;

    CosSin get(double angle, bool portable) {
        const auto angle_bits = std::bit_cast<std::uint64_t>(angle);
        if (bits != angle_bits) {
            value = compute(angle, portable);
            bits = angle_bits;
        }
        return value;
    }

    static CosSin compute(double angle, bool portable) {
        return portable ? compute<true>(angle) : compute<false>(angle);
    }

    /// The same with the kind known at compile time: the libm path compiles
    /// as it did before the portable functions existed.
    template <bool Portable>
    static CosSin compute(double angle) {
        if constexpr (Portable) {
            CosSin both;
            portable::sincos(angle, both.s, both.c);
            return both;
        } else {
            return {std::cos(angle), std::sin(angle)};
        }
    }
};

/// The memos of one evaluation: the heading (odometry and sensors) and the
/// arc angle of the last curved move (a controller holding or saturating its
/// outputs turns by the same angle step after step).
struct CosSinMemos {
    CosSinMemo heading;
    CosSinMemo turn;
    /// the evaluation's functions: portable::sincos, else std::cos and std::sin
    bool portable = false;
};

namespace detail {
// both constant-initialised, so that reading them is a plain thread-local load (an initialiser
// such as &thread_memos would put a guard check on every read, several times a step)
inline thread_local CosSinMemos thread_memos;
inline thread_local CosSinMemos* current_memos = nullptr;
}  // namespace detail

/// The memos cos_sin() and move_pose() use on this thread: those of the
/// evaluation a CosSinMemoScope names, else the thread's own.
inline CosSinMemos& current_memos() {
    CosSinMemos* const scoped = detail::current_memos;
    return scoped != nullptr ? *scoped : detail::thread_memos;
}

/// Makes `memos` the calling thread's memos until the scope ends (then the
/// previous ones again): an Episode's step uses its own, so that evaluations
/// stepped in turn on one thread (lanes of policies) keep their repeats.
class CosSinMemoScope {
public:
    explicit CosSinMemoScope(CosSinMemos& memos) : previous_(detail::current_memos) {
        detail::current_memos = &memos;
    }
    ~CosSinMemoScope() { detail::current_memos = previous_; }
    CosSinMemoScope(const CosSinMemoScope&) = delete;
    CosSinMemoScope& operator=(const CosSinMemoScope&) = delete;

private:
    CosSinMemos* previous_;
};

/// std::atan2(y, x), or portable::atan2 in an evaluation whose config says
/// "math": "portable" (the current memos say which): the simulator's one other
/// function of the math library, in the bumpers' rare fallback to bearings
/// (Arena::contact). Every call of lib/sim goes through here or a memo.
inline double evaluation_atan2(double y, double x) {
    return current_memos().portable ? portable::atan2(y, x) : std::atan2(y, x);
}

/// std::cos and std::sin of `angle`, remembering the last angle asked in the
/// current memos: the odometry of a straight move and the sensors at the
/// pose it reaches ask for the same heading. The memo holds the exact values
/// (the angle is compared bit for bit), so results never depend on it, and
/// each thread has its own.
inline CosSin cos_sin(double angle) {
    CosSinMemos& memos = current_memos();
    return memos.heading.get(angle, memos.portable);
}

}  // namespace stepstone::sim
