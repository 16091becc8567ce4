#!/usr/bin/env bash
# Sweeps the third seed of every random test over many seeds: the random backend tests (the
# reference against OSMesa llvmpipe and softpipe, `random_backend_tests`) and the core's
# sameness test (`core_tests`, every kernel path and thread count against the scalar model).
# CI runs seeds 1, 2 and 3 only (.ci/run fixes REFRASTER_TEST_SEED=3); run this before
# resolving any change to the core, and turn every failing seed into a regression test
# (docs/precision.md, "Random tests and seed sweeps").
#
#   scripts/seed-sweep.sh [--first S] [--count N] [--seeds "S1 S2 ..."] [--random]
#                         [--filter GTEST_FILTER] [--jobs J] [--no-build]
#
# Defaults: 200 seeds from 1000. --random draws the seeds from /dev/urandom (printed, so that a
# sweep can be repeated). Each seed runs only the seed-parameterised cases (the `/2` instance of
# each `Seeds/...` suite, which takes REFRASTER_TEST_SEED); the fixed seeds 1 and 2 run in CI.
# --jobs J runs J seeds at a time (default 1; each seed runs its tests one after another, so J
# up to the number of cores helps). Logs go to
# out/seed-sweep/seed-<S>.log; failing seeds to out/seed-sweep/failing.txt. Exit 0 when every
# seed passed, 1 when any failed, 2 on a bad argument.
set -euo pipefail
cd "$(dirname "$0")/.."

first=1000
count=200
seeds=""
random=0
filter='Seeds/*/2'
build=1
jobs=1
usage() { echo "usage: scripts/seed-sweep.sh [--first S] [--count N] [--seeds \"S ...\"] [--random] [--filter F] [--jobs J] [--no-build]" >&2; exit 2; }
is_uint() { [[ $1 =~ ^[0-9]{1,19}$ ]]; }
while [[ $# -gt 0 ]]; do
  case "$1" in
    --first) [[ $# -ge 2 ]] && is_uint "$2" || usage; first="$2"; shift 2 ;;
    --count) [[ $# -ge 2 ]] && is_uint "$2" && [[ $2 -ge 1 && $2 -le 100000 ]] || usage; count="$2"; shift 2 ;;
    --seeds) [[ $# -ge 2 ]] || usage; seeds="$2"; shift 2 ;;
    --random) random=1; shift ;;
    --filter) [[ $# -ge 2 ]] || usage; filter="$2"; shift 2 ;;
    --jobs) [[ $# -ge 2 ]] && is_uint "$2" && [[ $2 -ge 1 && $2 -le 256 ]] || usage; jobs="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    *) usage ;;
  esac
done
if [[ -z $seeds ]]; then
  if [[ $random -eq 1 ]]; then
    seeds=$(od -An -N$((4 * count)) -tu4 /dev/urandom | tr -s ' \n' ' ')
  else
    seeds=$(seq "$first" $((first + count - 1)) | tr '\n' ' ')
  fi
fi
for s in $seeds; do is_uint "$s" || { echo "seed-sweep: not a seed: $s" >&2; exit 2; }; done

if [[ $build -eq 1 ]]; then
  ./scripts/build.sh ci >/dev/null
fi
out=out/seed-sweep
mkdir -p "$out"
: >"$out/failing.txt"
export REFRASTER_WORKER_DIR="$PWD/build/bin"
read -r -a seed_list <<<"$seeds"
total=${#seed_list[@]}
echo "seed-sweep: $total seeds ($seeds), filter $filter, $jobs at a time, logs in $out/"
start=$SECONDS
# One seed: its log, its line, and its name in failing.txt when it failed (a line appended
# whole, so seeds running side by side do not mix their lines).
run_seed() {
  local s=$1 n=$2 log="$out/seed-$1.log" t0=$SECONDS status=pass
  {
    REFRASTER_TEST_SEED="$s" build/bin/random_backend_tests --gtest_filter="$filter" &&
      REFRASTER_TEST_SEED="$s" build/bin/core_tests --gtest_filter="$filter"
  } >"$log" 2>&1 || status=FAIL
  if [[ $status == FAIL ]]; then
    echo "$s" >>"$out/failing.txt"
    grep -E '^\[  FAILED  \]' "$log" | sed "s/^/  seed $s: /" | sort -u || true
  fi
  echo "seed-sweep: $n/$total seed $s $status ($((SECONDS - t0)) s; $((SECONDS - start)) s in all)"
}
n=0
running=0
for s in "${seed_list[@]}"; do
  n=$((n + 1))
  if [[ $running -ge $jobs ]]; then
    wait -n || true
    running=$((running - 1))
  fi
  run_seed "$s" "$n" &
  running=$((running + 1))
done
wait
failed=$(grep -c . "$out/failing.txt" || true)
echo "seed-sweep: $((total - failed)) of $total seeds passed; failing seeds in $out/failing.txt"
[[ $failed -eq 0 ]]
