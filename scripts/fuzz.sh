#!/usr/bin/env bash
# A fuzz campaign: installs clang and libFuzzer's runtime (idempotent), configures and builds
# the `fuzz` preset (build-fuzz/), then runs each libFuzzer target for SECONDS (default 600)
# with the dictionary fuzz/scene.dict over the checked-in corpus fuzz/corpus/<target>/. New
# inputs go to out/fuzz/<target>/corpus, never into the checked-in corpus; a crash, leak,
# timeout or out-of-memory input goes to out/fuzz/<target>/ and fails the script.
#   scripts/fuzz.sh [SECONDS] [TARGET...]     (targets: scene_loader renderer)
# One process a target, under nice: the machine is shared. docs/fuzzing.md has the figures.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
shift || true
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(scene_loader renderer)

./scripts/setup-deps.sh fuzz
cmake --preset fuzz >/dev/null
nice cmake --build --preset fuzz

failed=0
for t in "${targets[@]}"; do
  bin="build-fuzz/bin/${t}_fuzzer"
  out="out/fuzz/$t"
  mkdir -p "$out/corpus"
  log="$out/run.log"
  touch "$out/.started"
  echo "fuzz: $t for ${seconds}s, log $log"
  # -timeout: one input may take at most 25 s (the slowest seen take well under a second);
  # -rss_limit_mb: the limits of docs/limits.md keep a scene far below it.
  args=(-dict=fuzz/scene.dict -max_total_time="$seconds" -timeout=25 -rss_limit_mb=2560
        -print_final_stats=1 -artifact_prefix="$out/")
  status=0
  start=$(date +%s)
  nice "$bin" "${args[@]}" "$out/corpus" "fuzz/corpus/$t" >"$log" 2>&1 || status=$?
  took=$(( $(date +%s) - start ))
  runs=$(grep '^stat::number_of_executed_units:' "$log" | awk '{print $2}' || true)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1 | grep -oE 'cov: [0-9]+ ft: [0-9]+ corp: [0-9]+/[0-9A-Za-z]+' || true)
  echo "fuzz: $t: ${runs:-0} executions in ${took}s, ${last:-no coverage line}, exit $status"
  artifacts=$(find "$out" -maxdepth 1 -type f -newer "$out/.started" \( -name 'crash-*' \
    -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | tr '\n' ' ')
  if [[ $status -ne 0 || -n "$artifacts" ]]; then
    echo "fuzz: $t FAILED; input(s): ${artifacts:-none written}; reproduce with $bin FILE" >&2
    grep -hE 'ERROR: |SUMMARY: |runtime error|_fuzzer: ' "$log" | head -5 >&2 || true
    failed=1
  fi
done
exit $failed
