#pragma once

#include <array>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "sim/robot.hpp"

namespace stepstone::sim {

/// An axis-aligned wall box [x0, x1) x [y0, y1), in units.
struct WallBox {
    double x0 = 0.0;
    double y0 = 0.0;
    double x1 = 0.0;
    double y1 = 0.0;
    std::string name;

    bool operator==(const WallBox&) const = default;
};

/// A point of the arena, in units.
struct Point {
    double x = 0.0;
    double y = 0.0;

    bool operator==(const Point&) const = default;
};

/// The basket: a logical disc (releases within it score) and the lights that show it.
struct Basket {
    Point centre;
    double radius = 0.0;
    std::vector<Point> lights;

    bool operator==(const Basket&) const = default;
};

/// Most walls an arena holds, the door included (the hot path's fixed slots, sim/arena.hpp).
inline constexpr std::size_t kMaxWalls = 12;
/// Most balls an arena holds: balls, basket lights and the switch share 16 light bits.
inline constexpr std::size_t kMaxBalls = 8;
/// Most basket lights.
inline constexpr std::size_t kMaxBasketLights = 6;

/// Everything the two task families need to know of an arena (docs/simulator.md:
/// arenas as data): walls, the door the source task's switch opens, the balls
/// (the source task lights them all; the target task spawns `target_ball`), the
/// switch, the basket and the three start poses. Units as in sim/units.hpp: the
/// map is kMapSize wide and high, origin top-left, y down, angles clockwise.
struct ArenaSpec {
    std::string name;
    std::vector<WallBox> walls;   ///< fixed walls (at most kMaxWalls - 1)
    WallBox door;                 ///< a wall while closed (source task, until the switch is pressed)
    std::vector<Point> balls;     ///< 1 to kMaxBalls; their count x starts divides the reward
    std::size_t target_ball = 0;  ///< index into balls: where the target task's ball appears
    Point switch_light;
    Basket basket;
    std::array<Pose, 3> starts{};  ///< start poses, in order

    bool operator==(const ArenaSpec&) const = default;

    /// Strict parse (the format of docs/simulator.md): unknown keys, wrong
    /// types and bad values throw ConfigError naming `source` and the key,
    /// e.g. "walls[3]: x1 (700) is outside the map [0, 600]", a start pose whose
    /// robot disc meets a wall, two objects closer than the robot's reach.
    static ArenaSpec from_json(const nlohmann::json& json, std::string_view source = "arena");
    /// The spec as from_json reads it (every key; doubles round-trip exactly).
    nlohmann::json to_json() const;
    /// The same as an arena file's text: one wall a line, numbers written so
    /// that they read back exactly (examples/arenas/paper.json is this of the paper's).
    std::string to_text() const;
    /// Reads and parses an arena file; ConfigError names the file.
    static ArenaSpec load(const std::filesystem::path& path);

    /// Throws ConfigError (naming the key) unless the spec is usable: see from_json.
    void validate() const;
};

/// The paper's arena (collectball's arena2.pbm, docs/original.md: arena and objects):
/// the default of every task. to_json() of it is examples/arenas/paper.json.
const ArenaSpec& paper_arena();
/// A shared copy of paper_arena().
std::shared_ptr<const ArenaSpec> shared_paper_arena();

}  // namespace stepstone::sim
