#pragma once

#include <cstdint>
#include <string>

#include "report/canvas.hpp"
#include "report/trace.hpp"
#include "sim/task.hpp"

namespace stepstone::report {

/// Where the arena lies on a canvas: world units (y down, as the simulator)
/// to pixels, px = left + x scale, py = top + y scale.
struct ArenaLayout {
    double scale = 1.25;  ///< pixels per unit: 600 units -> 750 px
    double left = 25.0;
    double top = 46.0;
    int width = 800;
    int height = 680;  ///< room below the arena for the basket disc and the legend
    double legend_y = 445.0;  ///< units: where the legend rows start, below the arena
    double px(double x) const { return left + x * scale; }
    double py(double y) const { return top + y * scale; }

    /// The layout that fits `arena` in the same canvas: the paper's arena keeps
    /// the default; a taller one moves the legend down and shrinks the scale.
    static ArenaLayout fit(const sim::ArenaSpec& arena);
};

/// What a trajectory figure shows.
struct TrajectoryOptions {
    int first_step = 0;          ///< first step drawn
    int last_step = -1;          ///< one past the last step drawn; -1 = to the end
    int heading_every = 50;      ///< a heading mark every this many steps (0: none)
    double circle_radius = 2.6;  ///< in units
    std::string title;           ///< empty: made from the trace
};

/// The arena of `task` as at its start: walls, the door (closed, or dashed
/// when `door_open`), balls lit at the start (the target task's spawn point
/// dashed), the switch, the basket disc and the three start poses, with a
/// legend. The floor is kFloor and walls kWall, so pixels can be checked
/// against the geometry.
void draw_arena(Canvas& canvas, const sim::Task& task, bool door_open, const std::string& title,
                const ArenaLayout& layout = {});
/// The same with the lights lit given (bit i: Task::lights()[i]): a ball lit
/// at the start but not in `lit` is drawn taken (a grey outline), and the
/// legend names what is drawn (an open door, a taken ball, the spawn point).
void draw_arena(Canvas& canvas, const sim::Task& task, bool door_open, std::uint32_t lit,
                const std::string& title, const ArenaLayout& layout = {});

/// The paper's Fig. 4 / 8: the arena and the trace's poses as small circles in
/// step order, each filled with saliency_colour(average / max average) of the
/// KB segment matched at that step (white without a KB, without a match, or
/// when the KB's largest average is 0), a heading mark every
/// `heading_every` steps (white while carrying nothing, red while carrying),
/// and a colour bar. In SVG every circle has a hover title: step, segment,
/// KB segment id, distance and average reward.
void draw_trajectory(Canvas& canvas, const Trace& trace, const TrajectoryOptions& options = {},
                     const ArenaLayout& layout = {});

/// The fill of the circle at a step whose match is `match` in a KB whose
/// largest average is `max_average` (what draw_trajectory uses).
Colour circle_colour(const std::optional<kb::SegmentMatch>& match, double max_average);

/// The paper's Fig. 5: the average reward of the KB segment matched by each
/// segment of the trace, along time. Throws DataError for a trace without KB.
void draw_saliency_along_time(Canvas& canvas, const Trace& trace, const std::string& title = "");

}  // namespace stepstone::report
