#!/usr/bin/env bash
# The replication's two cheap cause tests (docs/results.md, section 6): the `sum`
# treatment of examples/campaign_replication.json rerun on the same 5 seeds with
#   delta/   the source run's own KB at delta 1.83 (not coarsened to 3.84)
#   nearest/ the replication's KB at 3.84 under the `nearest` match rule
# Everything else is the replication's target step. Resumable: run it again
# with the same arguments after an interruption.
#
# Usage: cause_tests.sh REPLICATION_DIR OUT_DIR [STEPSTONE] [JOBS]
#   e.g. docs/results/cause_tests.sh replication causes build/release/apps/stepstone/stepstone 2
set -euo pipefail
rep="$(realpath "$1")"
out="$2"
stepstone="${3:-stepstone}"
jobs="${4:-1}"
mkdir -p "$out"
out="$(realpath "$out")"

# the KBs: the source run's own, and a copy of the replication's under `nearest`
[ -f "$out/kb-1.83.db" ] || "$stepstone" kb export "$rep/source/seed-1.db" --out "$out/kb-1.83.db"
if [ ! -f "$out/kb-nearest.db" ]; then
    cp "$rep/kb/kb.db" "$out/kb-nearest.tmp"
    sqlite3 "$out/kb-nearest.tmp" "UPDATE kb SET match = 'nearest'"
    mv "$out/kb-nearest.tmp" "$out/kb-nearest.db"
fi

for variant in delta nearest; do
    kb="$out/kb-1.83.db"
    [ "$variant" = nearest ] && kb="$out/kb-nearest.db"
    cat > "$out/$variant.json" <<JSON
{
  "kb": {"file": "$kb"},
  "target": {
    "config": {
      "task": {"kind": "target", "steps_per_start": 4000, "starts": 3},
      "ea": {"population_size": 100, "generations": 500}
    },
    "runs": 5,
    "generations": 500,
    "treatments": ["sum"]
  }
}
JSON
    resume=()
    [ -f "$out/$variant/campaign.db" ] && resume=(--resume)
    "$stepstone" campaign "$out/$variant.json" --dir "$out/$variant" --jobs "$jobs" "${resume[@]}"
done
