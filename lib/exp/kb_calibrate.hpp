#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "kb/calibrate.hpp"
#include "kb/knowledge_base.hpp"

namespace stepstone::exp {

// The work behind `stepstone kb calibrate`: the paper's delta rule on a stored
// policy and the KB size per delta over a run's policies. The run file is
// opened read-only.

/// The delta rule and the KB size table computed from behaviours.
struct Calibration {
    std::size_t segment_width = 0;                    ///< steps per segment used
    std::size_t channels = 0;                         ///< channels of the behaviours
    std::size_t neighbours = kb::kDefaultNeighbours;  ///< the "20 closest" of the rule
    std::size_t segments = 0;                         ///< segments of the calibrating policy
    double delta = 0.0;                               ///< kb::calibrate_delta on the calibrating policy
    std::size_t policies = 0;                         ///< policies fed to the size table
    std::vector<kb::DeltaSize> sizes;                 ///< KB size per delta, in the order asked
};

/// The paper's delta rule on `policy` (a behaviour matrix: rows = steps,
/// `channels` columns) and, for each of `deltas`, the size of a KB fed with
/// `policies` in order. Throws DataError for bad behaviours (too few
/// segments, NaN) and ConfigError for a delta <= 0.
Calibration calibrate_behaviours(std::span<const float> policy, std::span<const std::vector<float>> policies,
                                 std::size_t channels, std::size_t segment_width,
                                 std::span<const double> deltas,
                                 std::size_t neighbours = kb::kDefaultNeighbours);

/// How `kb calibrate` reads the rule's "20 closest behaviors during 4000 time steps".
enum class DeltaReading {
    segments,  ///< the policy's non-overlapping segments (kb::calibrate_delta)
    windows,   ///< every window of the segment width at stride 1, both variants (kb::calibrate_delta_windows)
};

/// "segments" or "windows".
const char* to_string(DeltaReading reading);

/// What `kb calibrate` reads from a run file.
struct CalibrateOptions {
    DeltaReading reading = DeltaReading::segments;  ///< which reading of the rule
    std::string individual = "best";           ///< the successful policy: "best" or an id
    std::optional<std::size_t> segment_width;  ///< absent: the run KB's, else kb::kDefaultSegmentWidth
    std::string width_name = "segment_width";  ///< how messages name segment_width (a caller's flag)
    std::vector<double> deltas;                ///< the size table's deltas (empty: no table)
    std::size_t neighbours = kb::kDefaultNeighbours;
    unsigned threads = 0;                         ///< replays and KBs at once (0 = every core)
    std::size_t batch = 256;                      ///< policies replayed per batch (bounds memory)
    ProgressMode progress = ProgressMode::quiet;  ///< policies replayed, on stderr
};

/// Where the segment width of a calibration came from.
enum class WidthSource {
    option,         ///< CalibrateOptions::segment_width
    run_kb,         ///< the run's own knowledge base
    default_width,  ///< kb::kDefaultSegmentWidth
};

/// calibrate_behaviours on a run: the replayed behaviour of `individual` and
/// of every stored genome (in individual id order). The genomes are replayed
/// `batch` at a time on `threads` threads (first start only: the behaviour
/// is the first start's), then each batch is observed, in id order, into one
/// KB per delta, the KBs side by side on the same threads; the sizes do not
/// depend on `threads` or `batch`. Throws ConfigError naming
/// `options.width_name` for a width of 0 or one longer than the behaviours.
struct RunCalibration {
    std::int64_t individual_id = 0;  ///< the calibrating policy
    double reward = 0.0;             ///< its stored reward
    WidthSource width_from = WidthSource::default_width;
    Calibration calibration;
    DeltaReading reading = DeltaReading::segments;
    /// The windows reading (with DeltaReading::windows); calibration.delta is the segments reading in any
    /// case.
    std::optional<kb::WindowDeltas> windows;
};
RunCalibration calibrate_run(const std::filesystem::path& run_db, const CalibrateOptions& options);

/// Parses "0.5,1,1.83" into deltas; throws ConfigError naming `what` (the
/// caller's name for the list) for an empty item, a non-number or a value
/// that is not finite and > 0.
std::vector<double> parse_deltas(const std::string& text, const std::string& what);

}  // namespace stepstone::exp
