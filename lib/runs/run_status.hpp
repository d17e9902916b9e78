#pragma once

#include <string>
#include <string_view>

namespace stepstone::runs {

// A run's status and a campaign run's step, as enums in the code and as text
// in the databases (run.status, campaign_run.status, campaign_run.step). The
// text is converted only where rows are written or read, as Treatment's is.

/// Where a run stands. A run file's `run.status` is running or finished; a
/// campaign's `campaign_run.status` is any of the four.
enum class RunStatus {
    pending,   ///< planned, not started
    running,   ///< started, not finished (or killed while running)
    finished,  ///< every generation asked for is committed
    failed,    ///< its evolve process failed (campaigns only)
};
/// "pending", "running", "finished" or "failed".
std::string_view to_string(RunStatus status);
/// Parses a stored status; throws DatabaseError naming `what` (the file and
/// column) for any other text.
RunStatus parse_run_status(std::string_view text, const std::string& what);

/// The step of a campaign a run belongs to.
enum class CampaignStep {
    source,  ///< the source task, whose runs make the knowledge base
    target,  ///< the target task, one run per treatment and seed
};
/// "source" or "target" (also the step's folder and config file name).
std::string_view to_string(CampaignStep step);
/// Parses a stored step; throws DatabaseError naming `what` for any other text.
CampaignStep parse_campaign_step(std::string_view text, const std::string& what);

}  // namespace stepstone::runs
