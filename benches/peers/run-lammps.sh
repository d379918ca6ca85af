#!/usr/bin/env bash
# LAMMPS peer of `facets bench`: builds each settled deposit once (cached), then times
# `steps` steps at dt = 1e-6 s on 1 and 2 MPI processes. Prints a table and writes
# benches/peers/lammps-results.csv.
#
# Usage: benches/peers/run-lammps.sh [CASE:N[:STEPS[:LAYOUT]] ...]
#   default: squares:3000 squares:30000:1000:side squares:30000:1000:stacked (rods:5000 crashes
#   LAMMPS 2021 while settling: README, "Differences" 10)
#   N > 10 000: 10 settled deposits of N/10 grains, LAYOUT `side` by side in a box 10 times as
#   wide or `stacked` in the same box (the default; see README).
# Environment: STEPS (timed steps, default 20000), NPS (process counts, default "1 2";
#   0 builds the settled deposits only),
#   WORK (scratch dir for data, restarts and logs, default benches/peers/lammps/work).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
lmpdir="$here/lammps"
work="${WORK:-$lmpdir/work}"
steps="${STEPS:-20000}"
nps="${NPS:-1 2}"
cases=("$@")
[ ${#cases[@]} -eq 0 ] && cases=(squares:3000 squares:30000:1000:side squares:30000:1000:stacked)
mkdir -p "$work"

command -v lmp >/dev/null || { echo "lmp not found: run benches/peers/install-lammps.sh" >&2; exit 1; }
mpirun_cmd=(mpirun --oversubscribe -np)
[ "$(id -u)" = 0 ] && mpirun_cmd=(mpirun --allow-run-as-root --oversubscribe -np)

# Settling parameters (not timed): terminal fall speed under the drag (keeps impact overlaps
# below r_i + r_j), settling time step, rest check every `chunk` steps.
settle_args() {
  case "$1" in
    squares) echo "-var vterm 2.0" ;;
    rods) echo "-var vterm 1.5" ;;
    *) echo "unknown case $1" >&2; exit 1 ;;
  esac
}

# Build the settled deposit of the grid rule (make_data.py + in.settle), once.
settle_grid() { # name n base
  local name="$1" n="$2" base="$3"
  python3 "$lmpdir/make_data.py" "$name" "$n" "$base.data" "$base.params"
  echo "settling $name N=$n (log: $base.settle.log) ..." >&2
  # shellcheck disable=SC2046
  nice lmp -in "$lmpdir/in.settle" -log "$base.settle.log" -screen none \
    -var common "$lmpdir/common.lmp" -var start "read_data $base.data" \
    -var params "$base.params" -var restart "$base.restart.tmp" -var mu_lmp 0.0 \
    -var lmpdir "$lmpdir" -var dt_settle 2e-5 -var relax_time 0.2 -var quench_time 0.05 \
    $(settle_args "$name")
  grep -E "^(RELAXED|SETTLED)" "$base.settle.log" >&2
  mv "$base.restart.tmp" "$base.restart"
}

csv_rows=()
printf '%-15s %7s %5s %7s %10s %14s %8s\n' case N procs steps wall_s grain_steps_s cpu_use%
for spec in "${cases[@]}"; do
  IFS=: read -r name n case_steps layout <<<"$spec"
  case_steps="${case_steps:-$steps}"
  label="$name"
  base="$work/${name}_$n"
  xcopies=1
  if [ "$n" -gt 10000 ]; then
    # 10 copies of the settled deposit of N/10 grains, timed as they are (README,
    # "Differences" 8): side by side (same depth and load) or stacked with 5 mm gaps.
    layout="${layout:-stacked}"
    sub=$((n / 10)); subbase="$work/${name}_$sub"
    [ -s "$subbase.restart" ] || settle_grid "$name" "$sub" "$subbase"
    base="$work/${name}_${n}_$layout"
    label="$name-$layout"
    cp "$subbase.params" "$base.params"
    case "$layout" in
      side) start="include $lmpdir/side_start.lmp"; xcopies=10 ;;
      stacked) start="include $lmpdir/stack_start.lmp" ;;
      *) echo "case $spec: layout \`$layout\`: expected side or stacked" >&2; exit 1 ;;
    esac
    source="$subbase.restart"
  else
    [ -s "$base.restart" ] || settle_grid "$name" "$n" "$base"
    start="read_restart $base.restart"
    source=none
  fi
  for np in $nps; do
    [ "$np" = 0 ] && continue # NPS=0: build the deposits only
    log="$base.bench.np$np.log"
    if [ "$np" = 1 ]; then run=(lmp); else run=("${mpirun_cmd[@]}" "$np" lmp); fi
    "${run[@]}" -in "$lmpdir/in.bench" -log "$log" -screen none \
      -var common "$lmpdir/common.lmp" -var start "$start" -var source "$source" -var copies 10 -var xcopies "$xcopies" \
      -var params "$base.params" -var mu_lmp 0.0 -var lmpdir "$lmpdir" \
      -var dt_bench 1e-6 -var steps "$case_steps"
    # "Loop time of T on P procs for S steps with M atoms" of the timed run
    read -r wall procs nsteps atoms < <(awk '/^Loop time of/ {print $4, $6, $9, $12}' "$log" | tail -1)
    # "X% CPU use with P MPI tasks": the share of a core each task got (the machine is shared)
    cpu=$(awk '/% CPU use with/ {sub("%", "", $1); print $1}' "$log" | tail -1)
    rate=$(awk -v a="$atoms" -v s="$nsteps" -v w="$wall" 'BEGIN {printf "%.4g", a*s/w}')
    printf '%-15s %7s %5s %7s %10.3f %14s %8s\n' "$label" "$atoms" "$procs" "$nsteps" "$wall" "$rate" "$cpu"
    csv_rows+=("$label,$atoms,$procs,mpi,$nsteps,1e-6,$wall,$rate,$cpu")
  done
done

# Merge into the CSV: rows of this run replace those of the same case, N and process count;
# rows of other cases (measured by an earlier invocation) are kept.
out="$here/lammps-results.csv"
header="case,n_grains,processes,parallelism,timed_steps,dt_s,wall_s,grain_steps_per_s,cpu_use_percent,measured_utc"
stamp="$(date -u +%Y-%m-%dT%H:%MZ)"
{
  echo "$header"
  {
    [ -s "$out" ] && tail -n +2 "$out" | awk -F, -v new="$(printf '%s\n' "${csv_rows[@]}")" '
      BEGIN { n = split(new, rows, "\n"); for (i = 1; i <= n; i++) { split(rows[i], f, ","); seen[f[1] "," f[2] "," f[3]] = 1 } }
      !(($1 "," $2 "," $3) in seen)'
    for row in "${csv_rows[@]}"; do echo "$row,$stamp"; done
  } | sort -t, -k1,1 -k2,2n -k3,3n
} > "$out.tmp"
mv "$out.tmp" "$out"
echo "wrote $out" >&2
