#!/usr/bin/env bash
# A tiny plan through a real one-node Slurm cluster on this machine: `facets reproduce --slurm`
# writes the scripts, submit.sh submits the job array (3 tasks, at most 2 at once) and the
# collect job, and the report must equal the one-machine run's (every number, every deposit
# and detection table, bit for bit; wall times aside).
#
# Needs root: installs slurm-wlm and munge (Debian packages) when missing, starts munged (if
# not running), slurmctld and slurmd with a configuration of its own in a temporary folder,
# and stops what it started on exit. Skips, saying so, when not root.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

if [ "$(id -u)" != 0 ]; then
    echo "slurm-test: SKIPPED: needs root (installs slurm-wlm and munge, starts munged, slurmctld and slurmd)"
    exit 0
fi
start_time=$(date +%s)
say() { echo "slurm-test [$(($(date +%s) - start_time)) s]: $*"; }

if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null \
    || ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
    say "installing slurm-wlm and munge"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge >/dev/null
fi

# CI builds with its own profile (no whole-program optimisation); by hand, the release build.
profile=${FACETS_PROFILE:-release}
cargo build --profile "$profile" --quiet
facets="$root/target/$profile/facets"

work=$(mktemp -d /tmp/facets-slurm-test.XXXXXX)
started=()
stop_daemons() {
    local status=$?
    for pid in "${started[@]}"; do
        kill "$pid" 2>/dev/null || true
    done
    for pid in "${started[@]}"; do
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    done
    if [ "$status" = 0 ]; then
        rm -rf "$work"
    else
        echo "slurm-test: FAILED; daemons' logs and outputs kept in $work" >&2
        tail -n 20 "$work"/*.log "$work"/slurm/logs/* 2>/dev/null >&2 || true
    fi
}
trap stop_daemons EXIT

# munge: a key if there is none, then munged unless one runs already.
if [ ! -s /etc/munge/munge.key ]; then
    mkdir -p /etc/munge
    dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key status=none
    chown munge:munge /etc/munge/munge.key 2>/dev/null || true
    chmod 400 /etc/munge/munge.key
fi
if ! munge -n >/dev/null 2>&1; then
    mkdir -p /run/munge /var/log/munge /var/lib/munge
    chown munge:munge /run/munge /var/log/munge /var/lib/munge 2>/dev/null || true
    munged --force
    for _ in $(seq 50); do [ -s /run/munge/munged.pid ] && break; sleep 0.1; done
    started+=("$(cat /run/munge/munged.pid)")
fi
munge -n | unmunge >/dev/null || { echo "slurm-test: munge does not work" >&2; exit 1; }

# A one-node cluster of its own: own ports, state, spool, pid and log files.
host=$(hostname -s)
memory_mb=$(awk '/MemTotal/ {print int($2 / 1024 * 0.8)}' /proc/meminfo)
mkdir -p "$work/state" "$work/spool"
cat >"$work/slurm.conf" <<CONF
ClusterName=facetstest
SlurmctldHost=$host
SlurmctldPort=6917
SlurmdPort=6918
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
ReturnToService=2
MinJobAge=600
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=$memory_mb State=UNKNOWN
PartitionName=facets Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
slurmctld -f "$SLURM_CONF"
for _ in $(seq 50); do [ -s "$work/slurmctld.pid" ] && break; sleep 0.1; done
started+=("$(cat "$work/slurmctld.pid")")
slurmd -f "$SLURM_CONF" -N "$host"
for _ in $(seq 50); do [ -s "$work/slurmd.pid" ] && break; sleep 0.1; done
started+=("$(cat "$work/slurmd.pid")")
for _ in $(seq 60); do
    state=$(sinfo -h -N -o %T 2>/dev/null | head -n 1)
    [ "$state" = idle ] && break
    sleep 1
done
[ "$state" = idle ] || { echo "slurm-test: the node is '$state', not idle, after 60 s" >&2; exit 1; }
say "one-node cluster up ($host, $(nproc) CPUs)"

# The tiny plan: squares in a 120 mm silo, two simulated fillings and one photographed.
cat >"$work/plan.json" <<'PLAN'
{
  "name": "slurm-test",
  "silo_width_mm": 120.0,
  "shapes": [{ "kind": "square", "grains": 40, "phi0s": [0.25], "w_over_d": 1.0 }],
  "simulation_realisations": 2,
  "photo_realisations": 1,
  "frame": "whole",
  "photo_px_per_mm": 8.0,
  "photo_style": "lab",
  "rdf_margin_over_d": 1.1,
  "w_scan_over_d": [1.0, 2.0],
  "max_relaxation_time_s": 0.5
}
PLAN

"$facets" reproduce --plan "$work/plan.json" --out "$work/cluster" --slurm "$work/slurm" \
    --tasks 3 --throttle 2 --partition facets --sbatch-line=--nice=0
submitted=$("$work/slurm/submit.sh")
echo "$submitted"
array=$(sed -n 's/^array job: //p' <<<"$submitted")
collect=$(sed -n 's/^collect job: //p' <<<"$submitted")
[ -n "$array" ] && [ -n "$collect" ] || { echo "slurm-test: submit.sh printed no job ids" >&2; exit 1; }

# Meanwhile, the same plan on this machine in one process.
"$facets" reproduce --plan "$work/plan.json" --out "$work/one" >"$work/one.log" 2>&1
say "one-machine run done"

deadline=$(($(date +%s) + 600))
while squeue -h -j "$array,$collect" 2>/dev/null | grep -q .; do
    if [ "$(date +%s)" -gt "$deadline" ]; then
        echo "slurm-test: jobs still queued or running after 10 minutes:" >&2
        squeue >&2
        scancel "$array" "$collect" || true
        exit 1
    fi
    sleep 2
done
for job in "$array" "$collect"; do
    states=$(scontrol -o show job "$job" | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | sort -u | tr '\n' ' ')
    say "job $job: $states"
    [ "$states" = "COMPLETED " ] || { echo "slurm-test: job $job ended $states" >&2; exit 1; }
done

# The same numbers: report.json without wall times and run counts, and every table.
numbers() { grep -v -e '"seconds' -e '"fillings_run"' -e '"fillings_reused"' "$1/report.json"; }
diff <(numbers "$work/one" | sed "s#$work/one#OUT#g") <(numbers "$work/cluster" | sed "s#$work/cluster#OUT#g") \
    || { echo "slurm-test: the cluster's report differs from the one-machine run's" >&2; exit 1; }
tables=0
while IFS= read -r file; do
    # Summaries name an example deposit by its path: the output folders' names aside.
    cmp <(sed "s#$work/one#OUT#g" "$work/one/$file") <(sed "s#$work/cluster#OUT#g" "$work/cluster/$file") \
        || { echo "slurm-test: $file differs from the one-machine run's" >&2; exit 1; }
    tables=$((tables + 1))
done < <(cd "$work/one" && find . -name '*.csv' -o -name summary.json -o -name comparison.json)
[ "$tables" -ge 10 ] || { echo "slurm-test: only $tables tables compared" >&2; exit 1; }
say "PASSED: 3 array tasks and the collect job completed; report.json and $tables tables equal the one-machine run's"
