#!/usr/bin/env bash
# Writes tests/conformance/data/rust_f32_display.txt: f32 values (as bit patterns) and how
# Rust's `{}` prints them, the formatting deqp-runner uses for results.csv's duration column.
# tests/conformance/deqp_runner_test.cpp checks conformance::deqp_runner_duration against it.
# Needs rustc (Debian's `rustc` package or rustup). Deterministic: the same file every time.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="$root/tests/conformance/data/rust_f32_display.txt"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cat > "$work/vectors.rs" <<'RUST'
// Prints "bits display" for chosen and pseudo-random f32 values.
fn show(v: f32) {
    println!("{:08x} {}", v.to_bits(), v);
}

fn main() {
    println!("# f32 bit pattern, then Rust's Display of it (made by scripts/make_deqp_runner_vectors.sh)");
    let special = [0.0f32, -0.0, 1.0, 0.1, 0.5, 1e-7, 1e20, f32::MAX, f32::MIN_POSITIVE,
                   1.0e-45, 16777216.0, 16777217.0, 123456.79, 0.000123, 2.5, 1e38, -1.5];
    for v in special.iter() {
        show(*v);
    }
    let mut p = 1.0e-45f64;
    while p < 3.0e38 {
        show(p as f32);
        p *= 10.0;
    }
    // xorshift32: bit patterns over every finite float, and durations a run could measure.
    let mut s: u32 = 0x9e37_79b9;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        s
    };
    let mut n = 0;
    while n < 3000 {
        let v = f32::from_bits(next());
        if v.is_finite() {
            show(v);
            n += 1;
        }
    }
    for _ in 0..3000 {
        let micros = (next() % 600_000_000) as f64;
        show((micros * 1e-6) as f32);
    }
    for _ in 0..1000 {
        let nanos = (next() % 50_000_000) as f64;
        show((nanos * 1e-9) as f32);
    }
}
RUST
rustc -O -o "$work/vectors" "$work/vectors.rs"
"$work/vectors" > "$out"
echo "wrote $out ($(wc -l < "$out") lines, $(rustc --version))"
