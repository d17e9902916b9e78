#include "reference/box2d_world.hpp"

#include <box2d/b2_distance.h>
#include <box2d/box2d.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/units.hpp"

namespace stepstone::reference {

using namespace stepstone::sim;

namespace {

// fixtures carry their wall index + 1 so the door can be skipped while open
int wall_of(b2Fixture* fixture) { return static_cast<int>(fixture->GetUserData().pointer) - 1; }

// closest hit along a ray, ignoring the door when open
class ClosestHit : public b2RayCastCallback {
public:
    ClosestHit(int skip) : skip_(skip) {}
    float ReportFixture(b2Fixture* fixture, const b2Vec2&, const b2Vec2&, float fraction) override {
        if (wall_of(fixture) == skip_) return -1.0f;
        best_ = std::min(best_, fraction);
        return fraction;
    }
    float best() const { return best_; }

private:
    int skip_;
    float best_ = 2.0f;
};

// every fixture whose AABB meets the query box, the door skipped when open
class Candidates : public b2QueryCallback {
public:
    Candidates(int skip, std::vector<b2Fixture*>& out) : skip_(skip), out_(out) {}
    bool ReportFixture(b2Fixture* fixture) override {
        if (wall_of(fixture) != skip_) out_.push_back(fixture);
        return true;
    }

private:
    int skip_;
    std::vector<b2Fixture*>& out_;
};

bool window_holds(double sensor_angle, double bearing) {
    const double lo = normalize_angle(sensor_angle - kLightWindow / 2);
    const double hi = normalize_angle(sensor_angle + kLightWindow / 2);
    return lo < bearing && bearing < hi;
}

// bearing range of the part of a convex polygon inside the disc, relative to
// `reference`: extremes lie at vertices inside the disc or at edge/circle crossings
void polygon_bearings(const b2PolygonShape& polygon, double cx, double cy, double reference, double& lo,
                      double& hi) {
    const double r = kRobotRadius;
    lo = hi = 0.0;
    auto consider = [&](double px, double py) {
        const double rel = normalize_angle(std::atan2(py - cy, px - cx) - reference);
        lo = std::min(lo, rel);
        hi = std::max(hi, rel);
    };
    const int n = polygon.m_count;
    for (int i = 0; i < n; ++i) {
        const double ax = polygon.m_vertices[i].x;
        const double ay = polygon.m_vertices[i].y;
        const double bx = polygon.m_vertices[(i + 1) % n].x;
        const double by = polygon.m_vertices[(i + 1) % n].y;
        if ((ax - cx) * (ax - cx) + (ay - cy) * (ay - cy) < r * r) consider(ax, ay);
        // |a + t (b - a) - c|^2 = r^2 for t in [0, 1]
        const double ex = bx - ax;
        const double ey = by - ay;
        const double fx = ax - cx;
        const double fy = ay - cy;
        const double qa = ex * ex + ey * ey;
        const double qb = 2.0 * (fx * ex + fy * ey);
        const double qc = fx * fx + fy * fy - r * r;
        const double disc = qb * qb - 4.0 * qa * qc;
        if (disc <= 0.0) continue;
        const double root = std::sqrt(disc);
        for (double t : {(-qb - root) / (2.0 * qa), (-qb + root) / (2.0 * qa)}) {
            if (t >= 0.0 && t <= 1.0) consider(ax + t * ex, ay + t * ey);
        }
    }
}

bool meets(double lo, double hi, double a, double b) {
    for (double shift : {-2.0 * kPi, 0.0, 2.0 * kPi}) {
        if (lo + shift < b && hi + shift > a) return true;
    }
    return false;
}

b2Vec2 vec(double x, double y) { return b2Vec2(static_cast<float>(x), static_cast<float>(y)); }

}  // namespace

struct ReferenceWorld::Impl {
    b2World world{b2Vec2(0.0f, 0.0f)};
    b2Body* walls = nullptr;
    int door = -1;
    std::vector<Light> lights;
    mutable std::vector<b2Fixture*> candidates;

    int skip(bool door_open) const { return door_open ? door : -2; }

    double ray(double x, double y, double dx, double dy, double range, bool door_open) const {
        ClosestHit hit(skip(door_open));
        world.RayCast(&hit, vec(x, y), vec(x + dx * range, y + dy * range));
        return hit.best() <= 1.0f ? static_cast<double>(hit.best()) * range : -1.0;
    }

    bool blocked(double x0, double y0, double x1, double y1, bool door_open) const {
        if (x0 == x1 && y0 == y1) return false;
        ClosestHit hit(skip(door_open));
        world.RayCast(&hit, vec(x0, y0), vec(x1, y1));
        return hit.best() <= 1.0f;
    }
};

ReferenceWorld::ReferenceWorld(const Arena& arena, std::span<const Light> lights)
    : impl_(std::make_unique<Impl>()) {
    impl_->door = arena.door_index();
    impl_->lights.assign(lights.begin(), lights.end());
    b2BodyDef body;
    body.type = b2_staticBody;
    impl_->walls = impl_->world.CreateBody(&body);
    const auto walls = arena.walls();
    for (std::size_t i = 0; i < walls.size(); ++i) {
        const WallBox& box = walls[i];
        b2PolygonShape shape;
        shape.SetAsBox(static_cast<float>((box.x1 - box.x0) / 2), static_cast<float>((box.y1 - box.y0) / 2),
                       vec((box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2), 0.0f);
        b2FixtureDef fixture;
        fixture.shape = &shape;
        fixture.userData.pointer = static_cast<uintptr_t>(i + 1);
        impl_->walls->CreateFixture(&fixture);
    }
}

ReferenceWorld::~ReferenceWorld() = default;

double ReferenceWorld::ray_distance(double x, double y, double dx, double dy, double range,
                                    bool door_open) const {
    return impl_->ray(x, y, dx, dy, range, door_open);
}

void ReferenceWorld::sense(const Pose& pose, const WorldState& state, SensorReadings& out) const {
    for (std::size_t i = 0; i < 3; ++i) {
        const double a = pose.heading + kLaserAngles[i];
        out.laser[i] = impl_->ray(pose.x, pose.y, std::cos(a), std::sin(a), kLaserRange, state.door_open);
    }
    out.light = {};
    for (std::size_t i = 0; i < impl_->lights.size(); ++i) {
        if ((state.lit >> i & 1u) == 0) continue;
        const Light& light = impl_->lights[i];
        const double bearing = normalize_angle(std::atan2(light.y - pose.y, light.x - pose.x) - pose.heading);
        const bool visible = !impl_->blocked(light.x, light.y, pose.x, pose.y, state.door_open);
        for (std::size_t side = 0; side < 2; ++side) {
            if (window_holds(kLightSensorAngles[side], bearing) && visible) {
                out.light[2 * static_cast<std::size_t>(light.kind) + side] = true;
            }
        }
    }
}

Contact ReferenceWorld::contact(const Pose& pose, bool door_open) const {
    Contact result;

    // the circle is shrunk by Box2D's polygon skin so the sum of radii is exactly kRobotRadius
    b2CircleShape disc;
    disc.m_radius = static_cast<float>(kRobotRadius) - b2_polygonRadius;
    b2Transform at;
    at.Set(vec(pose.x, pose.y), 0.0f);
    b2AABB box;
    box.lowerBound = vec(pose.x - kRobotRadius - 1.0, pose.y - kRobotRadius - 1.0);
    box.upperBound = vec(pose.x + kRobotRadius + 1.0, pose.y + kRobotRadius + 1.0);
    impl_->candidates.clear();
    Candidates query(impl_->skip(door_open), impl_->candidates);
    impl_->world.QueryAABB(&query, box);

    for (b2Fixture* fixture : impl_->candidates) {
        const b2Shape* shape = fixture->GetShape();
        const b2Transform& wall_at = fixture->GetBody()->GetTransform();
        if (!b2TestOverlap(&disc, 0, shape, 0, at, wall_at)) continue;
        result.hit = true;

        // bumpers: bearing range of the overlap around the closest point
        b2DistanceInput input;
        input.proxyA.Set(&disc, 0);
        input.proxyB.Set(shape, 0);
        input.transformA = at;
        input.transformB = wall_at;
        input.useRadii = false;
        b2SimplexCache cache;
        cache.count = 0;
        b2DistanceOutput output;
        b2Distance(&output, &cache, &input);
        if (output.distance <= 0.0f) {
            result.left = result.right = true;
            continue;
        }
        const double closest = std::atan2(output.pointB.y - pose.y, output.pointB.x - pose.x);
        double lo = 0.0;
        double hi = 0.0;
        polygon_bearings(*static_cast<const b2PolygonShape*>(shape), pose.x, pose.y, closest, lo, hi);
        const double base = normalize_angle(closest - pose.heading);
        result.left = result.left || meets(base + lo, base + hi, 0.0, kPi / 2);
        result.right = result.right || meets(base + lo, base + hi, -kPi / 2, 0.0);
    }
    return result;
}

}  // namespace stepstone::reference
