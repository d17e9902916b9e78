#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>

#include "core/rng.hpp"
#include "sim/arena.hpp"
#include "sim/cos_sin.hpp"
#include "sim/sensors.hpp"
#include "sim/task.hpp"
#include "sim/units.hpp"

using namespace stepstone::sim;

// The hot path's shortcuts must never change an answer: each is checked
// against the plain query it replaces, bit for bit.

// A lane count of 1 to 32 and each lane's door (bit l: open), drawn in that order.
struct LaneDraw {
    std::size_t count;
    std::uint32_t door_open;
};
LaneDraw draw_lanes(stepstone::Rng& rng) {
    const std::size_t count = 1 + static_cast<std::size_t>(rng.below(32));
    return {count, static_cast<std::uint32_t>(rng.below(1ull << 32))};
}

// Runs `check` with the AVX2 kernels off, then on where the CPU has AVX2.
template <class Check>
void with_each_kernel(Check&& check) {
    const bool initial = avx2_kernels();
    for (const bool avx2 : {false, true}) {
        set_avx2_kernels(avx2);
        check();
    }
    set_avx2_kernels(initial);
}

TEST_CASE("three rays at once read exactly what three single rays read", "[sim][arena][fast]") {
    with_each_kernel([] {
        const Arena arena;
        stepstone::Rng rng(7);
        for (int i = 0; i < 20'000; ++i) {
            const double x = rng.uniform(-20.0, 620.0);
            const double y = rng.uniform(-20.0, 420.0);
            double directions[3][2];
            for (auto& d : directions) {
                // every fourth ray along an axis: the zero-component guard
                const double a = i % 4 == 0 ? static_cast<double>(rng.below(4)) * kPi / 2 : rng.uniform(-kPi, kPi);
                d[0] = std::cos(a);
                d[1] = std::sin(a);
                if (i % 4 == 0) d[static_cast<std::size_t>(rng.below(2))] = 0.0;
            }
            const bool door_open = rng.bernoulli(0.5);
            double together[3];
            arena.ray_distances(x, y, directions, kLaserRange, door_open, together);
            for (std::size_t r = 0; r < 3; ++r) {
                const double alone =
                    arena.ray_distance(x, y, directions[r][0], directions[r][1], kLaserRange, door_open);
                REQUIRE(std::bit_cast<std::uint64_t>(together[r]) == std::bit_cast<std::uint64_t>(alone));
            }
        }
    });
}

TEST_CASE("the SSE2 and AVX2 kernels of sense read the same bits", "[sim][sensors][fast]") {
    const auto task = make_task(TaskConfig{});
    stepstone::Rng rng(17);
    for (int i = 0; i < 50'000; ++i) {
        const Pose pose{rng.uniform(-30.0, 630.0), rng.uniform(-30.0, 430.0),
                        i % 5 == 0 ? static_cast<double>(rng.below(8)) * kPi / 4 - kPi : rng.uniform(-kPi, kPi)};
        WorldState state;
        state.door_open = rng.bernoulli(0.5);
        state.lit = i % 2 == 0 ? task->initial_lit() : static_cast<std::uint32_t>(rng.below(1u << 13));
        SensorReadings readings[2];
        const bool initial = avx2_kernels();
        for (const bool avx2 : {false, true}) {
            set_avx2_kernels(avx2);
            sense(task->arena(), task->sight(), pose, state, readings[avx2 ? 1 : 0]);
        }
        set_avx2_kernels(initial);
        for (std::size_t r = 0; r < 3; ++r) {
            REQUIRE(std::bit_cast<std::uint64_t>(readings[0].laser[r]) ==
                    std::bit_cast<std::uint64_t>(readings[1].laser[r]));
        }
        REQUIRE(readings[0].light == readings[1].light);
        // and the plain overload, which tests every wall of every sight line
        SensorReadings plain;
        sense(task->arena(), task->lights(), pose, state, plain);
        REQUIRE(readings[0].light == plain.light);
    }
}

TEST_CASE("sight-table cells: clear lights are never blocked, hidden lights always are", "[sim][sensors][fast]") {
    for (const TaskKind kind : {TaskKind::source, TaskKind::target}) {
        TaskConfig config;
        config.kind = kind;
        const auto task = make_task(config);
        const Arena& arena = task->arena();
        const SightTable& sight = task->sight();
        const auto lights = sight.lights();
        stepstone::Rng rng(11);
        int hidden = 0;
        int clear = 0;
        for (int i = 0; i < 50'000; ++i) {
            const double x = rng.uniform(0.0, 600.0);
            const double y = rng.uniform(0.0, 400.0);
            const bool door_open = rng.bernoulli(0.5);
            const SightTable::Cell cell = sight.cell(x, y, door_open);
            REQUIRE((cell.clear & cell.hidden) == 0u);
            for (std::size_t l = 0; l < lights.size(); ++l) {
                const bool blocked = arena.segment_blocked(lights[l].x, lights[l].y, x, y, door_open);
                if ((cell.hidden >> l) & 1u) {
                    ++hidden;
                    REQUIRE(blocked);
                }
                if ((cell.clear >> l) & 1u) {
                    ++clear;
                    REQUIRE_FALSE(blocked);
                }
                REQUIRE(cell.walls[l] == sight.candidates(l, x, y));
            }
        }
        // both shortcuts matter: each settles a good share of the sight lines
        CHECK(hidden > 50'000);
        CHECK(clear > 50'000);
    }
}

TEST_CASE("sight-table reach candidates hold every light within reach", "[sim][sensors][fast]") {
    for (const TaskKind kind : {TaskKind::source, TaskKind::target}) {
        TaskConfig config;
        config.kind = kind;
        const auto task = make_task(config);
        const SightTable& sight = task->sight();
        const auto lights = sight.lights();
        stepstone::Rng rng(12);
        int within = 0;
        int filtered = 0;
        const auto check = [&](double x, double y) {
            const std::uint32_t candidates = sight.reach_candidates(x, y);
            for (std::size_t l = 0; l < lights.size(); ++l) {
                const double dx = x - lights[l].x;
                const double dy = y - lights[l].y;
                if (dx * dx + dy * dy < kReach * kReach) {
                    ++within;
                    REQUIRE(((candidates >> l) & 1u) != 0);
                } else if (((candidates >> l) & 1u) == 0) {
                    ++filtered;
                }
            }
        };
        for (const Light& light : lights) {
            for (int i = 0; i < 20'000; ++i) {
                // around the light, often exactly on a cell's edge or just below it
                double x = light.x + rng.uniform(-21.0, 21.0);
                double y = light.y + rng.uniform(-21.0, 21.0);
                if (rng.bernoulli(0.3)) x = std::round(x / SightTable::kCell) * SightTable::kCell;
                if (rng.bernoulli(0.3))
                    y = std::nextafter(std::round(y / SightTable::kCell) * SightTable::kCell, 0.0);
                check(x, y);
            }
        }
        for (const double x : {-5.0, 0.0, 599.999, 600.0, 700.0}) check(x, 20.0);
        CHECK(sight.reach_candidates(-1.0, 50.0) == ~0u);
        CHECK(within > 10'000);
        CHECK(filtered > 10'000);
        // and it is a filter: at a point drawn anywhere in the arena, few lights are candidates
        // (a light's candidate cells cover some 3,000 of the 240,000 square units)
        int candidates = 0;
        const std::uint32_t all = (1u << lights.size()) - 1u;
        for (int i = 0; i < 10'000; ++i) {
            candidates +=
                std::popcount(sight.reach_candidates(rng.uniform(0.0, 600.0), rng.uniform(0.0, 400.0)) & all);
        }
        CHECK(candidates < 10'000 / 2);
    }
}

TEST_CASE("the heading memo gives std::cos and std::sin bit for bit", "[sim][robot][fast]") {
    stepstone::Rng rng(3);
    for (int i = 0; i < 10'000; ++i) {
        const double angle = i % 3 == 0 ? 0.0 : rng.uniform(-4.0, 4.0);
        for (int repeat = 0; repeat < 2; ++repeat) {
            const CosSin v = cos_sin(angle);
            REQUIRE(std::bit_cast<std::uint64_t>(v.c) == std::bit_cast<std::uint64_t>(std::cos(angle)));
            REQUIRE(std::bit_cast<std::uint64_t>(v.s) == std::bit_cast<std::uint64_t>(std::sin(angle)));
        }
    }
    // -0 and +0 have the same cosine but sines of opposite signs
    CHECK(std::signbit(cos_sin(0.0).s) == false);
    CHECK(std::signbit(cos_sin(-0.0).s) == true);
}

TEST_CASE("evaluation_atan2 is glibc's, or the portable one inside a portable evaluation's scope",
          "[sim][arena][math]") {
    stepstone::Rng rng(5);
    int differing = 0;
    for (int i = 0; i < 2'000; ++i) {
        const double y = rng.uniform(-50.0, 50.0);
        const double x = rng.uniform(-50.0, 50.0);
        const double libm = std::atan2(y, x);
        const double own = stepstone::portable::atan2(y, x);
        differing += libm != own;
        REQUIRE(std::bit_cast<std::uint64_t>(evaluation_atan2(y, x)) == std::bit_cast<std::uint64_t>(libm));
        CosSinMemos memos;
        memos.portable = true;
        const CosSinMemoScope scope(memos);
        REQUIRE(std::bit_cast<std::uint64_t>(evaluation_atan2(y, x)) == std::bit_cast<std::uint64_t>(own));
    }
    // the two functions must differ somewhere for the checks above to tell them apart
    CHECK(differing > 100);
}

TEST_CASE("contact far off the map falls back to every wall and agrees with the overlap test", "[sim][arena][fast]") {
    const Arena arena;
    stepstone::Rng rng(5);
    for (int i = 0; i < 20'000; ++i) {
        const Pose pose{rng.uniform(-30.0, 630.0), rng.uniform(-30.0, 430.0), rng.uniform(-kPi, kPi)};
        const bool door_open = rng.bernoulli(0.5);
        REQUIRE(arena.contact(pose, door_open).hit == arena.disc_overlaps(pose.x, pose.y, door_open));
    }
    const Contact far = arena.contact(Pose{2e4, 2e4, 0.0}, false);
    CHECK_FALSE(far.hit);
    CHECK_FALSE(far.left);
    CHECK_FALSE(far.right);
}

TEST_CASE("bumpers from segment tests and from the quarters' signs equal those from atan2 bearings",
          "[sim][arena][fast]") {
    const Arena arena;
    const auto walls = arena.walls();
    stepstone::Rng rng(13);
    int contacts = 0;
    int left = 0;
    int right = 0;
    for (int i = 0; i < 300'000; ++i) {
        // near an edge or a corner of a random wall
        const WallBox& wall = walls[static_cast<std::size_t>(rng.below(walls.size()))];
        Pose pose{rng.uniform(wall.x0 - 21.0, wall.x1 + 21.0), rng.uniform(wall.y0 - 21.0, wall.y1 + 21.0), 0.0};
        if (i % 5 == 0) pose.x = (rng.bernoulli(0.5) ? wall.x0 : wall.x1) + rng.uniform(-21.0, 21.0);
        if (i % 5 == 1) pose.y = (rng.bernoulli(0.5) ? wall.y0 : wall.y1) + rng.uniform(-21.0, 21.0);
        switch (i % 4) {
        case 0:  // any heading
            pose.heading = rng.uniform(-kPi, kPi);
            break;
        case 1:  // along an axis or a diagonal: vertices on a quarter's edge
            pose.heading = normalize_angle(static_cast<double>(rng.below(8)) * kPi / 4);
            break;
        case 2: {  // towards a corner of the wall, or square to it, give or take a little
            const double cx = rng.bernoulli(0.5) ? wall.x0 : wall.x1;
            const double cy = rng.bernoulli(0.5) ? wall.y0 : wall.y1;
            const double jitter = rng.bernoulli(0.5) ? 0.0 : rng.uniform(-1e-8, 1e-8);
            pose.heading = normalize_angle(std::atan2(cy - pose.y, cx - pose.x) +
                                           static_cast<double>(rng.below(4)) * kPi / 2 + jitter);
            break;
        }
        default:  // a tiny angle either side of an axis
            pose.heading = normalize_angle(static_cast<double>(rng.below(4)) * kPi / 2 + rng.uniform(-1e-9, 1e-9));
            break;
        }
        if (i % 7 == 0) pose.y = wall.y0 - (20.0 - std::ldexp(1.0, -static_cast<int>(rng.below(40))));  // grazing
        const bool door_open = rng.bernoulli(0.5);
        const Contact fast = arena.contact(pose, door_open);
        const Contact exact = arena.contact_by_angles(pose, door_open);
        const Contact quarters = arena.contact_by_quarters(pose, door_open);
        INFO("pose (" << pose.x << ", " << pose.y << ", " << pose.heading << "), door open " << door_open);
        REQUIRE(fast.hit == exact.hit);
        REQUIRE(fast.left == exact.left);
        REQUIRE(fast.right == exact.right);
        REQUIRE(quarters.left == exact.left);
        REQUIRE(quarters.right == exact.right);
        contacts += fast.hit ? 1 : 0;
        left += fast.left ? 1 : 0;
        right += fast.right ? 1 : 0;
    }
    CHECK(contacts > 100'000);
    CHECK(left > 30'000);
    CHECK(right > 30'000);
}

TEST_CASE("bumpers of a disc that barely overlaps a wall's corner seen almost along a quarter's edge",
          "[sim][arena][fast]") {
    // the overlap region is a sliver around the corner, the closest point; the heading puts the
    // corner within a hair of the forward, left or right radius: the segment tests' margins
    const Arena arena;
    int hits = 0;
    int sides_differ = 0;  // contacts whose two bumpers differ: the margins decided something
    for (const WallBox& wall : arena.walls()) {
        for (const double cx : {wall.x0, wall.x1}) {
            for (const double cy : {wall.y0, wall.y1}) {
                const double ox = cx == wall.x0 ? -1.0 : 1.0;  // away from the box, diagonally
                const double oy = cy == wall.y0 ? -1.0 : 1.0;
                for (const double depth : {1e-13, 1e-11, 1e-9, 1e-7, 1e-5, 1e-3, 0.1}) {
                    const double reach = (kRobotRadius - depth) / std::sqrt(2.0);
                    Pose pose{cx + ox * reach, cy + oy * reach, 0.0};
                    const double towards = std::atan2(cy - pose.y, cx - pose.x);
                    for (int quarter = -1; quarter <= 1; ++quarter) {
                        for (const double tilt : {-1e-5, -1e-6, -3e-7, -1e-7, -1e-8, -1e-10, 0.0, 1e-10, 1e-8,
                                                  1e-7, 3e-7, 1e-6, 1e-5}) {
                            pose.heading = normalize_angle(towards + quarter * kPi / 2 + tilt);
                            const Contact fast = arena.contact(pose, false);
                            const Contact exact = arena.contact_by_angles(pose, false);
                            INFO("corner (" << cx << ", " << cy << "), depth " << depth << ", quarter "
                                            << quarter << ", tilt " << tilt);
                            REQUIRE(fast.hit == exact.hit);
                            REQUIRE(fast.left == exact.left);
                            REQUIRE(fast.right == exact.right);
                            hits += exact.hit ? 1 : 0;
                            sides_differ += exact.left != exact.right ? 1 : 0;
                        }
                    }
                }
            }
        }
    }
    CHECK(hits > 1'000);
    CHECK(sides_differ > 100);
}

TEST_CASE("disc overlaps of many centres at once equal one at a time, each lane with its own door",
          "[sim][arena][fast][lanes]") {
    with_each_kernel([] {
        const Arena arena;
        stepstone::Rng rng(23);
        long overlaps = 0;
        long door_answers_differ = 0;  // centres where the door's state changes the answer
        long bumpers = 0;
        for (int round = 0; round < 4'000; ++round) {
            const auto [count, door_open] = draw_lanes(rng);
            double xs[32];
            double ys[32];
            for (std::size_t l = 0; l < count; ++l) {
                // near a wall's box (the door's in a quarter of the lanes): inside, touching and clear of it
                const auto walls = arena.walls();
                const WallBox& box = l % 4 == 0 ? walls[static_cast<std::size_t>(arena.door_index())]
                                                : walls[static_cast<std::size_t>(rng.below(walls.size()))];
                xs[l] = rng.uniform(box.x0 - 30.0, box.x1 + 30.0);
                ys[l] = rng.uniform(box.y0 - 30.0, box.y1 + 30.0);
            }
            std::uint32_t near[32];
            const std::uint32_t bits = arena.disc_overlaps_lanes(xs, ys, door_open, count, near);
            REQUIRE(bits == arena.disc_overlaps_lanes(xs, ys, door_open, count));
            for (std::size_t l = 0; l < count; ++l) {
                const bool open = ((door_open >> l) & 1u) != 0;
                const bool alone = arena.disc_overlaps(xs[l], ys[l], open);
                REQUIRE(((bits >> l) & 1u) == (alone ? 1u : 0u));
                if (alone) {
                    // the bumpers from the lanes' near walls are contact()'s
                    const Pose pose{xs[l], ys[l], rng.uniform(-kPi, kPi)};
                    const Contact exact = arena.contact(pose, open);
                    const Contact lanes = arena.contact_of_overlap(pose, open, near[l]);
                    REQUIRE(lanes.hit);
                    REQUIRE(lanes.left == exact.left);
                    REQUIRE(lanes.right == exact.right);
                    bumpers += (exact.left ? 1 : 0) + (exact.right ? 1 : 0);
                }
                overlaps += alone ? 1 : 0;
                door_answers_differ += alone != arena.disc_overlaps(xs[l], ys[l], !open) ? 1 : 0;
            }
            REQUIRE((count == 32 || (bits >> count) == 0));  // no bit past the lanes
        }
        CHECK(overlaps > 10'000);
        CHECK(door_answers_differ > 1'000);
        CHECK(bumpers > 5'000);
    });
}

TEST_CASE("moves of many lanes at once equal portable move_pose, bit for bit, both widths",
          "[sim][robot][fast][lanes]") {
    with_each_kernel([] {
        stepstone::Rng rng(29);
        CosSinMemos memos;
        memos.portable = true;
        const CosSinMemoScope scope(memos);
        long straight = 0;
        long wrapped = 0;
        for (int round = 0; round < 4'000; ++round) {
            MoveLanes lanes;
            lanes.count = 1 + static_cast<std::size_t>(rng.below(32));
            for (std::size_t l = 0; l < lanes.count; ++l) {
                lanes.x[l] = rng.uniform(0.0, 600.0);
                lanes.y[l] = rng.uniform(0.0, 400.0);
                // a sixth of the headings next to +-pi, where a turn wraps
                lanes.heading[l] = l % 6 == 0 ? (rng.bernoulli(0.5) ? kPi : -kPi) + rng.uniform(-0.2, 0.2)
                                              : rng.uniform(-kPi, kPi);
                lanes.heading[l] = normalize_angle(lanes.heading[l]);
                // saturated, equal (straight) and free outputs
                const auto output = [&] {
                    const auto kind = rng.below(3);
                    return kind == 0 ? static_cast<float>(rng.below(2)) : static_cast<float>(rng.uniform());
                };
                lanes.left[l] = output();
                lanes.right[l] = rng.bernoulli(0.2) ? lanes.left[l] : output();
            }
            move_lanes(lanes);
            for (std::size_t l = 0; l < lanes.count; ++l) {
                const Pose pose{lanes.x[l], lanes.y[l], lanes.heading[l]};
                const Pose next = move_pose(pose, wheel_step(lanes.left[l]), wheel_step(lanes.right[l]));
                const auto same = [](double a, double b) {
                    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
                };
                REQUIRE(same(lanes.next_x[l], next.x));
                REQUIRE(same(lanes.next_y[l], next.y));
                REQUIRE(same(lanes.next_heading[l], next.heading));
                double s = 0.0;
                double c = 0.0;
                stepstone::portable::sincos(next.heading, s, c);
                REQUIRE(same(lanes.next_cos[l], c));
                REQUIRE(same(lanes.next_sin[l], s));
                straight += lanes.left[l] == lanes.right[l] ? 1 : 0;
                wrapped += std::fabs(next.heading - pose.heading) > kPi ? 1 : 0;  // crossed +-pi
            }
        }
        CHECK(straight > 5'000);
        CHECK(wrapped > 1'000);
    });
}

TEST_CASE("rays of many lanes at once read exactly what single rays read, each lane with its own door",
          "[sim][arena][fast][lanes]") {
    with_each_kernel([] {
        const Arena arena;
        stepstone::Rng rng(31);
        long hits = 0;
        for (int round = 0; round < 3'000; ++round) {
            const auto [count, door_open] = draw_lanes(rng);
            double xs[32];
            double ys[32];
            double dir_x[3][32];
            double dir_y[3][32];
            double distances[3][32];
            for (std::size_t l = 0; l < count; ++l) {
                xs[l] = rng.uniform(-20.0, 620.0);
                ys[l] = rng.uniform(-20.0, 420.0);
                for (std::size_t r = 0; r < 3; ++r) {
                    // every fourth ray along an axis: the zero-component guard
                    const double a =
                        l % 4 == 0 ? static_cast<double>(rng.below(4)) * kPi / 2 : rng.uniform(-kPi, kPi);
                    dir_x[r][l] = std::cos(a);
                    dir_y[r][l] = std::sin(a);
                    if (l % 4 == 0) (rng.bernoulli(0.5) ? dir_x : dir_y)[r][l] = 0.0;
                }
                if (l % 8 == 4) {
                    // the origin exactly on a wall's edge along a zero component: the offset is 0,
                    // and 0 times an unguarded inverse would be NaN
                    const WallBox& wall =
                        arena.walls()[static_cast<std::size_t>(rng.below(arena.walls().size()))];
                    if (dir_x[0][l] == 0.0) xs[l] = rng.bernoulli(0.5) ? wall.x0 : wall.x1;
                    if (dir_y[0][l] == 0.0) ys[l] = rng.bernoulli(0.5) ? wall.y0 : wall.y1;
                }
            }
            arena.ray_distances_lanes(xs, ys, {dir_x[0], dir_x[1], dir_x[2]}, {dir_y[0], dir_y[1], dir_y[2]},
                                      kLaserRange, door_open, count,
                                      {distances[0], distances[1], distances[2]});
            for (std::size_t l = 0; l < count; ++l) {
                const bool open = ((door_open >> l) & 1u) != 0;
                for (std::size_t r = 0; r < 3; ++r) {
                    const double alone =
                        arena.ray_distance(xs[l], ys[l], dir_x[r][l], dir_y[r][l], kLaserRange, open);
                    REQUIRE(std::bit_cast<std::uint64_t>(distances[r][l]) ==
                            std::bit_cast<std::uint64_t>(alone));
                    hits += alone >= 0.0 ? 1 : 0;
                }
            }
        }
        CHECK(hits > 50'000);
    });
}

TEST_CASE(
    "near masks of many centres at once are the plain single-precision distances, whatever the grid cell",
    "[sim][arena][fast][lanes]") {
    // the reference: every wall's squared distance in float, as near_slots() takes it, below
    // r^2 + 1 (the door a wall unless open); the lanes skip the walls their centres' cells rule out
    const Arena arena;
    const auto walls = arena.walls();
    const auto reference = [&](double x, double y, bool open) {
        std::uint32_t mask = 0;
        const auto cx = static_cast<float>(x);
        const auto cy = static_cast<float>(y);
        for (std::size_t k = 0; k < walls.size(); ++k) {
            if (open && k == static_cast<std::size_t>(arena.door_index())) continue;
            const float ex = std::max(
                std::max(static_cast<float>(walls[k].x0) - cx, cx - static_cast<float>(walls[k].x1)), 0.0f);
            const float ey = std::max(
                std::max(static_cast<float>(walls[k].y0) - cy, cy - static_cast<float>(walls[k].y1)), 0.0f);
            mask |= static_cast<std::uint32_t>(ex * ex + ey * ey <
                                               static_cast<float>(kRobotRadius * kRobotRadius) + 1.0f)
                    << k;
        }
        return mask;
    };
    with_each_kernel([&] {
        stepstone::Rng rng(37);
        long near_bits = 0;
        for (int round = 0; round < 6'000; ++round) {
            const auto [count, door_open] = draw_lanes(rng);
            double xs[32];
            double ys[32];
            for (std::size_t l = 0; l < count; ++l) {
                // about the radius away from a random wall's face or corner, anywhere along it
                const WallBox& box = walls[static_cast<std::size_t>(rng.below(walls.size()))];
                const double distance = rng.uniform(18.0, 21.5);
                const double angle = rng.uniform(-kPi, kPi);
                const double px = rng.uniform(box.x0, box.x1);
                const double py = rng.uniform(box.y0, box.y1);
                switch (rng.below(3)) {
                    case 0:  // off a vertical face
                        xs[l] = rng.bernoulli(0.5) ? box.x0 - distance : box.x1 + distance;
                        ys[l] = py;
                        break;
                    case 1:  // off a horizontal face
                        xs[l] = px;
                        ys[l] = rng.bernoulli(0.5) ? box.y0 - distance : box.y1 + distance;
                        break;
                    default:  // off a corner
                        xs[l] = (rng.bernoulli(0.5) ? box.x0 : box.x1) + distance * std::cos(angle);
                        ys[l] = (rng.bernoulli(0.5) ? box.y0 : box.y1) + distance * std::sin(angle);
                        break;
                }
            }
            std::uint32_t near[32];
            const std::uint32_t bits = arena.disc_overlaps_lanes(xs, ys, door_open, count, near);
            for (std::size_t l = 0; l < count; ++l) {
                const bool open = ((door_open >> l) & 1u) != 0;
                REQUIRE(near[l] == reference(xs[l], ys[l], open));
                REQUIRE(((bits >> l) & 1u) == (arena.disc_overlaps(xs[l], ys[l], open) ? 1u : 0u));
                near_bits += std::popcount(near[l]);
            }
        }
        CHECK(near_bits > 50'000);
    });
}

TEST_CASE("an arena far larger than the map keeps no near grid and overlaps as one centre at a time",
          "[sim][arena][fast][lanes]") {
    ArenaSpec spec = paper_arena();
    spec.walls.push_back(WallBox{1e6, 1e6, 1e6 + 10.0, 1e6 + 10.0, "far away"});  // past any parser's map
    const Arena arena(spec);
    stepstone::Rng rng(41);
    long overlaps = 0;
    for (int round = 0; round < 2'000; ++round) {
        double xs[8];
        double ys[8];
        for (std::size_t l = 0; l < 8; ++l) {
            const bool far = l % 2 == 0;
            xs[l] = far ? rng.uniform(1e6 - 30.0, 1e6 + 40.0) : rng.uniform(-30.0, 630.0);
            ys[l] = far ? rng.uniform(1e6 - 30.0, 1e6 + 40.0) : rng.uniform(-30.0, 430.0);
        }
        const std::uint32_t bits = arena.disc_overlaps_lanes(xs, ys, 0u, 8);
        for (std::size_t l = 0; l < 8; ++l) {
            const bool alone = arena.disc_overlaps(xs[l], ys[l], false);
            REQUIRE(((bits >> l) & 1u) == (alone ? 1u : 0u));
            overlaps += alone ? 1 : 0;
        }
    }
    CHECK(overlaps > 1'000);
}
