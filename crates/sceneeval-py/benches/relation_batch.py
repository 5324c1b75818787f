#!/usr/bin/env python3
"""Throughput of sceneeval.relation_batch from Python, counting the numpy round trip (reading
the (N, 7) float64 arrays, the boxes' checks, the scores and the returned array), on one core.
Also one sceneeval.relation call at a time (a Python tuple per box, a dict per room), for
comparison with the reference's milliseconds per call; surround scores the rows as groups of 4
targets around an anchor.

    python crates/sceneeval-py/benches/relation_batch.py [--pairs 1000000] [--repeat 5]

Build the extension in release mode first (`pip install ./crates/sceneeval-py`, or
`maturin develop --release`): a debug build is many times slower. Prints one Markdown table row
per predicate: the best of `repeat` runs.
"""

import argparse
import time

import numpy as np

import sceneeval

ROOM = {
    "floor": [[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]],
    "openings": [
        {"kind": "door", "wall": 0, "along": [1.0, 1.9], "height": [0.0, 2.1]},
        {"kind": "window", "wall": 2, "along": [1.5, 2.7], "height": [0.9, 2.1]},
    ],
}


def boxes(rng, n):
    # Furniture-sized boxes in a 4 x 5 m room, so the regions cut the boxes and the distances
    # fall inside and outside the bands.
    b = np.empty((n, 7))
    b[:, 0] = rng.uniform(0.3, 3.7, n)
    b[:, 1] = rng.uniform(0.3, 4.7, n)
    b[:, 3:6] = rng.uniform(0.1, 0.8, (n, 3))
    b[:, 2] = b[:, 5]
    b[:, 6] = rng.uniform(-np.pi, np.pi, n)
    return b


def best(f, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return min(times)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pairs", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--single", type=int, default=20_000, help="calls of sceneeval.relation timed")
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    targets, anchors = boxes(rng, args.pairs), boxes(rng, args.pairs)
    print(f"| predicate | relation_batch, {args.pairs:,} boxes | per box | relation(), one call |")
    print("|---|---|---|---|")
    cases = [
        ("inside_of", {}), ("outside_of", {}), ("face_to", {}), ("side_of", {"side": "left"}),
        ("side_region", {"side": "front"}), ("long_short_side_of", {"side": "long"}), ("on_top", {}),
        ("middle_of", {}), ("next_to", {}), ("near", {}), ("across_from", {}), ("far", {}),
        ("next_to", {"arch": "wall"}), ("near", {"arch": "door"}), ("inside_room", {}),
        ("middle_of_room", {}), ("corner_of_room", {}), ("on_wall", {}), ("against_wall", {}),
        ("hang_from_ceiling", {}),
    ]
    t_list = [tuple(map(float, r)) for r in targets[: args.single]]
    a_list = [tuple(map(float, r)) for r in anchors[: args.single]]
    # surround: one score per group of 4 targets around an anchor (the rows as groups).
    groups = targets[: args.pairs // 4 * 4].reshape(-1, 4, 7)
    group_anchors = anchors[: len(groups)]
    seconds = best(lambda: sceneeval.relation_batch("surround", groups, group_anchors), args.repeat)
    g_list = [[tuple(map(float, r)) for r in g] for g in groups[: args.single]]
    single = best(lambda: [sceneeval.relation("surround", None, a, targets=g) for g, a in zip(g_list, a_list)], 1)
    print(f"| `surround`, groups of 4 ({len(groups):,} groups) | {len(groups) / seconds / 1e6:.2f} M/s "
          f"| {seconds / len(groups) * 1e9:.0f} ns | {single / len(g_list) * 1e6:.1f} µs |")
    for name, kw in cases:
        arch = "arch" in kw or name in ("inside_room", "middle_of_room", "corner_of_room", "on_wall", "against_wall", "hang_from_ceiling")
        if arch:
            run = lambda: sceneeval.relation_batch(name, targets, room=ROOM, **kw)  # noqa: E731
            one = lambda: [sceneeval.relation(name, t, room=ROOM, **kw) for t in t_list]  # noqa: E731
        else:
            run = lambda: sceneeval.relation_batch(name, targets, anchors, **kw)  # noqa: E731
            one = lambda: [sceneeval.relation(name, t, a, **kw) for t, a in zip(t_list, a_list)]  # noqa: E731
        seconds = best(run, args.repeat)
        single = best(one, 1) / args.single
        label = name + "".join(f"({v})" for v in kw.values())
        print(f"| `{label}` | {args.pairs / seconds / 1e6:.2f} M/s | {seconds / args.pairs * 1e9:.0f} ns "
              f"| {single * 1e6:.1f} µs |")


if __name__ == "__main__":
    main()
