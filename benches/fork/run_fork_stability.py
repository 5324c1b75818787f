#!/usr/bin/env python3
"""Run the SceneSmith fork's stability metrics on rooms exported by `stability-rooms`.

A measurement tool, outside the build: never run in CI, never used by a test. It needs

- a checkout of the fork (https://github.com/nepfaff/SceneEval; only its `metrics/` folder is
  read), given by `--fork`;
- a Python environment with the fork's physics dependencies: `python3 -m venv /work/fork-venv
  && /work/fork-venv/bin/pip install drake coacd trimesh numpy scipy omegaconf pydantic`
  (measured with drake 1.51.1, coacd 1.0.14, trimesh 5.2.0);
- rooms written by `target/release/stability-rooms [--heavy] --export-fork DIR`: for each room
  the sceneState file, every object's world-space mesh (OBJ) and its support type.

The fork's own metric classes are imported from the checkout and run unchanged
(`StaticEquilibriumMetricCoACD`, `WeldedEquilibriumMetricCoACD`,
`ArchitecturalWeldedEquilibriumMetricCoACD`, `CombinedWeldedEquilibriumMetricCoACD`, with the
parameters of the fork's `configs/metrics.yaml`: CoACD threshold 0.03, 5 s at 1 ms, point
contact, 1 cm and 0.1 rad). The fork loads scenes through Blender (`bpy`); this driver replaces
only that loader: a small `Scene` stand-in with the attributes the metrics read (`t_objs`: each
object's world-space trimesh; `t_architecture`: the floor and wall meshes built as the fork's
`TrimeshScene.load_architecture` builds them, floor at the lowest object point, 1 mm thick;
`output_dir` holding `obj_support_type_result.json` from the scene's support types). Two
settings differ from the fork's configuration file, both on the fork's side of the comparison:
no Meshcat HTML is recorded (`save_simulation_html` off), and the `none` variant
(`StaticEquilibriumMetricCoACD`) runs with `weld_wall_ceiling_objects` off, since its default
welds wall and ceiling objects like `architectural`.

Usage:
  run_fork_stability.py --fork /work/fork-src --rooms /tmp/rooms [--scenes 0,1] \\
      [--variants none,architectural,penetration,combined] [--work DIR] [--out results.json]

Prints one line per room and variant (wall and CPU seconds, of which CoACD, pieces, the
unstable objects) and writes every result to `--out`.
"""

import argparse
import importlib
import json
import pathlib
import sys
import tempfile
import time
import types

VARIANTS = {
    "none": ("static_equilibrium", "StaticEquilibriumMetricCoACD", "StaticEquilibriumMetricConfigCoACD"),
    "architectural": (
        "architectural_welded_equilibrium",
        "ArchitecturalWeldedEquilibriumMetricCoACD",
        "ArchitecturalWeldedEquilibriumMetricConfigCoACD",
    ),
    "penetration": ("welded_equilibrium", "WeldedEquilibriumMetricCoACD", "WeldedEquilibriumMetricConfigCoACD"),
    "combined": (
        "combined_welded_equilibrium",
        "CombinedWeldedEquilibriumMetricCoACD",
        "CombinedWeldedEquilibriumMetricConfigCoACD",
    ),
}

# configs/metrics.yaml of the fork, CoACD variants.
FORK_PARAMS = dict(
    simulation_time=5.0,
    time_step=1.0e-3,
    coacd_threshold=0.03,
    displacement_threshold=0.01,
    rotation_threshold=0.1,
    hydroelastic_modulus=None,
    save_simulation_html=False,
)


def import_fork_metrics(fork: pathlib.Path):
    """Imports the fork's metric modules without its Blender-bound `scenes` package and
    without `metrics/__init__.py` (which imports every metric, VLM ones included)."""
    scenes = types.ModuleType("scenes")

    class Scene:  # only used in type annotations by the metric modules
        pass

    scenes.Scene = Scene
    sys.modules["scenes"] = scenes
    metrics = types.ModuleType("metrics")
    metrics.__path__ = [str(fork / "metrics")]
    sys.modules["metrics"] = metrics
    drake_utils = importlib.import_module("metrics.drake_utils")
    modules = {v: importlib.import_module(f"metrics.{m}") for v, (m, _, _) in VARIANTS.items()}
    return drake_utils, modules


class CoacdTimer:
    """Wraps the fork's `generate_collision_geometry` to add up its wall and CPU time."""

    def __init__(self, drake_utils):
        self.inner = drake_utils.generate_collision_geometry
        self.reset()
        drake_utils.generate_collision_geometry = self

    def reset(self):
        self.wall = self.cpu = 0.0
        self.calls = self.pieces = 0

    def __call__(self, mesh, *args, **kwargs):
        w, c = time.perf_counter(), time.process_time()
        pieces = self.inner(mesh, *args, **kwargs)
        self.wall += time.perf_counter() - w
        self.cpu += time.process_time() - c
        self.calls += 1
        self.pieces += len(pieces)
        return pieces


class RoomScene:
    """What the fork's stability metrics read from its `Scene`."""

    def __init__(self, trimesh, np, room_dir: pathlib.Path, output_dir: pathlib.Path):
        manifest = json.loads((room_dir / "manifest.json").read_text())
        self.t_objs = {}
        support = {}
        for o in manifest["objects"]:
            self.t_objs[o["id"]] = trimesh.load(room_dir / o["mesh"], force="mesh", process=False)
            if o["support"] is not None:
                support[o["id"]] = o["support"]
        self.triangles = sum(o["triangles"] for o in manifest["objects"])
        self.output_dir = output_dir
        output_dir.mkdir(parents=True, exist_ok=True)
        (output_dir / "obj_support_type_result.json").write_text(json.dumps(support))
        self.t_architecture = architecture(trimesh, np, json.loads(pathlib.Path(manifest["scene"]).read_text()), self.t_objs)

    def get_obj_ids(self):
        return list(self.t_objs.keys())


def architecture(trimesh, np, scene_state: dict, t_objs: dict) -> dict:
    """The fork's `TrimeshScene.load_architecture` for rectangular rooms: floors as 1 mm slabs
    whose top is the lowest object point, walls as boxes of the wall's length, 1 mm thick and
    the wall's height. Holes are left out: the fork fills them with 1 mm boxes of their own,
    and only each element's bounding box reaches Drake (`generate_floor_sdf`)."""
    thickness = 0.001
    floor_height = min(m.bounds[0][2] for m in t_objs.values())
    arch = {}
    for e in scene_state["scene"]["arch"]["elements"]:
        if e["type"] == "Floor":
            pts = np.asarray(e["points"])[:, :2]
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            floor = trimesh.creation.box((hi[0] - lo[0], hi[1] - lo[1], thickness))
            floor.apply_translation([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, floor_height])
            arch[f"floor_{e['roomId'].replace(' ', '_')}"] = floor
        elif e["type"] == "Wall":
            a, b = np.asarray(e["points"][0], float), np.asarray(e["points"][1], float)
            wall = trimesh.creation.box((np.linalg.norm(b - a), thickness, e["height"]))
            if np.isclose(a[0], b[0]):
                wall.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 0, 1]))
            centre = (a + b) / 2 + [0, 0, floor_height - thickness / 2 + e["height"] / 2]
            wall.apply_translation(centre)
            arch[f"wall_{e['id']}"] = wall
    return arch


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fork", type=pathlib.Path, required=True)
    ap.add_argument("--rooms", type=pathlib.Path, required=True)
    ap.add_argument("--scenes", default=None, help="comma-separated room numbers (default: all)")
    ap.add_argument("--variants", default="none,architectural,penetration,combined")
    ap.add_argument("--work", type=pathlib.Path, default=None, help="Drake output folder (default: a temporary one)")
    ap.add_argument("--out", type=pathlib.Path, default=None)
    args = ap.parse_args()

    import numpy as np
    import trimesh

    drake_utils, modules = import_fork_metrics(args.fork.resolve())
    timer = CoacdTimer(drake_utils)
    rooms = sorted(args.rooms.glob("scene_*"), key=lambda p: int(p.name.split("_")[1]))
    if args.scenes:
        wanted = {f"scene_{n}" for n in args.scenes.split(",")}
        rooms = [r for r in rooms if r.name in wanted]
    work_tmp = None
    if args.work is None:
        work_tmp = tempfile.TemporaryDirectory(prefix="fork-stability-")
        work = pathlib.Path(work_tmp.name)
    else:
        work = args.work
    results = []
    total_wall = total_cpu = 0.0
    for variant in args.variants.split(","):
        module_name, cls_name, cfg_name = VARIANTS[variant]
        module = modules[variant]
        cfg_cls = getattr(module, cfg_name)
        fields = cfg_cls.__dataclass_fields__
        cfg = cfg_cls(**{k: v for k, v in FORK_PARAMS.items() if k in fields})
        if variant == "none":
            cfg.weld_wall_ceiling_objects = False
        for room in rooms:
            out_dir = work / variant / room.name
            scene = RoomScene(trimesh, np, room, out_dir)
            metric = getattr(module, cls_name)(scene=scene, output_dir=out_dir, cfg=cfg)
            timer.reset()
            w, c = time.perf_counter(), time.process_time()
            r = metric.run()
            wall, cpu = time.perf_counter() - w, time.process_time() - c
            total_wall += wall
            total_cpu += cpu
            per = r.data["per_object_results"]
            unstable = sorted(k for k, v in per.items() if not v["stable"])
            welded = sorted(k for k, v in per.items() if v.get("welded"))
            row = dict(
                variant=variant,
                room=room.name,
                objects=len(scene.t_objs),
                simulated_objects=len(per),
                triangles=scene.triangles,
                wall_s=wall,
                cpu_s=cpu,
                coacd_calls=timer.calls,
                coacd_wall_s=timer.wall,
                coacd_cpu_s=timer.cpu,
                coacd_pieces=timer.pieces,
                unstable=unstable,
                welded=welded,
                per_object={k: dict(stable=v["stable"], displacement=v["displacement"], rotation=v["rotation"]) for k, v in per.items()},
            )
            results.append(row)
            print(
                f"{variant:13} {room.name:9}: {len(scene.t_objs):3} objects ({len(per)} simulated), {scene.triangles:7} triangles, "
                f"{wall:8.2f} s wall, {cpu:8.2f} s CPU, CoACD {timer.calls} calls {timer.wall:7.2f} s wall {timer.cpu:7.2f} s CPU "
                f"{timer.pieces} pieces; unstable {unstable}",
                flush=True,
            )
            if args.out:
                tmp = args.out.with_suffix(".tmp")
                tmp.write_text(json.dumps(results, indent=1))
                tmp.replace(args.out)
    print(f"total: {len(results)} evaluations in {total_wall:.1f} s wall, {total_cpu:.1f} s CPU")
    if work_tmp is not None:
        work_tmp.cleanup()


if __name__ == "__main__":
    main()
