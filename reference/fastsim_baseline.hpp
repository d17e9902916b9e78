#pragma once

// A fastsim-style simulator of the ball-collecting arena, kept as the
// baseline of `stepstone bench sim` and `stepstone bench episode`: the
// 296 x 296 one-bit bitmap, supercover Bresenham lasers and lines of sight,
// pixel-scan collision with bumpers, arc odometry and the collectball task
// rules (docs/original.md: arena, objects, speed). Written to be as fast as fastsim
// itself, not faster (no geometric shortcuts) and not slower (no per-step
// allocation, no file reads on door swaps).

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace stepstone::reference {

/// Side of the square bitmap, in pixels (docs/original.md: arena).
inline constexpr int kMapPixels = 296;
/// Side of the square world the bitmap covers, in world units.
inline constexpr float kMapWorld = 600.0f;
/// Pixels per world unit, fx = 296 / 600.
inline constexpr float kPixelsPerUnit = static_cast<float>(kMapPixels) / kMapWorld;

/// World x or y to pixel index: round(v * fx), as fastsim's real_to_pixel.
inline int to_pixel(float v) { return static_cast<int>(std::round(v * kPixelsPerUnit)); }
/// Pixel index to world units: i / fx, as fastsim's pixel_to_real.
inline float to_world(int i) { return static_cast<float>(i) / kPixelsPerUnit; }

/// Whether the divider's door is open (arena2b.pbm) or closed (arena2.pbm).
enum class Door { closed, open };

/// An axis-aligned wall in world units, covering [x0, x1) x [y0, y1).
struct WallRect {
    float x0, y0, x1, y1;
};

/// The walls (docs/original.md: arena; plus the outer walls of the unreachable
/// lower box), for the given door state.
std::vector<WallRect> arena_walls(Door door);

/// A 296 x 296 one-bit obstacle map covering 600 x 600 world units, y down.
/// Immutable once built; shared read-only by any number of robots.
class BitmapMap {
public:
    /// Rasterises `walls`: pixel (i, j) is an obstacle when its centre
    /// (i / fx, j / fx) lies in a wall, so pixel i covers world
    /// [(i - 0.5) / fx, (i + 0.5) / fx).
    explicit BitmapMap(std::span<const WallRect> walls);
    /// The original arena (docs/original.md: arena) with the door in the given state.
    explicit BitmapMap(Door door);

    /// True if (x, y) is a wall pixel or outside the map.
    bool obstacle(int x, int y) const {
        if (x < 0 || y < 0 || x >= kMapPixels || y >= kMapPixels) return true;
        return pixels_[static_cast<std::size_t>(y) * kMapPixels + static_cast<std::size_t>(x)] != 0;
    }

    /// Walks the supercover Bresenham line from pixel (x0, y0) to (x1, y1)
    /// (the start pixel excluded, side pixels included where the line crosses
    /// a pixel corner) and stops at the first obstacle. Returns true and sets
    /// (hit_x, hit_y) to the line pixel of that step if there is one.
    bool first_obstacle(int x0, int y0, int x1, int y1, int& hit_x, int& hit_y) const;

    /// True if the line between two world points crosses a wall pixel
    /// (fastsim's check_inter_real).
    bool blocked(float x0, float y0, float x1, float y1) const {
        int hx = 0;
        int hy = 0;
        return first_obstacle(to_pixel(x0), to_pixel(y0), to_pixel(x1), to_pixel(y1), hx, hy);
    }

private:
    std::vector<std::uint8_t> pixels_;
};

/// Robot position (world units, y down) and heading (radians, clockwise on
/// screen, in [-pi, pi]).
struct BitmapPose {
    float x = 0;
    float y = 0;
    float theta = 0;
};

/// fastsim's angle normalisation into [-pi, pi].
float normalize_angle(float a);

/// Exact differential-drive arc odometry (docs/original.md: arena): wheel
/// displacements in world units, wheels 40 apart.
BitmapPose arc_move(const BitmapPose& pose, float d_left, float d_right);

/// Colours of the illuminated objects (docs/original.md: objects).
enum class LightColor : std::uint8_t { basket = 2, ball = 3, button = 4 };

/// An illuminated switch: a ball, a basket light or the door switch.
struct Light {
    float x = 0;
    float y = 0;
    LightColor color = LightColor::ball;
    bool on = true;
};

/// A differential-drive robot of radius 20 with the paper's sensors: 3 lasers
/// (+pi/4, -pi/4, 0; range 320), 6 binary light sensors (ball, basket, switch
/// at +-pi/4) and 2 bumpers (docs/original.md: arena).
class BitmapRobot {
public:
    /// Robot radius in world units.
    static constexpr float kRadius = 20.0f;
    /// Laser range in world units.
    static constexpr float kLaserRange = 320.0f;

    explicit BitmapRobot(BitmapPose pose = {});

    /// Places the robot without moving it (sensors unchanged).
    void set_pose(BitmapPose pose) { pose_ = pose; }
    /// Clears the sticky collision flag and both bumpers (fastsim's reinit).
    void reinit();
    /// One step: arc odometry, pixel collision at the attempted pose (on a
    /// collision the old position is restored and the new heading kept), then
    /// every sensor at the final pose.
    void move(float d_left, float d_right, const BitmapMap& map, std::span<const Light> lights);

    const BitmapPose& pose() const { return pose_; }
    /// Laser i's distance in world units (quantised to pixels), -1 if nothing
    /// within range.
    float laser(int i) const { return lasers_[static_cast<std::size_t>(i)]; }
    /// Light sensor i (ball+, ball-, basket+, basket-, switch+, switch-).
    bool light(int i) const { return lights_[static_cast<std::size_t>(i)]; }
    /// Bumper of the (0, pi/2) side (input 9).
    bool left_bumper() const { return left_bumper_; }
    /// Bumper of the (-pi/2, 0) side (input 10).
    bool right_bumper() const { return right_bumper_; }
    /// Sticky: any collision since the last reinit().
    bool collision() const { return collision_; }

    /// The 11 sensor inputs (lasers, lights, bumpers; docs/original.md: arena).
    void sensor_inputs(float* out11) const;

private:
    bool check_collision(const BitmapMap& map);
    void update_lasers(const BitmapMap& map);
    void update_lights(const BitmapMap& map, std::span<const Light> lights);

    BitmapPose pose_;
    std::array<float, 3> lasers_{-1, -1, -1};
    std::array<bool, 6> lights_{};
    bool left_bumper_ = false;
    bool right_bumper_ = false;
    bool collision_ = false;
    // colliding pixels of the last check, reused from step to step
    std::vector<std::array<int, 2>> contacts_;
};

/// Which collectball variant an episode runs (docs/original.md: objects).
enum class BitmapTask { source, target };

/// Both door states of the arena; immutable, shared by episodes.
struct BitmapArena {
    BitmapMap closed{Door::closed};
    BitmapMap open{Door::open};
};

/// Result of one baseline evaluation.
struct BitmapEpisodeResult {
    int collected = 0;     ///< balls scored over the three starts
    double reward = 0;     ///< collected / 24
    int steps = 0;         ///< steps run (12,000 unless stopped early)
    bool stopped = false;  ///< the stand-still rule ended the evaluation
};

/// Caller-owned recording buffers, each may be empty.
struct BitmapRecording {
    std::span<float> behaviour;     ///< 4000 x 15 (row = step: 12 inputs, 3 outputs)
    std::span<std::int32_t> cells;  ///< 80 x 2 grid cells (x, y) of the first start
};

/// The collectball evaluation as the original runs it, one step at a time
/// (docs/original.md: arena): the caller feeds inputs to a controller and passes its
/// outputs back. Use run_bitmap_episode for the whole loop.
class BitmapCollectBall {
public:
    /// Steps per start, starts per evaluation, trajectory samples.
    static constexpr int kStepsPerStart = 4000;
    static constexpr int kStarts = 3;
    static constexpr int kCells = 80;
    static constexpr int kChannels = 15;

    /// `arena` must outlive this object.
    BitmapCollectBall(const BitmapArena& arena, BitmapTask task);

    /// Starts the evaluation over.
    void reset();
    /// Start pose, sensor update and task reset of start `index` (0-2),
    /// in the original's order (sensors see the previous start's objects).
    void begin_start(int index);
    /// Per-step task bookkeeping before the inputs are read (switch timer).
    void pre_step();
    /// The 12 inputs, in the order of docs/original.md (arena).
    void inputs(float* in12) const;
    /// Records the step's inputs and outputs, then applies the action and the
    /// move (outputs already NaN-free). Returns false once the stand-still
    /// rule ends the evaluation.
    bool apply(int step, const float* in12, const float* out3, const BitmapRecording& recording);
    /// Pads the trajectory after an early stop and returns the result.
    BitmapEpisodeResult finish(int steps, const BitmapRecording& recording) const;

    const BitmapRobot& robot() const { return robot_; }
    /// Balls scored so far.
    int collected() const { return collected_; }
    /// Whether a ball is carried.
    bool carrying() const { return carrying_; }
    /// Whether the door-open map is loaded.
    bool door_open() const { return map_ == &arena_->open; }
    /// Lights in index order: balls, basket lights, then the switch.
    std::span<const Light> lights() const { return lights_; }

    /// Places the robot and senses there (test scenes).
    void place(BitmapPose pose);
    /// Sets the carried flag (test scenes).
    void set_carrying(bool carrying) { carrying_ = carrying; }

private:
    void reinit_objects();
    void act(float action);

    const BitmapArena* arena_;
    BitmapTask task_;
    const BitmapMap* map_;
    BitmapRobot robot_;
    std::vector<Light> lights_;
    bool carrying_ = false;
    int collected_ = 0;
    int still_steps_ = 0;
    int switch_timer_ = 0;
};

/// Throws std::invalid_argument if a non-empty buffer of `recording` is not
/// 4000 x 15 floats (behaviour) or 80 x 2 integers (cells).
void check_recording(const BitmapRecording& recording);

/// One whole evaluation (3 starts x 4000 steps, stand-still rule) of
/// `controller` (reset(), step(const float* in12, float* out3)). Throws as
/// check_recording.
template <class Controller>
BitmapEpisodeResult run_bitmap_episode(BitmapCollectBall& episode, Controller& controller,
                                       const BitmapRecording& recording = {}) {
    check_recording(recording);
    episode.reset();
    float in[12];
    float out[3];
    int step = 0;
    for (int start = 0; start < BitmapCollectBall::kStarts; ++start) {
        episode.begin_start(start);
        controller.reset();
        for (int k = 0; k < BitmapCollectBall::kStepsPerStart; ++k, ++step) {
            episode.pre_step();
            episode.inputs(in);
            controller.step(in, out);
            for (float& o : out) {
                if (std::isnan(o)) o = 0;
            }
            if (!episode.apply(step, in, out, recording)) return episode.finish(step + 1, recording);
        }
    }
    return episode.finish(step, recording);
}

}  // namespace stepstone::reference
