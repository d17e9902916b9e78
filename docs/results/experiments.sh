#!/usr/bin/env bash
# The pre-registered experiments of docs/results.md section 9, resumable.
#   e1   the positive control: 3 paper-size source runs, the best one's KB at
#        delta 1.83, then none / sum / sum-rand x 20 seeds on the source task
#   e2   the target task with E1's KB: none / sum / sum-rand x 20 seeds
#   e2c  E2's completion on a machine without E1's and E2's files: the KB
#        rebuilt from source seed 1 alone, then seeds 2012-2020 of the 3 arms
#        (2012 of none was already run: a reproducibility check), see
#        docs/results.md section 9, deviations
#   src1 E1's source run of seed 1 rebuilt alone (OUT/source-1/seed-1.db) and its KB
#        exported (OUT/source-1/kb.db); stops unless the run digest is E1's
#   l    experiment L (docs/results.md section 10): none / sum x 40 seeds x 2000
#        generations on the target task with the KB of src1, one run at a time;
#        stops unless the campaign recorded E1's KB digest
#   lcsv L's statistics so far into docs/results/l_*.csv (interim until 40 an arm)
#   e4   experiment E4 (docs/results.md section 12): none / seed / sum x 20 seeds x 300
#        generations, seeded from and shaped by src1's run and KB
#   e4csv E4's statistics so far into docs/results/e4_*.csv (interim until 20 an arm)
#   (the statistics steps need a build with stats --hazard-csv: 0.2.0 or later)
#   csv  the statistics of whatever has finished, into docs/results/:
#        e1_events.csv, e1_logrank.csv, e1_runs.csv, e1_tests.csv (and e2_*),
#        the Kaplan-Meier figure as e1_kaplan_meier.png; with e2c, its CSVs
#        as e2_part2_* and E2 as the pool of e2_part1_* (the 34 runs of the
#        first machine) and e2_part2_*
# Campaign directories go under OUT (default: experiments/), never into git.
# Run a step again after an interruption: finished runs are kept (campaign --resume).
#
# Usage: docs/results/experiments.sh e1|e2|e2c|src1|l|lcsv|e4|e4csv|csv [OUT] [STEPSTONE] [JOBS]
#   e.g. nice docs/results/experiments.sh e1 /work/exp build/release/apps/stepstone/stepstone 2
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
step="${1:?usage: experiments.sh e1|e2|e2c|src1|l|lcsv|e4|e4csv|csv [OUT] [STEPSTONE] [JOBS]}"
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

stats() {  # NAME [PREFIX]: the CSVs and the Kaplan-Meier figure of the runs that have finished
    local dir="$out/$1" name="${2:-$1}"
    [ -f "$dir/campaign.db" ] || { echo "experiments.sh: $dir has no campaign yet" >&2; return 0; }
    local last
    last="$(sqlite3 "$dir/campaign.db" "SELECT max(generations) FROM campaign_run WHERE step = 'target'")"
    "$stepstone" stats "$dir" --available --generation "$last" --force \
        --events-csv "$here/${name}_events.csv" --logrank-csv "$here/${name}_logrank.csv" \
        --runs-csv "$here/${name}_runs.csv" --tests-csv "$here/${name}_tests.csv" \
        --hazard-csv "$here/${name}_hazard.csv" > "$here/${name}_stats.txt"
    "$stepstone" report "$dir" --out "$out/$1-report" --force --quiet
    cp "$out/$1-report/kaplan-meier.png" "$here/figures/${name}_kaplan_meier.png"
    cp "$out/$1-report/milestone-shares.png" "$here/figures/${name}_milestone_shares.png"
    cp "$out/$1-report/treatment-rewards.png" "$here/figures/${name}_rewards.png"
    /usr/bin/python3 "$repo/scripts/logrank-check" "$here/${name}_events.csv" "$here/${name}_logrank.csv" > /dev/null
    /usr/bin/python3 "$repo/scripts/hazard-check" "$here/${name}_events.csv" "$here/${name}_hazard.csv" > /dev/null
}

pool_e2() {  # E2 = every part's runs (e2_part1_*: the first machine's 34, e2_part2_*: e2c's, ...), pooled
    [ -f "$here/e2_part2_runs.csv" ] || return 0
    local program
    program="$(realpath "$stepstone" 2>/dev/null || command -v "$stepstone")"
    # in docs/results, so that the text names the inputs as the repository does
    (cd "$here" && runs=(e2_part*_runs.csv) && events=(e2_part*_events.csv) &&
        "$program" pool --runs "${runs[@]}" --events "${events[@]}" --force \
            --runs-csv e2_runs.csv --events-csv e2_events.csv --tests-csv e2_tests.csv \
            --logrank-csv e2_logrank.csv --kaplan-meier figures/e2_kaplan_meier.png > e2_stats.txt &&
        { echo; "$program" pool --runs "${runs[@]}" --events "${events[@]}" --event release |
            sed -n "/^time to first/,\$p"; } >> e2_stats.txt)
    /usr/bin/python3 "$repo/scripts/logrank-check" "$here/e2_events.csv" "$here/e2_logrank.csv" > /dev/null
}

e1_run_digest=4ac92bd112bdeb45
e1_kb_digest=3bd55b8ecc1c0c6c1b844eea1842ce9d

src1() {  # E1's seed-1 source run and its KB, digest-checked
    local dir="$out/source-1"
    mkdir -p "$dir"
    if [ -f "$dir/seed-1.db" ]; then
        "$stepstone" evolve --db "$dir/seed-1.db" --resume --quiet
    else
        "$stepstone" evolve --config "$repo/examples/source_paper.json" --db "$dir/seed-1.db" --seed 1 --quiet
    fi
    local digest
    digest="$("$stepstone" db digest "$dir/seed-1.db")"
    case "$digest" in
        "$e1_run_digest"*) echo "experiments.sh: source seed 1 has E1's run digest $digest" ;;
        *) echo "experiments.sh: source seed 1 digest $digest is not E1's $e1_run_digest..." >&2; exit 1 ;;
    esac
    [ -f "$dir/kb.db" ] || "$stepstone" kb export "$dir/seed-1.db" --out "$dir/kb.db"
}

l_run() {
    [ -f "$out/source-1/kb.db" ] || { echo "experiments.sh: run src1 first" >&2; exit 1; }
    ln -sf "$out/source-1/kb.db" "$repo/examples/experiments/source_kb.db"
    if [ -f "$out/l/campaign.db" ]; then  # the KB the campaign recorded at its start must be E1's
        local kb
        kb="$(sqlite3 "$out/l/campaign.db" "SELECT digest FROM campaign_kb ORDER BY name LIMIT 1")"
        [ "$kb" = "$e1_kb_digest" ] || { echo "experiments.sh: L's KB digest $kb is not E1's $e1_kb_digest" >&2; exit 1; }
    fi
    campaign l "$repo/examples/experiments/l_horizon.json"
}

case "$step" in
    e1) campaign e1 "$repo/examples/experiments/e1_positive_control.json" ;;
    e2)
        [ -f "$out/e1/kb/kb.db" ] || { echo "experiments.sh: run e1 first (its KB is $out/e1/kb/kb.db)" >&2; exit 1; }
        ln -sf "$out/e1/kb/kb.db" "$repo/examples/experiments/source_kb.db"
        campaign e2 "$repo/examples/experiments/e2_target.json" ;;
    e2c) campaign e2c "$repo/examples/experiments/e2_completion.json" ;;
    src1) src1 ;;
    l) l_run ;;
    lcsv) stats l ;;
    e4)
        [ -f "$out/source-1/kb.db" ] || { echo "experiments.sh: run src1 first" >&2; exit 1; }
        ln -sf "$out/source-1/kb.db" "$repo/examples/experiments/source_kb.db"
        ln -sf "$out/source-1/seed-1.db" "$repo/examples/experiments/source_run.db"
        campaign e4 "$repo/examples/experiments/e4_reuse.json" ;;
    e4csv)
        stats e4
        for event in release ball; do  # the primary endpoint (ball) and its precursor, as text
            echo
            "$stepstone" stats "$out/e4" --available --generation 300 --event "$event" |
                sed -n "/^time to first/,\$p"
        done >> "$here/e4_stats.txt"
        /usr/bin/python3 "$here/e4_fisher.py" "$here/e4_runs.csv" > "$here/e4_fisher.csv" ;;
    csv) stats e1; stats e2; stats e2c e2_part2; pool_e2 ;;
    *) echo "experiments.sh: unknown step '$step' (e1, e2, e2c, src1, l, lcsv, e4, e4csv or csv)" >&2; exit 2 ;;
esac
