#!/bin/sh
# Simulates the feed axis at the model's values (the truth) with 0.1 %
# seeded noise on the encoder: data.csv beside the model file.
# Usage: generate.sh [SEED]   (default 1)
# e.g. after the README's first command: examples/feed-axis/generate.sh
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
"$rfeid" simulate "$dir/model.toml" -o "$dir/data.csv" --noise 0.001 --seed "$seed" --quiet
