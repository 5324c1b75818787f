#!/usr/bin/env python3
"""Random layout sampler: places a bedroom's furniture at random and keeps only the layouts
whose spatial relations hold and that pass the collision and out-of-bounds checks.

The predicates are scored for thousands of candidate layouts at once with
``sceneeval.relation_batch`` (numpy arrays of boxes, GIL released); only the survivors are
built as scenes and checked with the plausibility metrics.

    python examples/python/layout_sampler.py --candidates 20000 --keep 5 --out layouts.json
"""

import argparse
import json
import sys

import numpy as np

import sceneeval

# A 4 x 5 m bedroom with a door in its first wall (y = 0) and a window in the opposite wall.
ROOM = {
    "floor": [[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]],
    "height": 2.7,
    "openings": [
        {"kind": "door", "wall": 0, "along": [0.4, 1.3], "height": [0.0, 2.1]},
        {"kind": "window", "wall": 2, "along": [1.5, 2.7], "height": [0.9, 2.1]},
    ],
}
# Furniture: category and half extents (width/2, depth/2, height/2) in metres.
FURNITURE = [
    ("bed", (0.8, 1.05, 0.3)),
    ("nightstand", (0.22, 0.2, 0.28)),
    ("nightstand", (0.22, 0.2, 0.28)),
    ("wardrobe", (0.6, 0.3, 1.0)),
    ("desk", (0.6, 0.35, 0.38)),
]
BED, LEFT_STAND, RIGHT_STAND, WARDROBE, DESK = range(len(FURNITURE))


# Per wall of ROOM: the yaw that turns an object's back (local +y) to the wall, and the wall's
# line (axis 0: x = value, axis 1: y = value) with the direction into the room.
WALLS = [
    (np.pi, 1, 0.0, +1.0),  # wall 0, y = 0
    (-np.pi / 2, 0, 4.0, -1.0),  # wall 1, x = 4
    (0.0, 1, 5.0, -1.0),  # wall 2, y = 5
    (np.pi / 2, 0, 0.0, +1.0),  # wall 3, x = 0
]


def sample(rng, n):
    """`n` random layouts: an array of shape (n, objects, 7) of boxes standing on the floor.
    The bed, wardrobe and desk stand with their backs towards a random wall, at a random place
    along it and up to 10 cm from it; the nightstands beside the bed's head, up to 30 cm from
    it. Whether they collide, block the door or leave the room is left to the checks."""
    k = len(FURNITURE)
    half = np.array([h for _, h in FURNITURE])
    boxes = np.empty((n, k, 7))
    boxes[:, :, 2] = half[:, 2]
    boxes[:, :, 3:6] = half
    for obj in (BED, WARDROBE, DESK):
        wall = rng.integers(0, 4, n)
        gap = half[obj, 1] + rng.uniform(0.0, 0.1, n)
        yaw, axis, line, inward = (np.array([w[i] for w in WALLS])[wall] for i in range(4))
        along = rng.uniform(0.0, 1.0, n)
        boxes[:, obj, 6] = yaw
        boxes[:, obj, 0] = np.where(axis == 0, line + inward * gap, 0.5 + along * 3.0)
        boxes[:, obj, 1] = np.where(axis == 1, line + inward * gap, 0.5 + along * 4.0)
    yaw = boxes[:, BED, 6]
    for stand, side in ((LEFT_STAND, -1.0), (RIGHT_STAND, 1.0)):
        offset = side * (half[BED, 0] + half[stand, 0] + rng.uniform(0.0, 0.3, n))
        back = half[BED, 1] - half[stand, 1]
        boxes[:, stand, 0] = boxes[:, BED, 0] + offset * np.cos(yaw) - back * np.sin(yaw)
        boxes[:, stand, 1] = boxes[:, BED, 1] + offset * np.sin(yaw) + back * np.cos(yaw)
        boxes[:, stand, 6] = yaw
    return boxes


def relations_hold(boxes):
    """Which layouts satisfy every relation, scored for all layouts at once."""
    ok = np.ones(len(boxes), dtype=bool)
    checks = [
        ("against_wall", BED, None, {}),
        ("against_wall", WARDROBE, None, {}),
        ("against_wall", DESK, None, {}),
        ("side_of", LEFT_STAND, BED, {"side": "left"}),
        ("side_of", RIGHT_STAND, BED, {"side": "right"}),
        ("next_to", LEFT_STAND, BED, {}),
        ("next_to", RIGHT_STAND, BED, {}),
        ("across_from", DESK, BED, {}),
    ]
    for name, target, anchor, kw in checks:
        targets = np.ascontiguousarray(boxes[:, target])
        if anchor is None:
            scores = sceneeval.relation_batch(name, targets, room=ROOM, **kw)
        else:
            scores = sceneeval.relation_batch(name, targets, np.ascontiguousarray(boxes[:, anchor]), **kw)
        ok &= scores > 0.5
    # Nothing in front of the door: 0 for "next_to the door" (arch form) means it is clear.
    for obj in range(len(FURNITURE)):
        ok &= sceneeval.relation_batch("next_to", np.ascontiguousarray(boxes[:, obj]), arch="door", room=ROOM) < 0.5
    return ok


def plausible(layout):
    """Whether the layout has no collision and nothing out of bounds."""
    scene = sceneeval.Scene.from_boxes(layout, ROOM, categories=[c for c, _ in FURNITURE])
    summary = scene.plausibility(metrics=["collision", "out_of_bounds"])["summary"]
    return summary["col_sc"] is False and summary["oob"] == 0.0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--candidates", type=int, default=2000, help="layouts sampled per round")
    parser.add_argument("--keep", type=int, default=5, help="stop after this many accepted layouts")
    parser.add_argument("--rounds", type=int, default=20, help="give up after this many rounds")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", help="write the accepted layouts as JSON")
    args = parser.parse_args(argv)

    rng = np.random.default_rng(args.seed)
    kept, tried, passed_relations = [], 0, 0
    for _ in range(args.rounds):
        boxes = sample(rng, args.candidates)
        tried += len(boxes)
        survivors = boxes[relations_hold(boxes)]
        passed_relations += len(survivors)
        for layout in survivors:
            if plausible(layout):
                kept.append(layout)
                if len(kept) == args.keep:
                    break
        if len(kept) == args.keep:
            break
    print(f"{tried} layouts sampled, {passed_relations} satisfied the relations, {len(kept)} kept "
          f"(no collision, nothing out of bounds)")
    if args.out:
        with open(args.out, "w") as f:
            json.dump(
                {
                    "room": ROOM,
                    "categories": [c for c, _ in FURNITURE],
                    "layouts": [layout.tolist() for layout in kept],
                },
                f,
                indent=1,
            )
    return 0 if len(kept) == args.keep else 1


if __name__ == "__main__":
    sys.exit(main())
