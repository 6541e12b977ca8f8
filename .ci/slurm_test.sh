#!/usr/bin/env bash
# A real one-node Slurm cluster: installs slurm-wlm and munge, starts munged, slurmctld and
# slurmd, submits the book's job-array recipe (docs/book/src/how-to/slurm.md) word for word (4
# shards of a small study, one of them empty), waits, analyses the shard directories together,
# and checks that the rows and the occurrence table equal a single-machine run. Stops the
# daemons it started, whatever happens.
# Needs root (apt-get, daemons) and the release binary (built here if absent; CARGO_TARGET_DIR
# is honoured).
set -euo pipefail
cd "$(dirname "$0")/.."
REPO=$(pwd)

echo "== slurm: install slurm-wlm and munge"
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq slurm-wlm munge >/dev/null
fi
BIN_DIR="${CARGO_TARGET_DIR:-$REPO/target}/release"
[ -x "$BIN_DIR/polywear" ] || cargo build --release --quiet

WORK=$(mktemp -d /tmp/polywear-slurm.XXXXXX)
mkdir -p "$WORK/state" "$WORK/spool" "$WORK/munge" "$WORK/run"
cleanup() {
  set +e
  # Stop only the daemons this script started, by their pid.
  local daemons=()
  for f in "$WORK/slurmctld.pid" "$WORK/slurmd.pid" "$WORK/munge/munged.pid"; do
    [ -f "$f" ] && daemons+=("$(cat "$f")")
  done
  for p in "${daemons[@]}"; do kill "$p" 2>/dev/null; done
  # Wait (up to 20 s) until they are gone, so nothing of this test outlives it.
  for _ in $(seq 40); do
    alive=0
    for p in "${daemons[@]}"; do kill -0 "$p" 2>/dev/null && alive=1; done
    [ "$alive" = 0 ] && break
    sleep 0.5
  done
  if [ "${SLURM_TEST_OK:-0}" != 1 ]; then
    echo "-- slurmctld log"; tail -n 30 "$WORK/slurmctld.log" 2>/dev/null
    echo "-- slurmd log"; tail -n 30 "$WORK/slurmd.log" 2>/dev/null
    echo "-- job logs"; tail -n 30 "$WORK"/job/polywear-*.log 2>/dev/null
  fi
  rm -rf "$WORK"
}
trap cleanup EXIT

echo "== slurm: start munged"
# Its own socket, key copy and pid file, so a munged already running on the machine is untouched.
MUNGE_SOCKET="$WORK/munge/munge.socket"
if [ ! -s /etc/munge/munge.key ]; then
  dd if=/dev/urandom of="$WORK/munge/munge.key" bs=1024 count=1 status=none
else
  cp /etc/munge/munge.key "$WORK/munge/munge.key"
fi
chmod 700 "$WORK/munge"; chmod 400 "$WORK/munge/munge.key"
munged --force --socket="$MUNGE_SOCKET" --key-file="$WORK/munge/munge.key" \
  --pid-file="$WORK/munge/munged.pid" --log-file="$WORK/munge/munged.log" \
  --seed-file="$WORK/munge/munged.seed"
HOST=$(hostname -s)
CPUS=$(nproc)
MEM_MB=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2 ))
export SLURM_CONF="$WORK/slurm.conf"
cat > "$SLURM_CONF" <<CONF
ClusterName=polywear-ci
SlurmctldHost=$HOST(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$MUNGE_SOCKET
CredType=cred/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
StateSaveLocation=$WORK/state
SlurmdSpoolDir=$WORK/spool
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/slurmctld.log
SlurmdLogFile=$WORK/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$CPUS RealMemory=$MEM_MB State=UNKNOWN
PartitionName=ci Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
CONF

echo "== slurm: start slurmctld and slurmd ($CPUS CPUs on $HOST)"
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
for _ in $(seq 60); do
  if sinfo -h -o "%T" 2>/dev/null | grep -qE "^(idle|mixed|allocated)"; then break; fi
  sleep 1
done
sinfo

echo "== slurm: the book's job-array recipe, word for word"
# The recipe is the ```sh block after the marker <!-- slurm-recipe --> in the book's Slurm page.
RECIPE=docs/book/src/how-to/slurm.md
awk '/<!-- slurm-recipe/ {m=1; next} m && /^```sh/ {p=1; next} p && /^```/ {exit} p' \
  "$RECIPE" > "$WORK/polywear.sbatch"
grep -q -- "--array=0-3" "$WORK/polywear.sbatch" || { echo "recipe not found in $RECIPE"; exit 1; }
cat "$WORK/polywear.sbatch"
# A small study: 3 chunks of 100 samples for 4 shards, so shard 3 owns no chunk (an empty shard).
mkdir -p "$WORK/job"
cat > "$WORK/job/small.toml" <<'TOML'
name = "slurm_ci"
seed = 7
samples = 300
chunk_size = 100
variants = ["paper", "combined"]
[params]
speed_kmh = { dist = "uniform", min = 60, max = 250 }
toe_deg = { dist = "uniform", min = 0.1, max = 0.5 }
load_n = { dist = "uniform", min = 3000, max = 5500 }
pressure_kpa = { dist = "uniform", min = 200, max = 300 }
TOML
cd "$WORK/job"
JOB=$(PATH="$BIN_DIR:$PATH" STUDY=small.toml SAMPLES=300 OUT=results \
  sbatch --parsable --export=ALL "$WORK/polywear.sbatch")
echo "submitted job array $JOB"
for _ in $(seq 600); do
  [ -z "$(squeue -h -j "$JOB" 2>/dev/null)" ] && break
  sleep 1
done
[ -z "$(squeue -h -j "$JOB" 2>/dev/null)" ] || { echo "job array $JOB did not finish in 10 min"; exit 1; }
for k in 0 1 2 3; do
  state=$(scontrol show job "${JOB}_$k" 2>/dev/null | grep -o "JobState=[A-Z]*" || true)
  echo "task $k: ${state:-finished} ($(ls results/shard-$k | tr '\n' ' '))"
  [ -f "results/shard-$k/_manifest.json" ] || { echo "task $k left no manifest"; exit 1; }
done
grep -q "no rows" results/shard-3/_report/report.md || { echo "the empty shard's report does not say it holds no rows"; exit 1; }

echo "== slurm: analyze the shards, compare with a single-machine run"
P="$BIN_DIR/polywear"
"$P" analyze results/shard-* --out sharded_report
"$P" explore small.toml --samples 300 --out single --quiet --no-report
"$P" analyze single --out single_report >/dev/null
grep -q "300 of 300 samples present" sharded_report/report.md
cmp sharded_report/occurrence.csv single_report/occurrence.csv
cmp sharded_report/paired.csv single_report/paired.csv
python3 - <<'PY'
import glob
import pandas as pd
def rows(pattern):
    files = sorted(glob.glob(pattern))
    df = pd.concat([pd.read_parquet(f) for f in files], ignore_index=True)
    return df.sort_values(["sample_id", "variant", "wheel"]).reset_index(drop=True)
a, b = rows("results/shard-*/chunk-*.parquet"), rows("single/chunk-*.parquet")
assert len(a) == len(b) == 300 * 2 * 2, (len(a), len(b))
pd.testing.assert_frame_equal(a, b)
print(f"rows: {len(a)} from the shards equal the single-machine run")
PY
cd "$REPO"
SLURM_TEST_OK=1
echo "== slurm: passed (daemons stop on exit)"
