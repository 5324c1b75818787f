#!/usr/bin/env python3
"""Scenes of issue 34, item 7: copies of objects at one pose (docs/performance.md,
"Coincident objects and the time budget").

Writes, under OUT (first argument, default target/coincident):
  plants_<N>/scene_<N>.json   the bed of fixture scene 0 and N fixture plants at one pose
                              (x 1.05, y 3.95, turned 0.3 rad), over the bed's left strip;
  holodeck_<K>/house/house.json
                              the Holodeck fixture bedroom with each of its six Objaverse
                              objects (bed, nightstand, storage box, painting, table lamp,
                              ceiling lamp) placed K times at its pose, for `sceneeval convert`.
Run from the repository root; the scenes refer to fixtures/assets (plants) and
fixtures/native/holodeck/objathor (houses).
"""

import copy
import json
import math
import os
import sys

OUT = sys.argv[1] if len(sys.argv) > 1 else "target/coincident"
PLANTS = [10, 20, 30, 40, 45, 50]
COPIES = [10, 50, 200]


def plants(n):
    scene = json.load(open("fixtures/scenes/scene_0.json"))
    objects = scene["scene"]["object"]
    bed = copy.deepcopy(next(o for o in objects if o["modelId"] == "fixture.bed"))
    bed["index"] = 0
    c, s = math.cos(0.3), math.sin(0.3)
    # Column-major: asset x -> (c, s, 0), asset y (up) -> z, asset z (front) -> (s, -c, 0).
    pose = [c, s, 0, 0, 0, 0, 1, 0, s, -c, 0, 0, 1.05, 3.95, 0, 1]
    scene["scene"]["object"] = [bed] + [
        {"index": k + 1, "modelId": "fixture.plant", "supportType": "ground",
         "transform": {"rows": 4, "cols": 4, "data": pose}}
        for k in range(n)
    ]
    folder = os.path.join(OUT, f"plants_{n}")
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, f"scene_{n}.json"), "w") as f:
        json.dump(scene, f, indent=1)


def house(k):
    src = "fixtures/native/holodeck/scenes/bedroom-2024-05-01/bedroom.json"
    house = json.load(open(src))
    # The chair is an AI2-THOR asset, which convert skips: the six others.
    six = [o for o in house["objects"] if not o["id"].startswith("Chair")]
    assert len(six) == 6, [o["id"] for o in six]
    ids = {o["id"] for o in six}
    house["objects"] = [dict(o, id=f"{o['id']} #{j}") for o in six for j in range(k)]
    for key in ["floor_objects", "wall_objects", "small_objects", "ceiling_objects"]:
        house[key] = [{"id": f"{e['id']} #{j}"} for e in house[key] if e["id"] in ids for j in range(k)]
    folder = os.path.join(OUT, f"holodeck_{k}", "house")
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "house.json"), "w") as f:
        json.dump(house, f, indent=1)


for n in PLANTS:
    plants(n)
for k in COPIES:
    house(k)
