// The arena, a policy's trajectory coloured by saliency, and saliency along time.

#include "report/arena_figure.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/error.hpp"
#include "core/text.hpp"
#include "report/chart.hpp"
#include "sim/units.hpp"

namespace stepstone::report {

namespace {

constexpr Colour kOutline = Colour::hex(0x8C8C8C);
constexpr double kBallRadius = 7.0;  // units, drawn only

std::string fixed(double value, int decimals) {
    char text[32];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

void disc(cairo_t* cr, double x, double y, double r) {
    cairo_new_path(cr);
    cairo_arc(cr, x, y, r, 0.0, 2.0 * M_PI);
}

void dashed(cairo_t* cr, bool on) {
    const double dashes[] = {4.0, 3.0};
    cairo_set_dash(cr, on ? dashes : nullptr, on ? 2 : 0, 0.0);
}

// a legend row at the bottom of the figure: swatches drawn by `mark`
template <class Mark>
double legend_item(Canvas& canvas, double x, double y, const std::string& label, Mark mark) {
    mark(x + 8.0, y);
    canvas.text(x + 20.0, y, label, 12.0, kText, 0.0, 0.5);
    return x + 20.0 + canvas.text_width(label, 12.0) + 18.0;
}

void draw_start_pose(Canvas& canvas, const sim::Pose& pose, int number, const ArenaLayout& layout) {
    cairo_t* cr = canvas.cr();
    const double x = layout.px(pose.x);
    const double y = layout.py(pose.y);
    const double r = sim::kRobotRadius * layout.scale;
    disc(cr, x, y, r);
    canvas.set_colour(kBlack);
    cairo_set_line_width(cr, 1.2);
    dashed(cr, true);
    cairo_stroke(cr);
    dashed(cr, false);
    // an arrow along the heading
    const double c = std::cos(pose.heading), s = std::sin(pose.heading);
    cairo_move_to(cr, x + c * r * 0.2, y + s * r * 0.2);
    cairo_line_to(cr, x + c * r * 1.5, y + s * r * 1.5);
    cairo_stroke(cr);
    const double tip_x = x + c * r * 1.5, tip_y = y + s * r * 1.5;
    cairo_move_to(cr, tip_x, tip_y);
    cairo_line_to(cr, tip_x - c * 7.0 - s * 4.0, tip_y - s * 7.0 + c * 4.0);
    cairo_line_to(cr, tip_x - c * 7.0 + s * 4.0, tip_y - s * 7.0 - c * 4.0);
    cairo_close_path(cr);
    cairo_fill(cr);
    canvas.text(x, y, std::to_string(number), 13.0, kBlack, 0.5, 0.5, true);
}

// what the legend explains beyond the fixed items
struct ArenaState {
    bool door_open = false;
    bool taken = false;  // a ball on the floor at the start is gone by the last step drawn
    bool spawn = false;  // an unlit ball position: the target task's spawn point
};

// a ball taken by the robot: a grey outline where it lay
void taken_ball(cairo_t* cr, Canvas& canvas, double x, double y, const ArenaLayout& layout) {
    disc(cr, x, y, kBallRadius * layout.scale);
    canvas.set_colour(kGrey);
    cairo_set_line_width(cr, 1.2);
    cairo_stroke(cr);
}

// where the target task lights a ball at each press: a dashed outline in the ball's colour
void spawn_point(cairo_t* cr, Canvas& canvas, double x, double y, const ArenaLayout& layout) {
    disc(cr, x, y, kBallRadius * layout.scale);
    canvas.set_colour(kBall);
    cairo_set_line_width(cr, 1.5);
    dashed(cr, true);
    cairo_stroke(cr);
    dashed(cr, false);
}

// the legend row; `state` says which of the arena's items the figure shows
void draw_legend(Canvas& canvas, const ArenaLayout& layout, double y, const ArenaState& state) {
    cairo_t* cr = canvas.cr();
    double x = layout.left;
    x = legend_item(canvas, x, y, "wall", [&](double cx, double cy) {
        cairo_rectangle(cr, cx - 7.0, cy - 4.0, 14.0, 8.0);
        canvas.set_colour(kWall);
        cairo_fill(cr);
    });
    x = legend_item(canvas, x, y, state.door_open ? "open door" : "door", [&](double cx, double cy) {
        cairo_rectangle(cr, cx - 7.0, cy - 4.0, 14.0, 8.0);
        canvas.set_colour(kDoor);
        if (!state.door_open) return cairo_fill(cr);
        cairo_set_line_width(cr, 1.2);
        dashed(cr, true);
        cairo_stroke(cr);
        dashed(cr, false);
    });
    x = legend_item(canvas, x, y, "ball", [&](double cx, double cy) {
        disc(cr, cx, cy, kBallRadius * layout.scale);
        canvas.set_colour(kBall);
        cairo_fill(cr);
    });
    if (state.taken) {
        x = legend_item(canvas, x, y, "ball taken",
                        [&](double cx, double cy) { taken_ball(cr, canvas, cx, cy, layout); });
    }
    if (state.spawn) {
        x = legend_item(canvas, x, y, "spawn point",
                        [&](double cx, double cy) { spawn_point(cr, canvas, cx, cy, layout); });
    }
    x = legend_item(canvas, x, y, "switch", [&](double cx, double cy) {
        cairo_rectangle(cr, cx - 6.0, cy - 6.0, 12.0, 12.0);
        canvas.set_colour(kSwitch);
        cairo_fill(cr);
    });
    x = legend_item(canvas, x, y, "basket", [&](double cx, double cy) {
        disc(cr, cx, cy, 7.0);
        canvas.set_colour(kBasket, 0.35);
        cairo_fill(cr);
    });
    legend_item(canvas, x, y, "starts 1-3", [&](double cx, double cy) {
        disc(cr, cx, cy, 7.0);
        canvas.set_colour(kBlack);
        cairo_set_line_width(cr, 1.2);
        dashed(cr, true);
        cairo_stroke(cr);
        dashed(cr, false);
    });
}

// a trajectory circle: filled, with a thin grey outline so white ones show on the floor
void draw_circle(cairo_t* cr, double x, double y, double r, Colour fill) {
    disc(cr, x, y, r);
    cairo_set_source_rgb(cr, fill.r, fill.g, fill.b);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, kOutline.r, kOutline.g, kOutline.b);
    cairo_set_line_width(cr, 0.6);
    cairo_stroke(cr);
}

// Raster trajectories draw thousands of identical small circles: each fill
// colour is drawn once into a small surface (an odd number of pixels wide, the
// circle centred in its middle pixel) and stamped at the pixel holding each
// centre, about ten times faster than rasterising every circle. The centre
// moves by at most half a pixel; the SVG output draws exact circles.
class CircleStamps {
public:
    explicit CircleStamps(double radius) : radius_(radius), half_(static_cast<int>(std::ceil(radius + 1.0))) {}
    ~CircleStamps() {
        for (auto& [key, surface] : stamps_) cairo_surface_destroy(surface);
    }
    CircleStamps(const CircleStamps&) = delete;
    CircleStamps& operator=(const CircleStamps&) = delete;

    void stamp(cairo_t* cr, double x, double y, Colour fill) {
        const auto byte = [](double v) { return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); };
        const std::uint32_t key = byte(fill.r) << 16 | byte(fill.g) << 8 | byte(fill.b);
        auto it = stamps_.find(key);
        if (it == stamps_.end()) {
            const int size = 2 * half_ + 1;
            cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, size, size);
            cairo_t* s = cairo_create(surface);
            draw_circle(s, half_ + 0.5, half_ + 0.5, radius_,
                        {static_cast<double>(key >> 16) / 255.0, static_cast<double>((key >> 8) & 0xff) / 255.0,
                         static_cast<double>(key & 0xff) / 255.0});
            cairo_destroy(s);
            it = stamps_.emplace(key, surface).first;
        }
        cairo_set_source_surface(cr, it->second, std::floor(x) - half_, std::floor(y) - half_);
        cairo_paint(cr);
    }

private:
    double radius_;
    int half_;
    std::map<std::uint32_t, cairo_surface_t*> stamps_;
};

}  // namespace

ArenaLayout ArenaLayout::fit(const sim::ArenaSpec& arena) {
    ArenaLayout layout;
    double bottom = arena.door.y1;
    for (const auto& w : arena.walls) bottom = std::max(bottom, w.y1);
    bottom = std::max(bottom, arena.basket.centre.y + arena.basket.radius);
    if (bottom + 44.0 > layout.legend_y) {
        layout.scale *= layout.legend_y / (bottom + 44.0);
        layout.legend_y = bottom + 44.0;
    }
    return layout;
}

void draw_arena(Canvas& canvas, const sim::Task& task, bool door_open, const std::string& title,
                const ArenaLayout& layout) {
    draw_arena(canvas, task, door_open, task.initial_lit(), title, layout);
}

void draw_arena(Canvas& canvas, const sim::Task& task, bool door_open, std::uint32_t lit,
                const std::string& title, const ArenaLayout& layout) {
    ArenaState state;
    state.door_open = door_open;
    cairo_t* cr = canvas.cr();
    canvas.fill(kWhite);
    if (!title.empty()) canvas.text(canvas.width() / 2.0, 14.0, title, 17.0, kText, 0.5, 0.0, true);
    // the floor: the box around every wall (the paper's: the map's 600 x 400 units)
    const auto& arena = task.arena();
    const auto walls = arena.walls();
    double x0 = walls[0].x0, y0 = walls[0].y0, x1 = walls[0].x1, y1 = walls[0].y1;
    for (const auto& w : walls) {
        x0 = std::min(x0, w.x0), y0 = std::min(y0, w.y0), x1 = std::max(x1, w.x1), y1 = std::max(y1, w.y1);
    }
    cairo_rectangle(cr, layout.px(x0), layout.py(y0), (x1 - x0) * layout.scale, (y1 - y0) * layout.scale);
    canvas.set_colour(kFloor);
    cairo_fill(cr);

    // the basket disc first: it lies under the bottom wall
    const sim::Basket& basket = task.basket();
    disc(cr, layout.px(basket.centre.x), layout.py(basket.centre.y), basket.radius * layout.scale);
    canvas.set_colour(kBasket, 0.35);
    cairo_fill(cr);

    for (std::size_t i = 0; i < walls.size(); ++i) {
        const auto& w = walls[i];
        cairo_rectangle(cr, layout.px(w.x0), layout.py(w.y0), (w.x1 - w.x0) * layout.scale,
                        (w.y1 - w.y0) * layout.scale);
        if (static_cast<int>(i) != arena.door_index()) {
            canvas.set_colour(kWall);
            cairo_fill(cr);
        } else if (!door_open) {
            canvas.set_colour(kDoor);
            cairo_fill(cr);
        } else {
            canvas.set_colour(kDoor);
            cairo_set_line_width(cr, 1.2);
            dashed(cr, true);
            cairo_stroke(cr);
            dashed(cr, false);
        }
    }

    const auto lights = task.lights();
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const auto& light = lights[i];
        const double x = layout.px(light.x), y = layout.py(light.y);
        const bool at_start = (task.initial_lit() >> i) & 1u;
        const bool now = (lit >> i) & 1u;
        if (light.kind == sim::LightKind::ball) {
            if (now) {
                disc(cr, x, y, kBallRadius * layout.scale);
                canvas.set_colour(kBall);
                cairo_fill(cr);
            } else if (at_start) {
                // on the floor at the start, taken by the last step drawn
                taken_ball(cr, canvas, x, y, layout);
                state.taken = true;
            } else {
                // the target task's spawn point: a ball appears here at each switch press
                spawn_point(cr, canvas, x, y, layout);
                state.spawn = true;
            }
        } else if (light.kind == sim::LightKind::switch_light) {
            cairo_rectangle(cr, x - 7.0, y - 7.0, 14.0, 14.0);
            canvas.set_colour(kSwitch);
            cairo_fill(cr);
        }
    }
    for (int s = 0; s < 3; ++s) draw_start_pose(canvas, task.start_pose(s), s + 1, layout);
    draw_legend(canvas, layout, layout.py(layout.legend_y) + 14.0, state);
}

Colour circle_colour(const std::optional<kb::SegmentMatch>& match, double max_average) {
    if (!match || !match->id || !(max_average > 0.0)) return kWhite;
    return saliency_colour(match->average_reward / max_average);
}

void draw_trajectory(Canvas& canvas, const Trace& trace, const TrajectoryOptions& options,
                     const ArenaLayout& layout) {
    const int steps = static_cast<int>(trace.steps.size());
    const int first = std::clamp(options.first_step, 0, steps);
    const int last = options.last_step < 0 ? steps : std::clamp(options.last_step, first, steps);
    std::string title = options.title;
    if (title.empty()) {
        title = concat("Individual ", trace.individual_id, " (generation ", trace.generation, "), start ",
                       trace.start + 1, ", steps ", first, "-", last, ": reward ", fixed(trace.reward, 3));
    }
    // the arena as the last step drawn left it: the door, and which balls are still on the floor
    const TraceStep* end = last > first ? &trace.steps[static_cast<std::size_t>(last - 1)] : nullptr;
    draw_arena(canvas, *trace.task, end != nullptr && end->door_open,
               end ? end->lit : trace.task->initial_lit(), title, layout);
    cairo_t* cr = canvas.cr();

    const double r = options.circle_radius * layout.scale;
    CircleStamps stamps(r);
    for (int i = first; i < last; ++i) {
        const auto& step = trace.steps[static_cast<std::size_t>(i)];
        const auto match = trace.match_at(step.step);
        const double x = layout.px(step.x), y = layout.py(step.y);
        const Colour fill = circle_colour(match, trace.max_average);
        if (canvas.format() == Format::png) {
            stamps.stamp(cr, x, y, fill);
            continue;
        }
        draw_circle(cr, x, y, r, fill);
        // SVG: the exact circle, with its facts on hover
        std::string note = concat("step ", step.step);
        if (match) {
            note += concat(", segment ", static_cast<std::size_t>(step.step) / trace.segment_width);
            if (match->id) {
                note += concat(", KB segment ", *match->id, ", distance ", fixed(match->distance, 3),
                               ", average reward ", fixed(match->average_reward, 4));
            } else {
                note += ", no KB segment within delta";
            }
        }
        if (step.carrying) note += ", carrying";
        canvas.hover(x, y, r, note);
    }
    // heading marks over the circles: a tick beyond the circle along the heading
    if (options.heading_every > 0) {
        for (int i = first; i < last; ++i) {
            const auto& step = trace.steps[static_cast<std::size_t>(i)];
            if (step.step % options.heading_every != 0) continue;
            const double x = layout.px(step.x), y = layout.py(step.y);
            const double c = std::cos(step.heading), s = std::sin(step.heading);
            cairo_move_to(cr, x + c * (r + 1.0), y + s * (r + 1.0));
            cairo_line_to(cr, x + c * (r + 10.0), y + s * (r + 10.0));
            canvas.set_colour(kBlack);
            cairo_set_line_width(cr, 3.4);
            cairo_stroke_preserve(cr);
            canvas.set_colour(step.carrying ? kHeadingCarrying : kHeadingFree);
            cairo_set_line_width(cr, 1.8);
            cairo_stroke(cr);
        }
    }

    // the colour bar, then the heading key, on the legend's second and third rows
    double y = layout.py(layout.legend_y) + 38.0;
    double x = layout.left;
    if (trace.has_kb()) {
        const std::string label = "circles: average reward of the KB segment matched at that step";
        canvas.text(x, y, label, 12.0, kText, 0.0, 0.5);
        x += canvas.text_width(label, 12.0) + 10.0;
        canvas.text(x, y, "0", 12.0, kText, 0.0, 0.5);
        x += canvas.text_width("0", 12.0) + 5.0;
        const double bar = 150.0;
        for (int k = 0; k < 150; ++k) {
            cairo_rectangle(cr, x + k, y - 6.0, 1.0, 12.0);
            canvas.set_colour(saliency_colour(k / (bar - 1.0)));
            cairo_fill(cr);
        }
        cairo_rectangle(cr, x + 0.5, y - 5.5, bar - 1.0, 11.0);
        canvas.set_colour(kOutline);
        cairo_set_line_width(cr, 1.0);
        cairo_stroke(cr);
        x += bar + 5.0;
        canvas.text(x, y, fixed(trace.max_average, 3), 12.0, kText, 0.0, 0.5);
    } else {
        canvas.text(x, y, "no knowledge base: every circle is white", 12.0, kText, 0.0, 0.5);
    }
    y += 24.0;
    x = layout.left;
    for (const bool carrying : {false, true}) {
        cairo_move_to(cr, x, y);
        cairo_line_to(cr, x + 14.0, y);
        canvas.set_colour(kBlack);
        cairo_set_line_width(cr, 3.4);
        cairo_stroke_preserve(cr);
        canvas.set_colour(carrying ? kHeadingCarrying : kHeadingFree);
        cairo_set_line_width(cr, 1.8);
        cairo_stroke(cr);
        const std::string label = carrying ? "heading while carrying a ball" : "heading while carrying nothing";
        canvas.text(x + 19.0, y, label, 12.0, kText, 0.0, 0.5);
        x += 19.0 + canvas.text_width(label, 12.0) + 16.0;
    }
    if (trace.has_kb()) {
        const std::string kb = concat("KB \"", trace.kb_name, "\", r_max ", fixed(trace.r_max, 3));
        canvas.text(x + 10.0, y, kb, 12.0, kText, 0.0, 0.5);
    }
}

void draw_saliency_along_time(Canvas& canvas, const Trace& trace, const std::string& title) {
    if (!trace.has_kb()) throw DataError("saliency along time needs a knowledge base");
    Curve curve;
    curve.colour = kBlue;
    curve.steps = true;
    for (std::size_t i = 0; i < trace.segments.size(); ++i) {
        curve.x.push_back(static_cast<double>(i * trace.segment_width));
        curve.y.push_back(trace.segments[i].average_reward);
    }
    // the last segment's value held to its end
    if (!curve.x.empty()) {
        curve.x.push_back(static_cast<double>(trace.segments.size() * trace.segment_width));
        curve.y.push_back(curve.y.back());
    }
    ChartFrame frame;
    frame.title = title.empty() ? concat("Saliency along time: individual ", trace.individual_id, ", start ",
                                         trace.start + 1, " (r_max ", fixed(trace.r_max, 3), ")")
                                : title;
    frame.x_label = "time step";
    frame.y_label = "average reward of the matched KB segment";
    frame.y_range = std::pair{0.0, trace.max_average > 0.0 ? trace.max_average : 1.0};
    line_chart(canvas, frame, std::span<const Curve>(&curve, 1));
}

}  // namespace stepstone::report
