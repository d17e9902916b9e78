// The Kaplan-Meier figure's content: where the step curves sit, read back
// from the PNG's pixels, against the estimates worked out by hand.

#include "report/event_figures.hpp"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <optional>

#include "images.hpp"
#include "report/canvas.hpp"
#include "runs/campaign_events.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using namespace stepstone::report;

namespace {

// the topmost row of column x whose pixel is near `colour` (within 40 per channel), within [y0, y1)
std::optional<int> first_row(const reporttest::Image& image, int x, int y0, int y1, reporttest::Rgb colour) {
    for (int y = y0; y < y1; ++y) {
        const auto p = image.at(x, y);
        if (std::abs(p.r - colour.r) < 40 && std::abs(p.g - colour.g) < 40 && std::abs(p.b - colour.b) < 40)
            return y;
    }
    return std::nullopt;
}

}  // namespace

TEST_CASE("the Kaplan-Meier panels draw each treatment's estimate where the hand computation puts it",
          "[report][figures][events]") {
    // none: 4 runs, 1 presses at generation 50, 3 are censored at 100: S = 1 before 50, 3/4 after.
    // sum: 4 runs, all press at generation 50: S = 0 after 50
    std::vector<runs::RunEvents> runs;
    for (int k = 0; k < 4; ++k) {
        runs::FirstEvents none, sum;
        if (k == 0) none[0] = 50;
        sum[0] = 50;
        runs.push_back({runs::Treatment::none, static_cast<std::uint64_t>(k), none});
        runs.push_back({runs::Treatment::sum, static_cast<std::uint64_t>(k), sum});
    }
    const runs::Treatment order[] = {runs::Treatment::none, runs::Treatment::sum};
    const auto events = runs::campaign_events(runs, order, 100);
    Canvas canvas(kPanelFigureWidth, kPanelFigureHeight, Format::png);
    draw_kaplan_meier(canvas, events);
    const std::string bytes = canvas.finish();
    const auto image = reporttest::decode_png(bytes);
    if (const char* keep = std::getenv("STEPSTONE_KEEP_FIGURE")) test::write_file(keep, bytes);

    // the press panel is the top-left one: sample columns 30 % and 70 % across it (generations ~20 and ~65),
    // below the title and above the at-risk table
    const int panel_w = kPanelFigureWidth / 2;
    const int left_x = panel_w * 30 / 100, right_x = panel_w * 70 / 100;  // clear of the legend (top right)
    const int y0 = 40, y1 = kPanelFigureHeight / 2 - 95;  // above the axis label and the table
    const reporttest::Rgb black{0, 0, 0}, blue{0x00, 0x72, 0xB2};
    // before generation 50 both curves are at S = 1 (sum, drawn last, on top of none)
    const auto top = first_row(image, left_x, y0, y1, blue);
    REQUIRE(top);
    // after 50: none at S = 3/4, a quarter of the way from S = 1 to the axis line at S = 0; sum's curve
    // ended at 50 with S = 0 (no run left to follow), so no blue pixel lies above that axis
    const auto quarter = first_row(image, right_x, y0, y1, black);
    REQUIRE(quarter);
    const auto axis = first_row(image, right_x, *quarter + 5, y1, reporttest::Rgb{0x55, 0x55, 0x55});
    REQUIRE(axis);
    CHECK(*axis - *top > 200);
    CHECK(std::abs((*quarter - *top) - (*axis - *top) / 4) <= 3);
    CHECK_FALSE(first_row(image, right_x, y0, *axis - 2, blue));
    // the runs at risk under the axis: none keeps its 3 censored runs after 50, sum none
    CHECK(events.summaries[0].curve.at_risk(60) == 3);
    CHECK(events.summaries[1].curve.at_risk(60) == 0);
}

TEST_CASE("the Kaplan-Meier legend moves to the bottom corner when the curves stay high",
          "[report][figures][events]") {
    // 10 runs of none, one presses at generation 5, the others are censored at 100: S = 0.9 from 5 on, a
    // line in the top corner where the legend would cover it with its translucent white box
    std::vector<runs::RunEvents> runs;
    for (int k = 0; k < 10; ++k) {
        runs::FirstEvents none;
        if (k == 0) none[0] = 5;
        runs.push_back({runs::Treatment::none, static_cast<std::uint64_t>(k), none});
    }
    const runs::Treatment order[] = {runs::Treatment::none};
    const auto events = runs::campaign_events(runs, order, 100);
    Canvas canvas(kPanelFigureWidth, kPanelFigureHeight, Format::png);
    draw_kaplan_meier(canvas, events);
    const auto image = reporttest::decode_png(canvas.finish());
    const int panel_w = kPanelFigureWidth / 2;
    const int y0 = 40, y1 = kPanelFigureHeight / 2 - 95;
    const reporttest::Rgb black{0, 0, 0};
    // the S = 0.9 line found at 30 % across the press panel, then at 90 % across, under the legend's corner
    const auto line = first_row(image, panel_w * 30 / 100, y0 + 20, y1, black);
    REQUIRE(line);
    const auto right = first_row(image, panel_w * 90 / 100, *line - 3, *line + 4, black);
    CHECK(right);  // drawn in full, not washed out by the legend box
}
