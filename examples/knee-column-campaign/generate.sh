#!/bin/sh
# Simulates the campaign's three tests at the model's values (the truth) with
# 2 % seeded noise: low.csv, mid.csv and high.csv beside the model file.
# Usage: generate.sh [SEED]   (default 1; each test gets its own seed)
# e.g. after the README's first command: examples/knee-column-campaign/generate.sh
set -e
dir=$(dirname "$0")
seed=${1:-1}
# The binary: $RFEID, else rfeid on PATH, else this repository's release build
# (after `cargo run --release -- demo` or `cargo build --release`).
rfeid=${RFEID:-}
if [ -z "$rfeid" ]; then
  if command -v rfeid >/dev/null 2>&1; then
    rfeid=rfeid
  elif [ -x "$dir/../../target/release/rfeid" ]; then
    rfeid="$dir/../../target/release/rfeid"
  else
    echo "generate.sh: no rfeid binary: run 'cargo build --release' first, or set RFEID=/path/to/rfeid" >&2
    exit 2
  fi
fi
n=0
for e in low mid high; do
  "$rfeid" simulate "$dir/model.toml" --experiment "$e" -o "$dir/$e.csv" \
    --noise 0.02 --seed $((seed * 10 + n)) --quiet
  n=$((n + 1))
done
