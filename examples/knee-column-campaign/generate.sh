#!/bin/sh
# Simulates the campaign's three tests at the model's values (the truth) with
# 2 % seeded noise: low.csv, mid.csv and high.csv beside the model file.
# Usage: generate.sh [SEED]   (default 1; each test gets its own seed)
set -e
dir=$(dirname "$0")
seed=${1:-1}
rfeid=${RFEID:-rfeid}
n=0
for e in low mid high; do
  "$rfeid" simulate "$dir/model.toml" --experiment "$e" -o "$dir/$e.csv" \
    --noise 0.02 --seed $((seed * 10 + n)) --quiet
  n=$((n + 1))
done
