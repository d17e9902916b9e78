#pragma once

#include <memory>
#include <span>

#include "sim/arena.hpp"
#include "sim/sensors.hpp"

namespace stepstone::reference {

/// The reference geometry: the arena's walls as static Box2D 2.4 box fixtures,
/// lasers and line of sight by b2World::RayCast, the robot disc by an AABB
/// query and b2TestOverlap. It answers the same questions as Arena and sense()
/// and exists to check them; it is far slower. Box2D stays behind this pimpl.
/// Queries are const but not thread-safe (Box2D's world is not): use one
/// ReferenceWorld per thread.
class ReferenceWorld {
public:
    /// Builds the Box2D world from the arena's walls; keeps a copy of `lights`.
    ReferenceWorld(const sim::Arena& arena, std::span<const sim::Light> lights);
    ~ReferenceWorld();
    ReferenceWorld(const ReferenceWorld&) = delete;
    ReferenceWorld& operator=(const ReferenceWorld&) = delete;

    /// Same contract as sense(); bearings from atan2 as the original code.
    void sense(const sim::Pose& pose, const sim::WorldState& state, sim::SensorReadings& out) const;
    /// Same contract as Arena::contact(); bumpers from the polygon's vertices
    /// and Box2D's closest points.
    sim::Contact contact(const sim::Pose& pose, bool door_open) const;
    /// Distance to the first wall along a ray, or -1 (same contract as Arena::ray_distance).
    double ray_distance(double x, double y, double dx, double dy, double range, bool door_open) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace stepstone::reference
