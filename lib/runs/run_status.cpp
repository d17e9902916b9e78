#include "runs/run_status.hpp"

#include <array>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::runs {

namespace {

constexpr std::array kStatuses = {RunStatus::pending, RunStatus::running, RunStatus::finished,
                                  RunStatus::failed};
constexpr std::array kSteps = {CampaignStep::source, CampaignStep::target};

// the value of `values` whose text is `text`
template <class Enum, std::size_t N>
Enum parse(const std::array<Enum, N>& values, std::string_view text, const std::string& what,
           const char* names) {
    for (const Enum value : values) {
        if (text == to_string(value)) return value;
    }
    throw DatabaseError(concat(what, " must be one of ", names, ", got \"", text, '"'));
}

}  // namespace

std::string_view to_string(RunStatus status) {
    switch (status) {
        case RunStatus::pending:
            return "pending";
        case RunStatus::running:
            return "running";
        case RunStatus::finished:
            return "finished";
        case RunStatus::failed:
            return "failed";
    }
    return "pending";
}

RunStatus parse_run_status(std::string_view text, const std::string& what) {
    return parse(kStatuses, text, what, "pending|running|finished|failed");
}

std::string_view to_string(CampaignStep step) { return step == CampaignStep::source ? "source" : "target"; }

CampaignStep parse_campaign_step(std::string_view text, const std::string& what) {
    return parse(kSteps, text, what, "source|target");
}

}  // namespace stepstone::runs
