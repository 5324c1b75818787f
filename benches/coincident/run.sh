#!/bin/sh
# Time and peak memory of `sceneeval evaluate` on the scenes of make_scenes.py (issue 34,
# item 7; docs/performance.md, "Coincident objects and the time budget"). Run from the
# repository root after `cargo build --release -p sceneeval-cli`. BUDGET (seconds, default 0:
# none) is passed as --time-budget.
set -eu
OUT=${OUT:-target/coincident}
BIN=${BIN:-target/release/sceneeval}
BUDGET=${BUDGET:-0}
python3 benches/coincident/make_scenes.py "$OUT"
run() { # name, scenes folder, assets
    rm -rf "$OUT/out_$1"
    /usr/bin/time -f "$1: %e s wall, %M KB peak RSS, exit %x" \
        "$BIN" evaluate "$2" --assets "$3" --out "$OUT/out_$1" --time-budget "$BUDGET" \
        >/dev/null 2>"$OUT/$1.log" || true
    tail -n 1 "$OUT/$1.log"
    python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print('  ' + ', '.join(f\"{m['metric']} {m['seconds']:.3f} s\" for m in d['metrics']), f\"(load {d['load_seconds']:.3f} s)\")" \
        "$(ls "$OUT/out_$1"/*/timing.json)" 2>/dev/null || true
}
for n in 10 20 30 40 45 50; do
    run "plants_$n" "$OUT/plants_$n" "fixture=fixtures/assets"
done
for k in 10 50 200; do
    rm -rf "$OUT/converted_$k"
    "$BIN" convert holodeck "$OUT/holodeck_$k" --out "$OUT/converted_$k" \
        --assets objaverse=fixtures/native/holodeck/objathor >/dev/null 2>&1
    run "holodeck_$k" "$OUT/converted_$k" "objaverse=fixtures/native/holodeck/objathor"
done
