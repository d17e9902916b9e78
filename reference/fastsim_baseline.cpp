#include "reference/fastsim_baseline.hpp"

#include <cstdlib>
#include <numbers>
#include <stdexcept>
#include <string>

namespace stepstone::reference {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// the walk of BitmapMap::first_obstacle along its major axis a (minor axis b);
// XMajor says whether a is x
template <bool XMajor>
bool supercover_walk(const BitmapMap& map, int a, int b, int da, int db, int sa, int sb, int& hit_x,
                     int& hit_y) {
    auto wall = [&map](int major, int minor) {
        return XMajor ? map.obstacle(major, minor) : map.obstacle(minor, major);
    };
    const int two_da = 2 * da;
    const int two_db = 2 * db;
    int error = da;
    int previous = da;
    // a start pixel inside a wall reports at the first step, as fastsim does
    bool inter = wall(a, b);
    for (int i = 0; i < da; ++i) {
        a += sa;
        error += two_db;
        if (error > two_da) {
            b += sb;
            error -= two_da;
            // the line left the previous pixel through a side or exactly through
            // its corner: test the neighbour(s) it crossed as well
            const int crossing = error + previous;
            if (crossing < two_da) {
                inter = inter || wall(a, b - sb);
            } else if (crossing > two_da) {
                inter = inter || wall(a - sa, b);
            } else {
                inter = inter || wall(a, b - sb);
                inter = inter || wall(a - sa, b);
            }
        }
        inter = inter || wall(a, b);
        previous = error;
        if (inter) {
            hit_x = XMajor ? a : b;
            hit_y = XMajor ? b : a;
            return true;
        }
    }
    return false;
}

// light sensors: colour and mounting angle, in input order (docs/original.md: arena)
struct LightSensorSpec {
    LightColor color;
    float angle;
};
constexpr std::array<LightSensorSpec, 6> kLightSensors{{
    {LightColor::ball, kPi / 4},
    {LightColor::ball, -kPi / 4},
    {LightColor::basket, kPi / 4},
    {LightColor::basket, -kPi / 4},
    {LightColor::button, kPi / 4},
    {LightColor::button, -kPi / 4},
}};
// half of the light sensors' window, (pi/2 + 0.01) / 2
constexpr float kLightHalfWindow = (kPi / 2 + 0.01f) / 2;
// laser mounting angles: right, left, middle
constexpr std::array<float, 3> kLaserAngles{kPi / 4, -kPi / 4, 0.0f};

// task constants (docs/original.md: objects, arena)
constexpr std::array<BitmapPose, 3> kStartPoses{{
    {296.25f, 101.25f, kPi / 4},
    {498.75f, 303.75f, -3 * kPi / 4},
    {296.25f, 303.75f, -kPi / 4},
}};
constexpr float kBasketX = 296.25f;
constexpr float kBasketY = 405.0f;
constexpr float kBasketRadius = 33.75f;
constexpr float kGrabRadius = 20.0f;
constexpr int kSwitchRearm = 100;
constexpr int kStillLimit = 100;

float distance(float x0, float y0, float x1, float y1) {
    const float dx = x0 - x1;
    const float dy = y0 - y1;
    return std::sqrt(dx * dx + dy * dy);
}

}  // namespace

std::vector<WallRect> arena_walls(Door door) {
    // world edges (docs/original.md: arena); every edge lies between two pixel centres
    std::vector<WallRect> walls{
        {0.0f, 0.0f, 9.1f, 600.0f},        // outer left
        {588.9f, 0.0f, 600.0f, 600.0f},    // outer right
        {0.0f, 0.0f, 600.0f, 9.1f},        // outer top
        {0.0f, 394.3f, 600.0f, 400.3f},    // arena bottom
        {0.0f, 588.9f, 600.0f, 600.0f},    // bottom of the unreachable lower box
        {201.7f, 199.7f, 453.0f, 205.7f},  // horizontal wall, left part
        {546.3f, 199.7f, 600.0f, 205.7f},  // horizontal wall, right part
        {396.3f, 205.7f, 402.4f, 256.4f},  // upper stub
        {396.3f, 351.7f, 402.4f, 394.3f},  // lower stub
    };
    if (door == Door::closed) {
        walls.push_back({201.7f, 9.1f, 207.8f, 394.3f});  // divider
    } else {
        walls.push_back({201.7f, 9.1f, 207.8f, 256.4f});    // divider above the door
        walls.push_back({201.7f, 351.7f, 207.8f, 394.3f});  // divider below the door
    }
    return walls;
}

BitmapMap::BitmapMap(std::span<const WallRect> walls)
    : pixels_(static_cast<std::size_t>(kMapPixels) * kMapPixels, 0) {
    for (int j = 0; j < kMapPixels; ++j) {
        const float y = to_world(j);
        for (int i = 0; i < kMapPixels; ++i) {
            const float x = to_world(i);
            for (const auto& w : walls) {
                if (x >= w.x0 && x < w.x1 && y >= w.y0 && y < w.y1) {
                    pixels_[static_cast<std::size_t>(j) * kMapPixels + static_cast<std::size_t>(i)] = 1;
                    break;
                }
            }
        }
    }
}

BitmapMap::BitmapMap(Door door) : BitmapMap(arena_walls(door)) {}

bool BitmapMap::first_obstacle(int x0, int y0, int x1, int y1, int& hit_x, int& hit_y) const {
    const int dx = std::abs(x1 - x0);
    const int dy = std::abs(y1 - y0);
    const int sx = x1 < x0 ? -1 : 1;
    const int sy = y1 < y0 ? -1 : 1;
    if (dx >= dy) return supercover_walk<true>(*this, x0, y0, dx, dy, sx, sy, hit_x, hit_y);
    return supercover_walk<false>(*this, y0, x0, dy, dx, sy, sx, hit_x, hit_y);
}

float normalize_angle(float a) {
    while (a > kPi) a -= 2 * kPi;
    while (a < -kPi) a += 2 * kPi;
    return a;
}

BitmapPose arc_move(const BitmapPose& pose, float d_left, float d_right) {
    constexpr float kWheelBase = 2 * BitmapRobot::kRadius;
    const float alpha = (d_right - d_left) / kWheelBase;
    BitmapPose next = pose;
    if (std::fabs(alpha) > 1e-10f) {
        // arc of radius r around the instantaneous centre, in the robot frame,
        // then rotated by theta - pi/2 into the world
        const float r = d_left / alpha + kWheelBase / 2;
        const float dx = (std::cos(alpha) - 1) * r;
        const float dy = std::sin(alpha) * r;
        const float rot = pose.theta - kPi / 2;
        const float c = std::cos(rot);
        const float s = std::sin(rot);
        next.x = pose.x + (c * dx - s * dy);
        next.y = pose.y + (c * dy + s * dx);
        next.theta = normalize_angle(pose.theta + normalize_angle(alpha));
    } else {
        next.x = pose.x + d_left * std::cos(pose.theta);
        next.y = pose.y + d_left * std::sin(pose.theta);
    }
    return next;
}

BitmapRobot::BitmapRobot(BitmapPose pose) : pose_(pose) { contacts_.reserve(64); }

void BitmapRobot::reinit() {
    collision_ = false;
    left_bumper_ = false;
    right_bumper_ = false;
}

void BitmapRobot::move(float d_left, float d_right, const BitmapMap& map, std::span<const Light> lights) {
    const BitmapPose previous = pose_;
    pose_ = arc_move(previous, d_left, d_right);
    // blocked: back to the old position, keeping the new heading
    if (check_collision(map)) {
        const float theta = pose_.theta;
        pose_ = previous;
        pose_.theta = theta;
        collision_ = true;
    }
    update_lasers(map);
    update_lights(map, lights);
}

bool BitmapRobot::check_collision(const BitmapMap& map) {
    // every wall pixel of the bounding box (+-(r + 4) units) within rp pixels
    // of the centre pixel
    const int rp = to_pixel(kRadius);
    const int r2 = rp * rp;
    const int xc = to_pixel(pose_.x);
    const int yc = to_pixel(pose_.y);
    const float half = kRadius + 4;
    const int x_begin = to_pixel(pose_.x - half);
    const int y_begin = to_pixel(pose_.y - half);
    const int x_end = to_pixel(pose_.x + half);
    const int y_end = to_pixel(pose_.y + half);
    contacts_.clear();
    for (int i = x_begin; i < x_end; ++i) {
        for (int j = y_begin; j < y_end; ++j) {
            if (map.obstacle(i, j)) {
                const int d1 = i - xc;
                const int d2 = j - yc;
                if (d1 * d1 + d2 * d2 <= r2) contacts_.push_back({i, j});
            }
        }
    }

    // bumpers by the side of each contact pixel; dead ahead and behind set none
    left_bumper_ = false;
    right_bumper_ = false;
    if (contacts_.empty()) return false;
    for (const auto& p : contacts_) {
        const float a = normalize_angle(
            std::atan2(static_cast<float>(p[1] - yc), static_cast<float>(p[0] - xc)) - pose_.theta);
        if (a > 0 && a < kPi / 2) left_bumper_ = true;
        if (a < 0 && a > -kPi / 2) right_bumper_ = true;
    }
    return true;
}

void BitmapRobot::update_lasers(const BitmapMap& map) {
    const int x0 = to_pixel(pose_.x);
    const int y0 = to_pixel(pose_.y);
    for (std::size_t k = 0; k < kLaserAngles.size(); ++k) {
        const float a = pose_.theta + kLaserAngles[k];
        const int x1 = to_pixel(pose_.x + kLaserRange * std::cos(a));
        const int y1 = to_pixel(pose_.y + kLaserRange * std::sin(a));
        int hx = 0;
        int hy = 0;
        // distance from the true centre to the hit pixel, quantised to pixels
        lasers_[k] = map.first_obstacle(x0, y0, x1, y1, hx, hy)
                         ? distance(pose_.x, pose_.y, to_world(hx), to_world(hy))
                         : -1.0f;
    }
}

void BitmapRobot::update_lights(const BitmapMap& map, std::span<const Light> lights) {
    for (std::size_t s = 0; s < kLightSensors.size(); ++s) {
        const auto& sensor = kLightSensors[s];
        const float lo = normalize_angle(sensor.angle - kLightHalfWindow);
        const float hi = normalize_angle(sensor.angle + kLightHalfWindow);
        bool active = false;
        // every lit light of the colour in the window and in sight, no early exit
        for (const auto& light : lights) {
            if (light.color != sensor.color || !light.on) continue;
            const float a = normalize_angle(std::atan2(light.y - pose_.y, light.x - pose_.x) - pose_.theta);
            if (a > lo && a < hi && !map.blocked(light.x, light.y, pose_.x, pose_.y)) active = true;
        }
        lights_[s] = active;
    }
}

void BitmapRobot::sensor_inputs(float* out11) const {
    for (std::size_t k = 0; k < 3; ++k) out11[k] = lasers_[k] < 0 ? 0.0f : 1.0f - lasers_[k] / kLaserRange;
    for (std::size_t k = 0; k < 6; ++k) out11[3 + k] = lights_[k] ? 1.0f : 0.0f;
    out11[9] = left_bumper_ ? 1.0f : 0.0f;
    out11[10] = right_bumper_ ? 1.0f : 0.0f;
}

BitmapCollectBall::BitmapCollectBall(const BitmapArena& arena, BitmapTask task)
    : arena_(&arena), task_(task), map_(&arena.closed) {
    // balls first, then the basket lights, then the switch (docs/original.md: objects)
    const float w = 405.0f;
    if (task_ == BitmapTask::source) {
        lights_ = {
            {195 + w / 4, w / 8, LightColor::ball, true},    {195 + w / 4, 3 * w / 8, LightColor::ball, true},
            {195 + w / 2, w / 8, LightColor::ball, true},    {195 + w / 2, 3 * w / 8, LightColor::ball, true},
            {195.0f / 2, w / 8, LightColor::ball, true},     {195.0f / 2, 3 * w / 8, LightColor::ball, true},
            {195.0f / 2, 5 * w / 8, LightColor::ball, true}, {195.0f / 2, 7 * w / 8, LightColor::ball, true},
        };
    } else {
        lights_ = {{195.0f / 2, w / 8, LightColor::ball, false}};
    }
    for (const float x : {195 + w / 6, 195 + 2 * w / 6, 195 + 4 * w / 18, 195 + 5 * w / 18}) {
        lights_.push_back({x, w - 20, LightColor::basket, true});
    }
    lights_.push_back({195 + 15 * w / 18, w / 10, LightColor::button, true});
    reset();
}

void BitmapCollectBall::reset() {
    map_ = task_ == BitmapTask::source ? &arena_->closed : &arena_->open;
    robot_.set_pose(kStartPoses[0]);
    robot_.reinit();
    carrying_ = false;
    collected_ = 0;
    still_steps_ = 0;
    reinit_objects();
}

void BitmapCollectBall::reinit_objects() {
    if (task_ == BitmapTask::source) {
        map_ = &arena_->closed;
        for (auto& light : lights_) light.on = true;
    } else {
        for (auto& light : lights_) light.on = light.color != LightColor::ball;
        switch_timer_ = 0;
    }
}

void BitmapCollectBall::begin_start(int index) {
    // the original updates the sensors before it resets the objects
    robot_.set_pose(kStartPoses[static_cast<std::size_t>(index)]);
    robot_.move(0, 0, *map_, lights_);
    carrying_ = false;
    robot_.reinit();
    reinit_objects();
}

void BitmapCollectBall::place(BitmapPose pose) {
    robot_.set_pose(pose);
    robot_.move(0, 0, *map_, lights_);
}

void check_recording(const BitmapRecording& recording) {
    constexpr auto kRows = static_cast<std::size_t>(BitmapCollectBall::kStepsPerStart);
    if (!recording.behaviour.empty() && recording.behaviour.size() != kRows * BitmapCollectBall::kChannels) {
        throw std::invalid_argument("bitmap episode: behaviour buffer holds " +
                                    std::to_string(recording.behaviour.size()) + " floats, expected 60000");
    }
    if (!recording.cells.empty() && recording.cells.size() != 2 * BitmapCollectBall::kCells) {
        throw std::invalid_argument("bitmap episode: cell buffer holds " +
                                    std::to_string(recording.cells.size()) + " integers, expected 160");
    }
}

void BitmapCollectBall::pre_step() {
    if (task_ != BitmapTask::target) return;
    if (switch_timer_ == 0) {
        lights_.back().on = true;
    } else {
        --switch_timer_;
    }
}

void BitmapCollectBall::inputs(float* in12) const {
    robot_.sensor_inputs(in12);
    in12[11] = carrying_ ? 1.0f : 0.0f;
}

void BitmapCollectBall::act(float action) {
    const BitmapPose& p = robot_.pose();
    if (action < 0.5f) {
        // release: scores only pressed against a wall near the basket
        if (!carrying_) return;
        carrying_ = false;
        if (robot_.collision() && distance(p.x, p.y, kBasketX, kBasketY) <= kBasketRadius) ++collected_;
        return;
    }
    if (carrying_) return;
    // grab: the first lit ball within reach, or press the switch
    for (auto& light : lights_) {
        if (!light.on || distance(p.x, p.y, light.x, light.y) >= kGrabRadius) continue;
        if (light.color == LightColor::ball) {
            light.on = false;
            carrying_ = true;
            return;
        }
        if (light.color == LightColor::button) {
            light.on = false;
            if (task_ == BitmapTask::source) {
                map_ = &arena_->open;
            } else {
                lights_.front().on = true;
                switch_timer_ = kSwitchRearm;
            }
        }
    }
}

bool BitmapCollectBall::apply(int step, const float* in12, const float* out3,
                              const BitmapRecording& recording) {
    // history of the first start: behaviour rows and one grid cell every 50 steps
    if (step < kStepsPerStart) {
        if (!recording.behaviour.empty()) {
            float* row = recording.behaviour.data() + static_cast<std::size_t>(step) * kChannels;
            for (int k = 0; k < 12; ++k) row[k] = in12[k];
            for (int k = 0; k < 3; ++k) row[12 + k] = out3[k];
        }
        if (!recording.cells.empty() && step % 50 == 0) {
            const auto slot = static_cast<std::size_t>(step / 50) * 2;
            recording.cells[slot] = static_cast<std::int32_t>(robot_.pose().x * 12 / kMapWorld);
            recording.cells[slot + 1] = static_cast<std::int32_t>(robot_.pose().y * 12 / kMapWorld);
        }
    }

    act(out3[2]);

    // move, then the stand-still rule on the pose change
    const BitmapPose before = robot_.pose();
    robot_.move(4 * (2 * out3[0] - 1), 4 * (2 * out3[1] - 1), *map_, lights_);
    const BitmapPose& after = robot_.pose();
    if (distance(before.x, before.y, after.x, after.y) < 1e-4f &&
        std::fabs(after.theta - before.theta) < 1e-4f) {
        ++still_steps_;
    }
    return still_steps_ <= kStillLimit;
}

BitmapEpisodeResult BitmapCollectBall::finish(int steps, const BitmapRecording& recording) const {
    BitmapEpisodeResult result;
    result.collected = collected_;
    result.reward = collected_ / 24.0;
    result.steps = steps;
    result.stopped = still_steps_ > kStillLimit;
    // an early stop pads the trajectory with the final cell
    if (!recording.cells.empty() && steps < kStepsPerStart) {
        const int recorded = (steps + 49) / 50;
        const auto x = static_cast<std::int32_t>(robot_.pose().x * 12 / kMapWorld);
        const auto y = static_cast<std::int32_t>(robot_.pose().y * 12 / kMapWorld);
        for (int k = recorded; k < kCells; ++k) {
            recording.cells[static_cast<std::size_t>(k) * 2] = x;
            recording.cells[static_cast<std::size_t>(k) * 2 + 1] = y;
        }
    }
    return result;
}

}  // namespace stepstone::reference
