#!/usr/bin/env bash
# Re-runs every measurement of the scaling and peer tables in docs/performance.md.
#
#   benches/peers/run.sh                       # everything (about 15 minutes on 2 cores)
#   SIZES="10 100 1000" KINDS=boxes benches/peers/run.sh    # a quick subset
#   PEER_KINDS="" OUT=target/peers-rust benches/peers/run.sh # the Rust part only
#
# Writes under $OUT (default target/peers): the generated scenes, rust.jsonl (one line per
# metric, kind and size, from `scaling run`), peers.jsonl (one line per task, peer and size,
# from peers.py) and report.md (the tables, from report.py). The Python peers are installed
# from PyPI into $OUT/venv at the versions pinned in requirements.txt.
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${OUT:-target/peers}
SIZES=${SIZES:-"10 50 100 1000 5000 20000"}
KINDS=${KINDS:-"boxes fixtures mesh8k"}
PEER_SIZES=${PEER_SIZES-"50 1000 5000"}
PEER_KINDS=${PEER_KINDS-"boxes mesh8k"}
THREADS=${THREADS:-1}
PEER_TIMEOUT=${PEER_TIMEOUT:-3600}
REPEAT=${REPEAT:-3}
mkdir -p "$OUT"

if [ ! -x "$OUT/venv/bin/python" ]; then
    python3 -m venv "$OUT/venv"
    "$OUT/venv/bin/pip" install --quiet -r benches/peers/requirements.txt
fi
PY="$OUT/venv/bin/python"

cargo build --release -p sceneeval-benches --bin scaling
BIN=target/release/scaling

assets_of() {
    if [ "$1" = fixtures ]; then echo "fixture=fixtures/assets"; else echo "bench=$OUT/$1/assets"; fi
}

: > "$OUT/rust.jsonl"
for kind in $KINDS; do
    for n in $SIZES; do
        "$BIN" gen --kind "$kind" --n "$n" --out "$OUT/$kind" --fixtures fixtures/assets > /dev/null
        # The minimum of $REPEAT runs (the first also builds the per-mesh tables, once per asset
        # in a batch run, like the peers' BVHs, which they build before their timers start;
        # `scaling run` reports it separately).
        repeat=$REPEAT
        # One process per metric, so that each peak memory is that metric's (plus loading).
        for metric in collision support navigability accessibility out_of_bounds opening_clearance evaluate; do
            "$BIN" run --scene "$OUT/$kind/scene_$n.json" --assets "$(assets_of "$kind")" \
                --metric "$metric" --repeat "$repeat" --threads "$THREADS" >> "$OUT/rust.jsonl"
        done
        # Navigability on a 2 cm grid (the peers' resolution).
        "$BIN" run --scene "$OUT/$kind/scene_$n.json" --assets "$(assets_of "$kind")" \
            --metric navigability --repeat "$repeat" --threads "$THREADS" --resolution 0.02 \
            | sed 's/"navigability"/"navigability_2cm"/g' >> "$OUT/rust.jsonl"
    done
done

: > "$OUT/peers.jsonl"
for kind in $PEER_KINDS; do
    for n in $PEER_SIZES; do
        m="$OUT/$kind/peers_$n.json"
        for tp in "collision fcl" "collision trimesh" "support embree" "out_of_bounds embree" \
                  "navigability shapely" "accessibility shapely"; do
            set -- $tp
            timeout "$PEER_TIMEOUT" "$PY" benches/peers/peers.py --manifest "$m" --task "$1" --peer "$2" \
                >> "$OUT/peers.jsonl" || echo "{\"manifest\": \"$m\", \"task\": \"$1\", \"peer\": \"$2\", \"failed\": true}" >> "$OUT/peers.jsonl"
        done
    done
done

"$PY" benches/peers/report.py "$OUT" > "$OUT/report.md"
cat "$OUT/report.md"
