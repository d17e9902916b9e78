// Arenas as data: the paper's arena as a file, a second arena's geometry by
// hand, and every refusal of a broken arena in one line naming the key.

#include "sim/arena_spec.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "core/config.hpp"
#include "core/error.hpp"
#include "sim/task.hpp"
#include "sim/units.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using namespace stepstone::sim;
using Catch::Matchers::Contains;
using nlohmann::json;

namespace {

const std::filesystem::path kArenas = std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples" / "arenas";

ArenaSpec two_rooms() { return ArenaSpec::load(kArenas / "two_rooms.json"); }

std::shared_ptr<const Task> task_in(const ArenaSpec& arena, TaskKind kind) {
    TaskConfig config;
    config.kind = kind;
    config.arena = std::make_shared<const ArenaSpec>(arena);
    return make_task(config);
}

// the error from_json gives `edit` applied to the two-rooms file
std::string refusal(const std::function<void(json&)>& edit) {
    json arena = load_json_file(kArenas / "two_rooms.json");
    edit(arena);
    try {
        ArenaSpec::from_json(arena, "broken.json");
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "(accepted)";
}

}  // namespace

TEST_CASE("the shipped paper.json is the built-in paper arena, decoded from the bitmap's pixels",
          "[sim][arena]") {
    const ArenaSpec file = ArenaSpec::load(kArenas / "paper.json");
    CHECK(file == paper_arena());
    // by hand: the door is pixels x 100-102, y 127-173 of the 296 px bitmap of 600 units
    const double s = 600.0 / 296.0;
    CHECK(paper_arena().door.x0 == (100 - 0.5) * s);
    CHECK(paper_arena().door.x1 == (102 + 0.5) * s);
    CHECK(paper_arena().door.y0 == (127 - 0.5) * s);
    CHECK(paper_arena().door.y1 == (173 + 0.5) * s);
    CHECK(paper_arena().walls.size() == 10);
    CHECK(paper_arena().balls.size() == 8);
    // to_text is what the file holds, and both forms read back exactly
    CHECK(paper_arena().to_text() == stepstone::test::read_file(kArenas / "paper.json"));
    CHECK(ArenaSpec::from_json(paper_arena().to_json()) == paper_arena());
    CHECK(ArenaSpec::from_json(json::parse(two_rooms().to_text())) == two_rooms());
}

TEST_CASE("a task in the two-rooms arena has its walls, door, balls, switch and starts", "[sim][arena]") {
    const ArenaSpec arena = two_rooms();
    const auto source = task_in(arena, TaskKind::source);
    const auto target = task_in(arena, TaskKind::target);
    // 8 balls, 4 basket lights, the switch; the target task keeps only ball 5, at (200, 60)
    REQUIRE(source->lights().size() == 13);
    REQUIRE(target->lights().size() == 6);
    CHECK(target->lights()[0].x == 200.0);
    CHECK(target->lights()[0].y == 60.0);
    CHECK(target->lights().back().kind == LightKind::switch_light);
    CHECK(target->lights().back().x == 560.0);
    CHECK(source->reward_divisor() == 24);  // 8 balls x 3 starts
    CHECK(source->start_pose(1).x == 520.0);
    CHECK(source->start_pose(1).heading == -kPi / 2);
    CHECK(source->basket().centre.x == 450.0);

    // by hand, rays from start 1 (380, 180) heading 0: the pillar's left face is at x = 430
    const Arena& walls = source->arena();
    CHECK(walls.walls().size() == 8);
    CHECK(walls.ray_distance(380, 180, 1, 0, kLaserRange, false) == Approx(50.0).margin(1e-3));
    // from (250, 190) to the right: the closed door's face at x = 295; open, the pillar at 430
    CHECK(walls.ray_distance(250, 190, 1, 0, kLaserRange, false) == Approx(45.0).margin(1e-3));
    CHECK(walls.ray_distance(250, 190, 1, 0, kLaserRange, true) == Approx(180.0).margin(1e-3));
    // straight up from (100, 100): the top wall's face at y = 9
    CHECK(walls.ray_distance(100, 100, 0, -1, kLaserRange, false) == Approx(91.0).margin(1e-3));
    CHECK(walls.disc_overlaps(440, 210, false));  // 10 units below the pillar: the disc meets it
    CHECK_FALSE(walls.disc_overlaps(440, 230, false));
}

TEST_CASE("a broken arena is refused in one line naming the key", "[sim][arena][errors]") {
    CHECK_THAT(refusal([](json& a) { a["walls"][2]["box"][2] = 700; }),
               Contains("broken.json: walls[2]: x1 (700) is outside the arena [-20, 620]"));
    CHECK_THAT(refusal([](json& a) {
                   a["walls"][6]["box"] = {900, 900, 950, 950};
               }),
               Contains("walls[6]: x0 (900) is outside the arena"));
    CHECK_THAT(refusal([](json& a) {
                   a["walls"][1]["box"] = {500, 10, 400, 20};
               }),
               Contains("walls[1]: x0 (500) must be below x1 (400)"));
    CHECK_THAT(refusal([](json& a) {
                   a["starts"][0] = {440, 205, 0};
               }),
               Contains("starts[0]: (440, 205) puts the robot inside the wall 'pillar'"));
    CHECK_THAT(refusal([](json& a) {
                   a["starts"][2] = {300, 190, 0};
               }),
               Contains("starts[2]: (300, 190) puts the robot inside the wall 'door'"));
    CHECK_THAT(
        refusal([](json& a) {
            a["switch"] = {525, 65};
        }),
        Contains("switch: overlaps balls[1]: 7.0710678118654755 apart, closer than the robot's reach (20)"));
    CHECK_THAT(refusal([](json& a) {
                   a["balls"][3] = {450, 150};
               }),
               Contains("balls[3]: lies inside the wall 'pillar'"));
    CHECK_THAT(refusal([](json& a) {
                   a["balls"][3] = {450, 650};
               }),
               Contains("balls[3]: (450, 650) is outside the map"));
    CHECK_THAT(refusal([](json& a) { a["target_ball"] = 8; }),
               Contains("target_ball: must be a ball's index, 0 to 7, got 8"));
    CHECK_THAT(refusal([](json& a) { a["wals"] = a["walls"]; }), Contains("arena: unknown key 'wals'"));
    CHECK_THAT(refusal([](json& a) { a.erase("door"); }), Contains("'door' is required"));
    CHECK_THAT(refusal([](json& a) { a["basket"]["radius"] = "big"; }),
               Contains("basket.radius: must be a number"));
    CHECK_THAT(refusal([](json& a) {
                   a["starts"][1] = {520, 260};
               }),
               Contains("starts[1]: must be an array of 3 numbers"));
    CHECK_THAT(refusal([](json& a) {
                   for (int i = 0; i < 5; ++i) a["walls"].push_back({{"box", {10 + i, 10, 11 + i, 11}}});
               }),
               Contains("walls: must hold 1 to 11 walls (the door is the 12th), got 12"));
    CHECK_THAT(refusal([](json& a) {
                   a["balls"].push_back({560, 300});
               }),
               Contains("balls: must hold 1 to 8 balls, got 9"));
    CHECK(refusal([](json&) {}) == "(accepted)");
}

TEST_CASE("a task config's validation checks its arena", "[sim][arena][errors]") {
    TaskConfig config;
    config.arena = std::make_shared<const ArenaSpec>(two_rooms());
    CHECK_NOTHROW(config.validate());
    ArenaSpec broken = two_rooms();
    broken.target_ball = 11;
    config.arena = std::make_shared<const ArenaSpec>(broken);
    CHECK_THROWS_WITH(config.validate(), Contains("target_ball: must be a ball's index"));
    CHECK_THROWS_WITH(make_task(config), Contains("target_ball"));
}
