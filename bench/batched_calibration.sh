#!/usr/bin/env bash
# Wall and CPU time of scanning drift laws on dpm-bi-narrow (issue 21, "calibration at the speed of
# one run"): one replay, the 13 laws of cases/dpm-bi-narrow/drift_laws.sh as 13 rcfd run processes
# (what that script did), as one rcfd calibrate -calibrate_candidates one by one (-calibrate_batch
# false) and batched (the default), and a k_d search of two laws (rcfd calibrate -calibrate_models
# B,drag) one by one and batched.  Median of RUNS (default 3) of each, 1 rank: wall and CPU
# (user + system) of the whole process, and rcfd calibrate's own wall time of its replays.
#   bench/batched_calibration.sh [BUILD] [WORK_DIR]    (defaults: build, /tmp/rcfd-batched-bench)
# Needs ../shared/reference/dpm-bi-narrow (SHARED); makes the database as drift_laws.sh does.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rcfd=$(cd "${1:-$root/build}" && pwd)/rcfd
work=${2:-/tmp/rcfd-batched-bench}
shared=${SHARED:-$root/../shared/reference}
runs=${RUNS:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$work"
ref=$shared/dpm-bi-narrow
input=(-dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" -mesh_cells 16,2,60)
[ -f "$work/narrow-t02.h5" ] || "$rcfd" build "${input[@]}" -window 39,-1 -o "$work/narrow-t02.h5" \
  -init_out "$work/narrow-init.h5" -quiet
[ -f "$work/narrow-ref/cog.csv" ] || "$rcfd" reference "${input[@]}" -average_window 0.5,1.5 -o "$work/narrow-ref" >/dev/null
narrow=(-options_file "$root/cases/dpm-bi-narrow/case.yaml" -db "$work/narrow-t02.h5" -init_file "$work/narrow-init.h5"
  -t_end 3.29)
sed -n '/^laws=(/,/^)/p' "$root/cases/dpm-bi-narrow/drift_laws.sh" | sed -n 's/^ *"\([^|]*\)|\(.*\)"$/\1 \2/p' >"$work/laws.txt"
[ "$(wc -l <"$work/laws.txt")" -ge 2 ] || { echo "no laws read from drift_laws.sh" >&2; exit 1; }
score=(-reference "$work/narrow-ref/cog.csv" -rcfd_time_offset 0.2)

# timed LABEL COMMAND...: appends "LABEL wall cpu" (s) of the whole command to $work/times.txt.
timed() {
  local label=$1 TIMEFORMAT='%R %U %S'
  shift
  { time "$@" >"$work/last.txt" 2>&1; } 2>"$work/time.txt"
  # rcfd calibrate's own wall time of the replays (the process less start-up, loading and writing)
  local replays=$(sed -n 's/^replays: \([0-9.e+-]*\) s wall.*/\1/p' "$work/last.txt")
  echo "$label $(awk '{ print $1, $2 + $3 }' "$work/time.txt") ${replays:-nan}" >>"$work/times.txt"
}
separate() { # the laws as separate rcfd run processes
  while read -r name opts; do
    read -r -a opt <<<"$opts"
    "$rcfd" run "${narrow[@]}" "${opt[@]}" -output_dir "$work/separate/$name" -quiet -plot false
  done <"$work/laws.txt"
}
rm -f "$work/times.txt"
for ((r = 0; r < runs; ++r)); do
  timed single "$rcfd" run "${narrow[@]}" -drift_model B -drift_kd 1.732e4 -drift_agitation leaving \
    -drift_agitation_exponent 2 -output_dir "$work/single" -quiet -plot false
  timed separate separate
  timed laws-one-by-one "$rcfd" calibrate "${narrow[@]}" "${score[@]}" -calibrate_candidates "$work/laws.txt" \
    -output_dir "$work/alone" -calibrate_batch false
  timed laws-batched "$rcfd" calibrate "${narrow[@]}" "${score[@]}" -calibrate_candidates "$work/laws.txt" \
    -output_dir "$work/batched"
  timed search-one-by-one "$rcfd" calibrate "${narrow[@]}" "${score[@]}" -calibrate_models B,drag \
    -output_dir "$work/search-alone" -calibrate_batch false
  timed search-batched "$rcfd" calibrate "${narrow[@]}" "${score[@]}" -calibrate_models B,drag \
    -output_dir "$work/search-batched"
done
# The same numbers either way (the runs of one process, 1 rank).
for f in calibrate_candidates.csv $(cut -d' ' -f1 "$work/laws.txt" | sed 's|$|/cog.csv|'); do
  cmp -s "$work/alone/$f" "$work/batched/$f" || { echo "batched and one-by-one differ in $f" >&2; exit 1; }
done
for f in calibrate_scan.csv calibrate_best.csv; do
  cmp -s "$work/search-alone/$f" "$work/search-batched/$f" || { echo "batched and one-by-one differ in $f" >&2; exit 1; }
done
replays=$(grep -c . "$work/laws.txt")
searched=$(sed -n 's/^\([0-9]*\) replay runs.*/\1/p' "$work/last.txt")
echo "$(date -u '+%Y-%m-%d %H:%M UTC'), load average $(cut -d' ' -f1-3 /proc/loadavg), $runs runs each (median)"
echo "| what | replays | wall s | CPU s | wall / single run | replays' own wall s |"
echo "|---|---|---|---|---|---|"
python3 - "$work/times.txt" "$replays" "$searched" <<'P'
import sys, statistics as st
rows = {}
for line in open(sys.argv[1]):
    label, wall, cpu, own = line.split()
    rows.setdefault(label, []).append((float(wall), float(cpu), float(own)))
n, searched = sys.argv[2], sys.argv[3]
single = st.median(v[0] for v in rows["single"])
count = {"single": "1", "separate": n, "laws-one-by-one": n, "laws-batched": n,
         "search-one-by-one": searched, "search-batched": searched}
for label, values in rows.items():
    wall, cpu, own = (st.median(v[k] for v in values) for k in range(3))
    own = "" if own != own else f"{own:.2f}"
    print(f"| {label} | {count[label]} | {wall:.2f} | {cpu:.2f} | {wall / single:.2f} | {own} |")
P
