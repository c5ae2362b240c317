#!/usr/bin/env bash
# Memory of a run on several databases (docs/databases.md, "Memory"): four default-size synthetic beds
# (rcfd synth, 300 frames) recorded at four superficial velocities, and a schedule that visits each in
# turn (one switch every T_END/4 s), against a run on one of them alone, at 1 and 2 ranks.  Per run: the
# peak memory of the largest rank (the run's "peak memory" line, getrusage), the databases read and
# their load time per switch (the run's "databases:" line: reading the frames onto the layout), what a
# switch adds to the wall time against the one-database run (the load, the operators' set-up again and
# the remap), and the wall time.  With
# OLD_RCFD=path the same runs of another rcfd binary are measured as well (e.g. the one that kept the
# database the run started on, two held).  Not part of the test suite: a benchmark, several minutes.
#
#   bench/database_set_memory.sh [BUILD_DIR]
#
# Environment: VELOCITIES (default "1.0 1.1 1.2 1.3"), T_END (default 2 s), RANKS (default "1 2"),
# OLD_RCFD, WORK (default a temporary directory, removed unless KEEP=1).
# Writes the table to bench/results/database_set_memory.md and prints it.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
read -r -a velocities <<<"${VELOCITIES:-1.0 1.1 1.2 1.3}"
t_end=${T_END:-2}
read -r -a ranks <<<"${RANKS:-1 2}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=${WORK:-$(mktemp -d)}
mkdir -p "$work"
[ "${KEEP:-0}" = 1 ] || trap 'rm -rf "$work"' EXIT
binaries=("$build/rcfd")
[ -n "${OLD_RCFD:-}" ] && binaries+=("$OLD_RCFD")

files=() schedule=""
n=${#velocities[@]}
for i in "${!velocities[@]}"; do
  u=${velocities[$i]}
  db=$work/bed-$u.h5
  [ -f "$db" ] || "$build/rcfd" synth -o "$db" -synth_superficial_velocity "$u" -synth_nucleation steady \
    -superficial_velocity "$u" -quiet >/dev/null
  files+=("$db")
  schedule+="${schedule:+,}$(awk -v i="$i" -v t="$t_end" -v n="$n" 'BEGIN { print i * t / n }'):$u"
done
size=$(du -m "${files[0]}" | cut -f1)
info=$("$build/rcfd" info "${files[0]}")
cells=$(sed -n 's/.*mesh: box \([0-9x ]*\) cells.*/\1/p' <<<"$info")
frames=$(sed -n 's/.*frames: \([0-9]*\) every.*/\1/p' <<<"$info")

out=bench/results/database_set_memory.md
mkdir -p bench/results
{
  echo "# memory of a run on several databases, $(date -u +%Y-%m-%dT%H:%MZ), load average $(cut -d' ' -f1-3 /proc/loadavg)"
  echo
  echo "$n synthetic beds of ${cells:-?} cells, ${frames:-?} frames (${size} MB files), u_sup ${velocities[*]} m/s;"
  echo "schedule ${schedule} over ${t_end} s (shift,drift,carry, replay path); peak memory of the largest rank."
  echo
  echo "| rcfd | ranks | databases | switches | loads | load per switch [s] | wall per switch [s] | held at once | peak memory [MB] | wall [s] |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
} >"$out"
list=$(IFS=,; echo "${files[*]}")
for rcfd in "${binaries[@]}"; do
  for np in "${ranks[@]}"; do
    for what in one set; do
      if [ "$what" = one ]; then dbs=(-db "${files[0]}"); else dbs=(-db "$list" -db_switch_schedule "$schedule"); fi
      start=$(date +%s.%N)
      log=$(mpiexec -n "$np" "$rcfd" run "${dbs[@]}" -t_end "$t_end" -fields 0 -progress_interval 1e9 \
        -output_dir "$work/run-$what-$np" 2>&1)
      end=$(date +%s.%N)
      peak=$(sed -n 's/.*peak memory \([0-9.]*\) MB.*/\1/p' <<<"$log")
      line=$(grep 'databases:' <<<"$log" || true)
      switches=$(sed -n 's/.*databases: \([0-9]*\) switches.*/\1/p' <<<"$line")
      loads=$(sed -n 's/.* \([0-9]*\) loads in.*/\1/p' <<<"$line")
      per=$(sed -n 's/.*(\([0-9.e-]*\) s per load).*/\1/p' <<<"$line")
      held=$(sed -n 's/.*at most \([0-9]*\) held.*/\1/p;s/.*, \([0-9]*\) held at the end.*/\1 at the end/p' <<<"$line")
      wall=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')
      [ "$what" = one ] && alone=$wall
      # what a switch adds to the wall time: the set's run against the one database's, per switch
      added=$(awk -v w="$wall" -v a="$alone" -v s="${switches:-0}" 'BEGIN { if (s > 0) printf "%.2f", (w - a) / s; else print "-" }')
      printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' \
        "$(basename "$(dirname "$(dirname "$rcfd")")")/$(basename "$rcfd")" "$np" \
        "$([ "$what" = one ] && echo 1 || echo "$n")" "${switches:-0}" "${loads:-1}" "${per:--}" "$added" \
        "${held:-1}" "$peak" "$wall" >>"$out"
    done
  done
done
cat "$out"
