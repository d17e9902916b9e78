#include "sim/arena_spec.hpp"

#include <cmath>
#include <set>

#include "core/config.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "sim/sensors.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

namespace {

using nlohmann::json;

// the bitmap is 296 px for 600 units; pixel i covers [(i - 0.5) s, (i + 0.5) s)
constexpr double kUnitsPerPixel = 600.0 / 296.0;

WallBox pixel_box(int px0, int px1, int py0, int py1, std::string name) {
    return WallBox{(px0 - 0.5) * kUnitsPerPixel, (py0 - 0.5) * kUnitsPerPixel, (px1 + 0.5) * kUnitsPerPixel,
                   (py1 + 0.5) * kUnitsPerPixel, std::move(name)};
}

ArenaSpec make_paper_arena() {
    ArenaSpec spec;
    spec.name = "paper";
    // pixel ranges of arena2.pbm / arena2b.pbm (docs/original.md: arena), inclusive
    spec.walls = {
        pixel_box(0, 4, 0, 197, "outer left"),
        pixel_box(291, 295, 0, 197, "outer right"),
        pixel_box(0, 295, 0, 4, "outer top"),
        pixel_box(0, 295, 195, 197, "bottom"),
        pixel_box(100, 102, 5, 126, "divider above the door"),
        pixel_box(100, 102, 174, 194, "divider below the door"),
        pixel_box(100, 223, 99, 101, "horizontal wall, left part"),
        pixel_box(270, 295, 99, 101, "horizontal wall, right part"),
        pixel_box(196, 198, 102, 126, "upper stub"),
        pixel_box(196, 198, 174, 194, "lower stub"),
    };
    spec.door = pixel_box(100, 102, 127, 173, "door");
    // docs/original.md (objects); ball 4, behind the door at the top left, is the target task's
    spec.balls = {{296.25, 50.625}, {296.25, 151.875}, {397.5, 50.625}, {397.5, 151.875},
                  {97.5, 50.625},   {97.5, 151.875},   {97.5, 253.125}, {97.5, 354.375}};
    spec.target_ball = 4;
    spec.switch_light = {532.5, 40.5};
    spec.basket =
        Basket{{296.25, 405.0}, 33.75, {{262.5, 385.0}, {330.0, 385.0}, {285.0, 385.0}, {307.5, 385.0}}};
    // (195 + 405/4, 405/4, pi/4), (195 + 3*405/4, 3*405/4, -3pi/4), (195 + 405/4, 3*405/4, -pi/4)
    spec.starts = {{{296.25, 101.25, kPi / 4}, {498.75, 303.75, -3 * kPi / 4}, {296.25, 303.75, -kPi / 4}}};
    return spec;
}

// ---- parsing: every error names the key path

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw ConfigError(concat(path, ": ", what));
}

double number(const json& value, const std::string& path) {
    if (!value.is_number()) fail(path, concat("must be a number, got ", value.dump()));
    const double v = value.get<double>();
    if (!std::isfinite(v)) fail(path, "must be finite");
    return v;
}

std::vector<double> numbers(const json& value, std::size_t count, const std::string& path) {
    if (!value.is_array() || value.size() != count) {
        fail(path, concat("must be an array of ", count, " numbers, got ", value.dump()));
    }
    std::vector<double> out;
    for (std::size_t i = 0; i < count; ++i) out.push_back(number(value[i], concat(path, '[', i, ']')));
    return out;
}

Point point(const json& value, const std::string& path) {
    const auto v = numbers(value, 2, path);
    return {v[0], v[1]};
}

// an object's keys, each read at most once; unknown keys are refused at the end
class Keys {
public:
    Keys(const json& object, std::string path) : object_(object), path_(std::move(path)) {
        if (!object.is_object()) fail(path_.empty() ? "arena" : path_, "must be a JSON object");
    }
    const json* optional(const char* key) {
        read_.insert(key);
        const auto it = object_.find(key);
        return it == object_.end() ? nullptr : &*it;
    }
    const json& required(const char* key) {
        const json* value = optional(key);
        if (!value) fail(path_.empty() ? std::string(key) : path_, concat("'", key, "' is required"));
        return *value;
    }
    std::string at(const char* key) const {
        return path_.empty() ? std::string(key) : concat(path_, '.', key);
    }
    void finish() const {
        for (const auto& [key, value] : object_.items()) {
            if (!read_.count(key)) fail(path_.empty() ? "arena" : path_, concat("unknown key '", key, "'"));
        }
    }

private:
    const json& object_;
    std::string path_;
    std::set<std::string> read_;
};

WallBox wall(const json& value, const std::string& path, std::string default_name) {
    Keys keys(value, path);
    WallBox box;
    const auto v = numbers(keys.required("box"), 4, keys.at("box"));
    box = {v[0], v[1], v[2], v[3], std::move(default_name)};
    if (const json* name = keys.optional("name")) {
        if (!name->is_string() || name->get<std::string>().empty())
            fail(keys.at("name"), "must be a non-empty string");
        box.name = name->get<std::string>();
    }
    keys.finish();
    return box;
}

// ---- validation

// distance from (x, y) to the box (0 inside it)
double box_distance(const WallBox& box, double x, double y) {
    const double dx = std::max({box.x0 - x, 0.0, x - box.x1});
    const double dy = std::max({box.y0 - y, 0.0, y - box.y1});
    return std::hypot(dx, dy);
}

void check_box(const WallBox& box, const std::string& path) {
    if (!(box.x0 < box.x1))
        fail(path, concat("x0 (", shortest(box.x0), ") must be below x1 (", shortest(box.x1), ")"));
    if (!(box.y0 < box.y1))
        fail(path, concat("y0 (", shortest(box.y0), ") must be below y1 (", shortest(box.y1), ")"));
    // a wall may reach a robot radius past the map's edge, not beyond, and must meet the map
    constexpr double lo = -kRobotRadius;
    constexpr double hi = kMapSize + kRobotRadius;
    const double values[4] = {box.x0, box.y0, box.x1, box.y1};
    const char* names[4] = {"x0", "y0", "x1", "y1"};
    for (int i = 0; i < 4; ++i) {
        if (values[i] < lo || values[i] > hi) {
            fail(path, concat(names[i], " (", shortest(values[i]), ") is outside the arena [", shortest(lo),
                              ", ", shortest(hi), "]"));
        }
    }
    if (box.x1 <= 0.0 || box.x0 >= kMapSize || box.y1 <= 0.0 || box.y0 >= kMapSize) {
        fail(path, concat("lies outside the map [0, ", shortest(kMapSize), "]"));
    }
}

struct Object {
    std::string path;
    Point at;
};

void check_object(const ArenaSpec& spec, const Object& object) {
    if (!(object.at.x >= 0.0 && object.at.x < kMapSize && object.at.y >= 0.0 && object.at.y < kMapSize)) {
        fail(object.path, concat("(", shortest(object.at.x), ", ", shortest(object.at.y),
                                 ") is outside the map [0, ", shortest(kMapSize), ")"));
    }
    auto inside = [&](const WallBox& box) { return box_distance(box, object.at.x, object.at.y) == 0.0; };
    for (const WallBox& box : spec.walls) {
        if (inside(box)) fail(object.path, concat("lies inside the wall '", box.name, "'"));
    }
    if (inside(spec.door)) fail(object.path, "lies inside the door");
}

}  // namespace

void ArenaSpec::validate() const {
    if (name.empty()) fail("name", "must be a non-empty string");
    if (walls.empty() || walls.size() > kMaxWalls - 1) {
        fail("walls", concat("must hold 1 to ", kMaxWalls - 1, " walls (the door is the ", kMaxWalls,
                             "th), got ", walls.size()));
    }
    for (std::size_t i = 0; i < walls.size(); ++i) check_box(walls[i], concat("walls[", i, "]"));
    check_box(door, "door");
    if (balls.empty() || balls.size() > kMaxBalls) {
        fail("balls", concat("must hold 1 to ", kMaxBalls, " balls, got ", balls.size()));
    }
    if (target_ball >= balls.size()) {
        fail("target_ball", concat("must be a ball's index, 0 to ", balls.size() - 1, ", got ", target_ball));
    }
    if (basket.lights.size() > kMaxBasketLights) {
        fail("basket.lights",
             concat("must hold at most ", kMaxBasketLights, " lights, got ", basket.lights.size()));
    }
    if (!(basket.radius > 0.0 && basket.radius <= 100.0)) {
        fail("basket.radius", concat("must be in (0, 100], got ", shortest(basket.radius)));
    }

    // balls and the switch are what a grab reaches: no two within the robot's reach of each other
    std::vector<Object> grabbed;
    for (std::size_t i = 0; i < balls.size(); ++i) grabbed.push_back({concat("balls[", i, "]"), balls[i]});
    grabbed.push_back({"switch", switch_light});
    std::vector<Object> objects = grabbed;  // (the basket's centre may lie inside a wall, as the paper's)
    for (std::size_t i = 0; i < basket.lights.size(); ++i) {
        objects.push_back({concat("basket.lights[", i, "]"), basket.lights[i]});
    }
    for (const Object& object : objects) check_object(*this, object);
    if (!(basket.centre.x >= 0.0 && basket.centre.x < kMapSize && basket.centre.y >= 0.0 &&
          basket.centre.y < kMapSize)) {
        fail("basket.centre", concat("(", shortest(basket.centre.x), ", ", shortest(basket.centre.y),
                                     ") is outside the map [0, ", shortest(kMapSize), ")"));
    }
    for (std::size_t i = 0; i < grabbed.size(); ++i) {
        for (std::size_t j = i + 1; j < grabbed.size(); ++j) {
            const double d = std::hypot(grabbed[i].at.x - grabbed[j].at.x, grabbed[i].at.y - grabbed[j].at.y);
            if (d < kReach) {
                fail(grabbed[j].path,
                     concat("overlaps ", grabbed[i].path, ": ", shortest(d),
                            " apart, closer than the robot's reach (", shortest(kReach), ")"));
            }
        }
    }

    for (std::size_t s = 0; s < starts.size(); ++s) {
        const Pose& pose = starts[s];
        const std::string path = concat("starts[", s, "]");
        if (!std::isfinite(pose.heading)) fail(path, "heading must be finite");
        if (!(pose.x >= kRobotRadius && pose.x <= kMapSize - kRobotRadius && pose.y >= kRobotRadius &&
              pose.y <= kMapSize - kRobotRadius)) {
            fail(path,
                 concat("(", shortest(pose.x), ", ", shortest(pose.y), ") puts the robot outside the map"));
        }
        auto check = [&](const WallBox& box) {
            if (box_distance(box, pose.x, pose.y) < kRobotRadius) {
                fail(path, concat("(", shortest(pose.x), ", ", shortest(pose.y),
                                  ") puts the robot inside the wall '", box.name, "'"));
            }
        };
        for (const WallBox& box : walls) check(box);
        check(door);
    }
}

ArenaSpec ArenaSpec::from_json(const json& value, std::string_view source) {
    try {
        Keys keys(value, "");
        ArenaSpec spec;
        const json& name = keys.required("name");
        if (!name.is_string()) fail("name", "must be a string");
        spec.name = name.get<std::string>();
        const json& walls = keys.required("walls");
        if (!walls.is_array()) fail("walls", "must be an array of walls");
        for (std::size_t i = 0; i < walls.size(); ++i) {
            spec.walls.push_back(wall(walls[i], concat("walls[", i, "]"), concat("wall ", i)));
        }
        spec.door = wall(keys.required("door"), "door", "door");
        const json& balls = keys.required("balls");
        if (!balls.is_array()) fail("balls", "must be an array of [x, y] points");
        for (std::size_t i = 0; i < balls.size(); ++i)
            spec.balls.push_back(point(balls[i], concat("balls[", i, "]")));
        const json& target = keys.required("target_ball");
        if (!target.is_number_integer() || target.get<std::int64_t>() < 0) {
            fail("target_ball", concat("must be a ball's index, got ", target.dump()));
        }
        spec.target_ball = target.get<std::size_t>();
        spec.switch_light = point(keys.required("switch"), "switch");
        {
            Keys basket(keys.required("basket"), "basket");
            spec.basket.centre = point(basket.required("centre"), basket.at("centre"));
            spec.basket.radius = number(basket.required("radius"), basket.at("radius"));
            const json& lights = basket.required("lights");
            if (!lights.is_array()) fail(basket.at("lights"), "must be an array of [x, y] points");
            for (std::size_t i = 0; i < lights.size(); ++i) {
                spec.basket.lights.push_back(point(lights[i], concat("basket.lights[", i, "]")));
            }
            basket.finish();
        }
        const json& starts = keys.required("starts");
        if (!starts.is_array() || starts.size() != 3)
            fail("starts", "must be an array of 3 [x, y, heading] poses");
        for (std::size_t s = 0; s < 3; ++s) {
            const auto v = numbers(starts[s], 3, concat("starts[", s, "]"));
            spec.starts[s] = Pose{v[0], v[1], v[2]};
        }
        if (const json* units = keys.optional("units"); units && !units->is_string())
            fail("units", "must be a string");
        keys.finish();
        spec.validate();
        return spec;
    } catch (const ConfigError& e) {
        throw ConfigError(concat(source, ": ", e.what()));
    }
}

json ArenaSpec::to_json() const {
    auto box = [](const WallBox& b) { return json{{"name", b.name}, {"box", {b.x0, b.y0, b.x1, b.y1}}}; };
    auto pt = [](const Point& p) { return json::array({p.x, p.y}); };
    json out;
    out["name"] = name;
    out["units"] =
        "world units: the map is 600 x 600, origin top-left, y down, headings in radians clockwise";
    out["walls"] = json::array();
    for (const WallBox& b : walls) out["walls"].push_back(box(b));
    out["door"] = box(door);
    out["balls"] = json::array();
    for (const Point& p : balls) out["balls"].push_back(pt(p));
    out["target_ball"] = target_ball;
    out["switch"] = pt(switch_light);
    out["basket"] = {{"centre", pt(basket.centre)}, {"radius", basket.radius}, {"lights", json::array()}};
    for (const Point& p : basket.lights) out["basket"]["lights"].push_back(pt(p));
    out["starts"] = json::array();
    for (const Pose& p : starts) out["starts"].push_back({p.x, p.y, p.heading});
    return out;
}

std::string ArenaSpec::to_text() const {
    auto n = [](double v) { return shortest(v); };
    auto pt = [&](const Point& p) { return concat('[', n(p.x), ", ", n(p.y), ']'); };
    auto box = [&](const WallBox& b) {
        return concat("{\"name\": ", json(b.name).dump(), ", \"box\": [", n(b.x0), ", ", n(b.y0), ", ",
                      n(b.x1), ", ", n(b.y1), "]}");
    };
    auto points = [&](const std::vector<Point>& list) {
        std::string out = "[";
        for (std::size_t i = 0; i < list.size(); ++i) out += concat(i ? ", " : "", pt(list[i]));
        return out + "]";
    };
    std::string out = concat("{\n  \"name\": ", json(name).dump(),
                             ",\n  \"units\": ", to_json()["units"].dump(), ",\n  \"walls\": [\n");
    for (std::size_t i = 0; i < walls.size(); ++i) {
        out += concat("    ", box(walls[i]), i + 1 < walls.size() ? ",\n" : "\n");
    }
    out += concat("  ],\n  \"door\": ", box(door), ",\n  \"balls\": ", points(balls),
                  ",\n  \"target_ball\": ", target_ball, ",\n  \"switch\": ", pt(switch_light),
                  ",\n  \"basket\": {\"centre\": ", pt(basket.centre), ", \"radius\": ", n(basket.radius),
                  ", \"lights\": ", points(basket.lights), "},\n  \"starts\": [");
    for (std::size_t s = 0; s < starts.size(); ++s) {
        out +=
            concat(s ? ", " : "", '[', n(starts[s].x), ", ", n(starts[s].y), ", ", n(starts[s].heading), ']');
    }
    return out + "]\n}\n";
}

ArenaSpec ArenaSpec::load(const std::filesystem::path& path) {
    return from_json(load_json_file(path), path.string());
}

const ArenaSpec& paper_arena() {
    static const ArenaSpec spec = make_paper_arena();
    return spec;
}

std::shared_ptr<const ArenaSpec> shared_paper_arena() {
    static const auto spec = std::make_shared<const ArenaSpec>(paper_arena());
    return spec;
}

}  // namespace stepstone::sim
