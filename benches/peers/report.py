#!/usr/bin/env python3
"""Markdown tables from the lines `run.sh` collected: per kind of scene, the seconds of every
metric at every size (`collision_first`: collision's first run, which also builds the per-mesh
tables; every other figure is the minimum of the repeated runs) with its growth exponent
(least-squares slope of log time against log objects over the sizes from 1,000 up, next to
the exponent n log n itself has over those sizes), the peak memory of `evaluate`; then
sceneeval against each peer at the sizes both ran, warm (per-mesh tables and BVHs built) and,
for collision, cold (first runs: sceneeval's builds its tables, fcl's adds its BVH build)."""

import json
import math
import os
import sys
from collections import defaultdict

METRICS = [
    "collision",
    "collision_first",
    "support",
    "navigability",
    "navigability_2cm",
    "accessibility",
    "out_of_bounds",
    "opening_clearance",
    "evaluate",
]


def kind_of(path):
    return os.path.basename(os.path.dirname(path))


def read(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def fmt_s(s):
    if s is None:
        return "-"
    if s < 1e-3:
        return f"{s * 1e6:.0f} µs"
    if s < 1:
        return f"{s * 1e3:.1f} ms" if s < 0.1 else f"{s * 1e3:.0f} ms"
    return f"{s:.2f} s" if s < 10 else f"{s:.0f} s"


def exponent(points):
    pts = [(math.log(n), math.log(t)) for n, t in points if n >= 1000 and t and t > 0]
    if len(pts) < 2:
        return None
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    den = sum((x - mx) ** 2 for x, _ in pts)
    return sum((x - mx) * (y - my) for x, y in pts) / den if den else None


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "target/peers"
    rust = read(os.path.join(out, "rust.jsonl"))
    peers = read(os.path.join(out, "peers.jsonl"))
    # (kind, n) -> metric -> seconds; (kind, n) -> peak MB of the evaluate run.
    times = defaultdict(dict)
    peak = {}
    tris = {}
    for r in rust:
        key = (kind_of(r["scene"]), r["objects"])
        for m, s in r["seconds"].items():
            times[key][m] = s
            if m == "evaluate":
                peak[key] = r.get("peak_mb")
        # The first run of collision also builds the per-mesh tables.
        first = r.get("first_seconds", {}).get("collision")
        if first is not None:
            times[key]["collision_first"] = first
        tris[key] = r.get("triangles")
    kinds = sorted({k for k, _ in times})
    for kind in kinds:
        sizes = sorted(n for k, n in times if k == kind)
        print(f"### {kind}\n")
        print("| metric | " + " | ".join(f"{n:,}" for n in sizes) + " | exponent |")
        print("|---" * (len(sizes) + 2) + "|")
        for m in METRICS:
            row = [times[(kind, n)].get(m) for n in sizes]
            if all(x is None for x in row):
                continue
            e = exponent([(n, times[(kind, n)].get(m)) for n in sizes])
            print(f"| {m} | " + " | ".join(fmt_s(x) for x in row) + f" | {e:.2f} |" if e is not None else f"| {m} | " + " | ".join(fmt_s(x) for x in row) + " | - |")
        # What n log n work alone would show as an exponent over the same sizes.
        e = exponent([(n, n * math.log(n)) for n in sizes])
        if e is not None:
            print("| (n log n for reference) | " + " | ".join("" for _ in sizes) + f" | {e:.2f} |")
        row = [peak.get((kind, n)) for n in sizes]
        print("| peak memory, evaluate | " + " | ".join("-" if x is None else f"{x:.0f} MB" for x in row) + " | |")
        row = [tris.get((kind, n)) for n in sizes]
        print("| triangles | " + " | ".join("-" if x is None else f"{x:,}" for x in row) + " | |")
        print()

    ours_for = {
        "collision": "collision",
        "support": "support",
        "out_of_bounds": "out_of_bounds",
        "navigability": "navigability_2cm",
        "accessibility": "accessibility",
    }
    rows = defaultdict(dict)
    for p in peers:
        if p.get("failed") or p.get("skipped"):
            continue
        key = (kind_of(p["manifest"]), p["task"], p["peer"])
        rows[key][p["objects"]] = p
    if rows:
        print("### sceneeval against the peers (seconds, peak memory; ratio = peer / sceneeval)\n")
        print("| scenes | task | peer | objects | peer | sceneeval | ratio | peer, first run | sceneeval, first run | ratio, first run | peer memory |")
        print("|---" * 11 + "|")
        for (kind, task, peer), by_n in sorted(rows.items()):
            for n in sorted(by_n):
                p = by_n[n]
                ours = times[(kind, n)].get(ours_for[task])
                ratio = p["seconds"] / ours if ours else None
                # First runs: sceneeval's builds its per-mesh tables, fcl's its BVHs
                # (build_seconds); trimesh builds its BVHs inside its timer.
                first = times[(kind, n)].get("collision_first") if task == "collision" else None
                peer_first = None
                if task == "collision":
                    peer_first = p["seconds"] + p.get("build_seconds", 0.0)
                ratio_first = peer_first / first if first and peer_first else None
                print(
                    f"| {kind} | {task} | {peer} | {n:,} | {fmt_s(p['seconds'])} | {fmt_s(ours)} | "
                    + ("-" if ratio is None else f"{ratio:.1f}x")
                    + f" | {fmt_s(peer_first)} | {fmt_s(first)} | "
                    + ("-" if ratio_first is None else f"{ratio_first:.1f}x")
                    + f" | {p['peak_mb']:.0f} MB |"
                )

if __name__ == "__main__":
    main()
