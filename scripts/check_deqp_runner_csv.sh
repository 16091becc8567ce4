#!/usr/bin/env bash
# Reads a run's results.csv with deqp-runner's rules and writes it back the way deqp-runner
# writes results.csv and failures.csv (Rust's formatting of an f32, bytewise name order, its
# success rule), then compares byte for byte with the run's own files.
#   scripts/check_deqp_runner_csv.sh OUTPUT_DIR
# Needs rustc. Exit 0 when both files are identical, 1 when they differ, 2 on bad input.
set -euo pipefail
dir="${1:?usage: $0 OUTPUT_DIR}"
[ -f "$dir/results.csv" ] && [ -f "$dir/failures.csv" ] ||
  { echo "$dir: no results.csv and failures.csv" >&2; exit 2; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cat > "$work/rewrite.rs" <<'RUST'
// deqp-runner's status words (RunnerStatus) and its success rule.
use std::io::{BufRead, Write};

fn known(status: &str) -> bool {
    const WORDS: [&str; 10] = ["Pass", "Fail", "Crash", "Skip", "Flake", "KnownFlake", "Warn",
                               "Missing", "ExpectedFail", "Timeout"];
    const INNER: [&str; 6] = ["Pass", "Fail", "Crash", "Skip", "Warn", "Timeout"];
    if WORDS.contains(&status) {
        return true;
    }
    match status.strip_prefix("UnexpectedImprovement(").and_then(|s| s.strip_suffix(')')) {
        Some(inner) => INNER.contains(&inner),
        None => false,
    }
}

fn success(status: &str) -> bool {
    ["Pass", "Skip", "Warn", "Flake", "KnownFlake", "ExpectedFail"].contains(&status)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let file = std::fs::File::open(&args[1]).expect("results.csv");
    let mut rows: Vec<(String, String, f32)> = Vec::new();
    for (n, line) in std::io::BufReader::new(file).lines().enumerate() {
        let line = line.expect("read");
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != 3 || fields[0].is_empty() || !known(fields[1]) {
            eprintln!("results.csv:{}: not name,Status,duration: {}", n + 1, line);
            std::process::exit(2);
        }
        let duration: f32 = fields[2].parse().unwrap_or_else(|_| {
            eprintln!("results.csv:{}: duration {} is not an f32", n + 1, fields[2]);
            std::process::exit(2);
        });
        rows.push((fields[0].to_string(), fields[1].to_string(), duration));
    }
    rows.sort_by(|a, b| a.0.cmp(&b.0));
    let mut results = std::fs::File::create(&args[2]).expect("write");
    let mut failures = std::fs::File::create(&args[3]).expect("write");
    for (name, status, duration) in &rows {
        writeln!(results, "{},{},{}", name, status, duration).unwrap();
        if !success(status) {
            writeln!(failures, "{},{}", name, status).unwrap();
        }
    }
}
RUST
rustc -O -o "$work/rewrite" "$work/rewrite.rs"
"$work/rewrite" "$dir/results.csv" "$work/results.csv" "$work/failures.csv"
status=0
for f in results.csv failures.csv; do
  if cmp -s "$dir/$f" "$work/$f"; then
    echo "$f: identical to deqp-runner's writing of it ($(wc -l < "$dir/$f") lines)"
  else
    echo "$f: differs from deqp-runner's writing of it:"; diff "$dir/$f" "$work/$f" | head -20
    status=1
  fi
done
exit $status
