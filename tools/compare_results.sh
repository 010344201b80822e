#!/usr/bin/env bash
# Runs the examples, the demo and the command lines the CLI tests use with one
# rfeid binary and keeps every RESULT.json, so that two builds can be compared
# with tools/compare_results.py.
#
# Usage: tools/compare_results.sh RFEID_BINARY OUT_DIR
# Example (old and new build, then compare):
#   tools/compare_results.sh /tmp/old/rfeid /tmp/old-results
#   tools/compare_results.sh target/release/rfeid /tmp/new-results
#   python3 tools/compare_results.py /tmp/old-results /tmp/new-results
set -euo pipefail
bin=$(realpath "$1")
out=$(realpath -m "$2")
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
kc="$root/examples/knee-column/model.toml"
run() { # name, then the command's arguments; a run may exit 0 or 3
  local name=$1; shift
  set +e
  "$bin" "$@" -q >"$out/$name.stdout" 2>"$out/$name.stderr"
  echo $? >"$out/$name.status"
  set -e
}
"$bin" simulate "$kc" -o kc.csv --noise 0.02 --seed 1 -q
"$bin" simulate "$kc" -o kc0.csv -q
"$bin" simulate "$root/examples/lathe/model.toml" -o lathe.csv --noise 0.01 --seed 2 -q
"$bin" simulate "$root/examples/tailstock/model.toml" -o tail.csv --noise 0.01 --seed 3 -q
mkdir camp && cp "$root/examples/knee-column-campaign/"* camp/
RFEID="$bin" sh camp/generate.sh 1

run demo demo -o "$out/demo.json"
run demo_noise demo --noise 0.02 --seed 3 -o "$out/demo_noise.json"
run kc identify "$kc" --data kc.csv -o "$out/kc.json"
run kc_free identify "$kc" --data kc0.csv -o "$out/kc_free.json"
run kc_bfgs identify "$kc" --data kc.csv --method bfgs --plan 20 -o "$out/kc_bfgs.json"
run kc_equal identify "$kc" --data kc.csv --weights equal --window 0 -o "$out/kc_equal.json"
run kc_values identify "$kc" --data kc.csv --start values -o "$out/kc_values.json"
# A suspect verdict (a slideway stiffer than its box) and a warning (coarse
# fixed steps): the verdict's reasons and the warnings.
"$bin" simulate "$kc" -o kc_stiff.csv --noise 0.02 --seed 4 --set a_n1=7e15 -q 2>/dev/null
run kc_bound identify "$kc" --data kc_stiff.csv --plan 8 -o "$out/kc_bound.json"
run kc_coarse identify "$kc" --data kc.csv --plan 8 --substeps 1 -o "$out/kc_coarse.json"
run kc_set identify "$kc" --data kc.csv --set "a_t4=27 daN/um" --from 0.05 -o "$out/kc_set.json"
run kc_starts identify "$kc" --data kc.csv --starts 3 --plan 40 -o "$out/kc_starts.json"
run lathe identify "$root/examples/lathe/model.toml" --data lathe.csv -o "$out/lathe.json"
run tail identify "$root/examples/tailstock/model.toml" --data tail.csv -o "$out/tail.json"
run camp identify camp/model.toml -o "$out/camp.json"
for k in 0 1 2; do
  "$bin" identify "$kc" --data kc.csv --plan 30 --shard $k/3 -o "shard$k.json" -q
done
run merged merge shard0.json shard1.json shard2.json -o "$out/merged.json"
run validate validate "$kc" "$out/kc.json" --data kc0.csv --json
run validate_camp validate camp/model.toml "$out/camp.json" --json
echo "results in $out"
