#!/usr/bin/env bash
# The pre-registered experiments of docs/results.md section 9, resumable.
#   e1   the positive control: 3 paper-size source runs, the best one's KB at
#        delta 1.83, then none / sum / sum-rand x 20 seeds on the source task
#   e2   the target task with E1's KB: none / sum / sum-rand x 20 seeds
#   csv  the statistics of whatever has finished, into docs/results/:
#        e1_events.csv, e1_logrank.csv, e1_runs.csv, e1_tests.csv (and e2_*),
#        the Kaplan-Meier figure as e1_kaplan_meier.png
# Campaign directories go under OUT (default: experiments/), never into git.
# Run a step again after an interruption: finished runs are kept (campaign --resume).
#
# Usage: docs/results/experiments.sh e1|e2|csv [OUT] [STEPSTONE] [JOBS]
#   e.g. nice docs/results/experiments.sh e1 /work/exp build/release/apps/stepstone/stepstone 2
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
step="${1:?usage: experiments.sh e1|e2|csv [OUT] [STEPSTONE] [JOBS]}"
out="${2:-experiments}"
stepstone="${3:-stepstone}"
jobs="${4:-2}"
mkdir -p "$out"
out="$(realpath "$out")"

campaign() {  # NAME CONFIG
    local dir="$out/$1"
    if [ -f "$dir/campaign.db" ]; then
        "$stepstone" campaign "$2" --dir "$dir" --jobs "$jobs" --resume --quiet
    else
        "$stepstone" campaign "$2" --dir "$dir" --jobs "$jobs" --quiet
    fi
}

stats() {  # NAME: the CSVs and the Kaplan-Meier figure of the runs that have finished
    local dir="$out/$1"
    [ -f "$dir/campaign.db" ] || { echo "experiments.sh: $dir has no campaign yet" >&2; return 0; }
    local last
    last="$(sqlite3 "$dir/campaign.db" "SELECT max(generations) FROM campaign_run WHERE step = 'target'")"
    "$stepstone" stats "$dir" --available --generation "$last" --force \
        --events-csv "$here/$1_events.csv" --logrank-csv "$here/$1_logrank.csv" \
        --runs-csv "$here/$1_runs.csv" --tests-csv "$here/$1_tests.csv" > "$here/$1_stats.txt"
    "$stepstone" report "$dir" --out "$out/$1-report" --force --quiet
    cp "$out/$1-report/kaplan-meier.png" "$here/figures/$1_kaplan_meier.png"
    cp "$out/$1-report/milestone-shares.png" "$here/figures/$1_milestone_shares.png"
    /usr/bin/python3 "$repo/scripts/logrank-check" "$here/$1_events.csv" "$here/$1_logrank.csv" > /dev/null
}

case "$step" in
    e1) campaign e1 "$repo/examples/experiments/e1_positive_control.json" ;;
    e2)
        [ -f "$out/e1/kb/kb.db" ] || { echo "experiments.sh: run e1 first (its KB is $out/e1/kb/kb.db)" >&2; exit 1; }
        ln -sf "$out/e1/kb/kb.db" "$repo/examples/experiments/source_kb.db"
        campaign e2 "$repo/examples/experiments/e2_target.json" ;;
    csv) stats e1; stats e2 ;;
    *) echo "experiments.sh: unknown step '$step' (e1, e2 or csv)" >&2; exit 2 ;;
esac
