#!/usr/bin/env python3
"""The tools a Python researcher would use instead of sceneeval, on the same scenes.

Reads a manifest written by `scaling gen` (the scene exactly as sceneeval-io reads it back:
each distinct mesh in its object frame, world poses, floors, support types and functional
sides) and times one task with one peer, printing one JSON line:

  collision      fcl (python-fcl directly: one BVH per distinct mesh, a dynamic AABB tree
                 over the objects, every overlapping pair tested) or trimesh (its
                 CollisionManager, one BVH per object, `in_collision_internal(return_names)`)
  support        embree (trimesh with the embree backend: rays along the support direction
                 from every vertex within 1 cm of the object's extreme, 5 mm behind it, into
                 one intersector over every object and the floors; hits on the object itself
                 skipped)
  out_of_bounds  embree (max(1000, 5000 x box volume) surface samples per object, seeded,
                 cast straight down against the floors, as the reference does)
  navigability   shapely (floor shrunk and convex-hull footprints grown by half the robot
                 width, rasterised at pixel centres with shapely.contains_xy) + scipy
                 (ndimage.label, 8-connected), at --resolution metres per pixel
  accessibility  shapely (each functional side's strip, clipped to the floor, minus the
                 footprints an STRtree finds near it; free area over strip area)

Setup (loading the manifest, building meshes and BVHs of the distinct meshes) is not in
"seconds", as sceneeval's per-mesh tables are not in its repeated runs; fcl's BVH build is
reported as "build_seconds", the counterpart of sceneeval's first run (which builds its
per-mesh tables); trimesh's manager builds a BVH per object inside its timer. Peak memory is
the process's.
trimesh's manager (a BVH per object) and the embree support scene are skipped above 2 M and
8 M triangles, where they would not fit in the measuring machine's memory.
"""

import argparse
import json
import resource
import sys
import time

import numpy as np


def load(path):
    with open(path) as f:
        m = json.load(f)
    meshes = [
        (np.asarray(x["vertices"], dtype=np.float64), np.asarray(x["triangles"], dtype=np.int64))
        for x in m["meshes"]
    ]
    poses = [np.asarray(o["pose"], dtype=np.float64).reshape(4, 4) for o in m["objects"]]
    return m, meshes, poses


def world_vertices(meshes, poses, objects, k):
    v, _ = meshes[objects[k]["mesh"]]
    p = poses[k]
    return v @ p[:3, :3].T + p[:3, 3]


def peak_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def collision_fcl(m, meshes, poses):
    import fcl

    # Building the BVHs of the distinct meshes is timed separately ("build_seconds"): the
    # counterpart of sceneeval's per-mesh tables, which its first run builds ("first run"
    # columns of report.py compare build plus collision on both sides).
    t_build = time.perf_counter()
    bvhs = []
    for v, t in meshes:
        b = fcl.BVHModel()
        b.beginModel(len(v), len(t))
        b.addSubModel(v, t)
        b.endModel()
        bvhs.append(b)
    build_seconds = time.perf_counter() - t_build
    objs = [fcl.CollisionObject(bvhs[o["mesh"]], fcl.Transform(p[:3, :3], p[:3, 3])) for o, p in zip(m["objects"], poses)]
    t0 = time.perf_counter()
    manager = fcl.DynamicAABBTreeCollisionManager()
    manager.registerObjects(objs)
    manager.setup()
    request = fcl.CollisionRequest(num_max_contacts=1, enable_contact=False)
    count = [0]

    def callback(o1, o2, data):
        result = fcl.CollisionResult()
        if fcl.collide(o1, o2, request, result):
            count[0] += 1
        return False

    manager.collide(fcl.CollisionData(request=request), callback)
    return time.perf_counter() - t0, {"touching_pairs": count[0], "build_seconds": build_seconds}


def collision_trimesh(m, meshes, poses):
    import trimesh

    tms = [trimesh.Trimesh(vertices=v, faces=t, process=False) for v, t in meshes]
    t0 = time.perf_counter()
    manager = trimesh.collision.CollisionManager()
    for o, p in zip(m["objects"], poses):
        manager.add_object(o["id"], tms[o["mesh"]], transform=p)
    _, names = manager.in_collision_internal(return_names=True)
    return time.perf_counter() - t0, {"touching_pairs": len(names)}


def floor_mesh(m):
    """The floors as one triangle soup (fan triangulation of each polygon, ear clipping for
    concave ones through shapely/trimesh)."""
    import trimesh
    from shapely.geometry import Polygon

    parts = []
    for f in m["floors"]:
        v, faces = trimesh.creation.triangulate_polygon(Polygon(f["polygon"]))
        v3 = np.column_stack([v, np.full(len(v), f["z"])])
        parts.append(trimesh.Trimesh(vertices=v3, faces=faces, process=False))
    return trimesh.util.concatenate(parts)


def intersector(mesh):
    from trimesh.ray.ray_pyembree import RayMeshIntersector

    return RayMeshIntersector(mesh)


def support_embree(m, meshes, poses):
    import trimesh

    objects = m["objects"]
    world = [world_vertices(meshes, poses, objects, k) for k in range(len(objects))]
    parts = [trimesh.Trimesh(vertices=world[k], faces=meshes[o["mesh"]][1], process=False) for k, o in enumerate(objects)]
    floor = floor_mesh(m)
    scene = trimesh.util.concatenate(parts + [floor])
    owner = np.concatenate([np.full(len(meshes[o["mesh"]][1]), k) for k, o in enumerate(objects)] + [np.full(len(floor.faces), -1)])
    t0 = time.perf_counter()
    rays = intersector(scene)
    origins, dirs, who = [], [], []
    for k, o in enumerate(objects):
        w = world[k]
        p = poses[k]
        kind = o.get("support", "ground")
        if kind == "ceiling":
            g = np.array([0.0, 0.0, 1.0])
        elif kind == "wall":
            g = p[:3, :3] @ np.array([0.0, 1.0, 0.0])
        else:
            g = np.array([0.0, 0.0, -1.0])
        along = w @ g
        band = w[along >= along.max() - 0.01]
        band = np.unique(band, axis=0)
        origins.append(band - g * 0.005)
        dirs.append(np.repeat(g[None, :], len(band), axis=0))
        who.append(np.full(len(band), k))
    origins, dirs, who = np.concatenate(origins), np.concatenate(dirs), np.concatenate(who)
    locs, ray_idx, tri_idx = rays.intersects_location(origins, dirs, multiple_hits=True)
    # The nearest hit on anything but the ray's own object, within 1 cm.
    other = owner[tri_idx] != who[ray_idx]
    dist = np.linalg.norm(locs - origins[ray_idx], axis=1)
    ok = other & (dist < 0.01)
    contacts = len(np.unique(ray_idx[ok]))
    return time.perf_counter() - t0, {"rays": len(origins), "contact_rays": int(contacts)}


def oob_embree(m, meshes, poses):
    import trimesh

    objects = m["objects"]
    floor = floor_mesh(m)
    rng = np.random.default_rng(0)
    tms = [trimesh.Trimesh(vertices=v, faces=t, process=False) for v, t in meshes]
    t0 = time.perf_counter()
    rays = intersector(floor)
    out = 0
    total_rays = 0
    for k, o in enumerate(objects):
        mesh = tms[o["mesh"]]
        ext = mesh.bounds[1] - mesh.bounds[0]
        n = int(max(1000, 5000 * float(np.prod(ext))))
        pts, _ = trimesh.sample.sample_surface(mesh, n, seed=rng)
        p = poses[k]
        pts = pts @ p[:3, :3].T + p[:3, 3]
        hit = rays.intersects_any(pts, np.repeat([[0.0, 0.0, -1.0]], len(pts), axis=0))
        total_rays += n
        if hit.mean() < 0.99:
            out += 1
    return time.perf_counter() - t0, {"rays": total_rays, "out_of_bounds": out}


def footprints(m, meshes, poses):
    from shapely import MultiPoint

    objects = m["objects"]
    out = []
    for k in range(len(objects)):
        w = world_vertices(meshes, poses, objects, k)
        out.append((MultiPoint(w[:, :2]).convex_hull, w[:, 2].min(), w[:, 2].max()))
    return out


def navigability_shapely(m, meshes, poses, resolution, robot=0.2):
    import shapely
    from scipy import ndimage
    from shapely.geometry import Polygon

    r = robot / 2
    t0 = time.perf_counter()
    fps = footprints(m, meshes, poses)
    floor = shapely.union_all([Polygon(f["polygon"]) for f in m["floors"]])
    fz = min(f["z"] for f in m["floors"])
    obstacles = [fp.buffer(r) for fp, lo, hi in fps if lo - fz < 2.0 and hi - fz > 0.0]
    free = floor.buffer(-r).difference(shapely.union_all(obstacles))
    x0, y0, x1, y1 = floor.bounds
    xs = np.arange(x0 + resolution / 2, x1, resolution)
    ys = np.arange(y0 + resolution / 2, y1, resolution)
    shapely.prepare(free)
    mask = np.zeros((len(ys), len(xs)), dtype=bool)
    # Row by row keeps memory to one row of coordinates.
    for j, y in enumerate(ys):
        mask[j] = shapely.contains_xy(free, xs, np.full(len(xs), y))
    labels, count = ndimage.label(mask, structure=np.ones((3, 3)))
    sizes = np.bincount(labels.ravel())[1:]
    nav = float(sizes.max() / sizes.sum()) if sizes.size else 0.0
    return time.perf_counter() - t0, {"pixels": int(mask.size), "components": int(count), "nav": nav}


def accessibility_shapely(m, meshes, poses):
    import shapely
    from shapely.geometry import Polygon
    from shapely.strtree import STRtree

    objects = m["objects"]
    t0 = time.perf_counter()
    fps = footprints(m, meshes, poses)
    floor = shapely.union_all([Polygon(f["polygon"]) for f in m["floors"]])
    fz = min(f["z"] for f in m["floors"])
    blocking = [k for k, (fp, lo, hi) in enumerate(fps) if lo - fz < 2.0 and hi - fz > 0.0]
    tree = STRtree([fps[k][0] for k in blocking])
    dirs = {"front": (1, -1.0), "back": (1, 1.0), "left": (0, -1.0), "right": (0, 1.0)}
    scores = []
    for k, o in enumerate(objects):
        sides = o.get("sides") or []
        if not sides:
            continue
        v, _ = meshes[o["mesh"]]
        lo, hi = v.min(axis=0), v.max(axis=0)
        c, h = (lo + hi) / 2, (hi - lo) / 2
        best = 0.0
        for s in sides:
            a, sign = dirs[s]
            b = 1 - a
            near, far = c[a] + sign * (h[a] + 0.05), c[a] + sign * (h[a] + 0.25)
            corners = []
            for along, across in [(near, c[b] - h[b]), (far, c[b] - h[b]), (far, c[b] + h[b]), (near, c[b] + h[b])]:
                p = np.array([0.0, 0.0, c[2], 1.0])
                p[a], p[b] = along, across
                corners.append((poses[k] @ p)[:2])
            strip = Polygon(corners)
            if strip.area <= 0:
                continue
            part = strip.intersection(floor)
            near_fp = [fps[blocking[i]][0] for i in tree.query(strip) if blocking[i] != k]
            if near_fp:
                part = part.difference(shapely.union_all(near_fp))
            best = max(best, part.area / strip.area)
        scores.append(best)
    acc = float(np.mean(scores)) if scores else None
    return time.perf_counter() - t0, {"scored": len(scores), "acc": acc}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--manifest", required=True)
    ap.add_argument("--task", required=True)
    ap.add_argument("--peer", required=True)
    ap.add_argument("--resolution", type=float, default=0.02)
    args = ap.parse_args()
    m, meshes, poses = load(args.manifest)
    task = (args.task, args.peer)
    # Peers that copy every object's triangles (a BVH per object, one scene-wide ray
    # structure) are skipped where they would not fit in memory on the measuring machine.
    total = sum(len(meshes[o["mesh"]][1]) for o in m["objects"])
    limits = {("collision", "trimesh"): 2_000_000, ("support", "embree"): 8_000_000}
    if task in limits and total > limits[task]:
        print(json.dumps({"manifest": args.manifest, "objects": len(m["objects"]), "task": args.task,
                          "peer": args.peer, "skipped": f"{total:,} triangles > {limits[task]:,}"}))
        return
    if task == ("collision", "fcl"):
        seconds, info = collision_fcl(m, meshes, poses)
    elif task == ("collision", "trimesh"):
        seconds, info = collision_trimesh(m, meshes, poses)
    elif task == ("support", "embree"):
        seconds, info = support_embree(m, meshes, poses)
    elif task == ("out_of_bounds", "embree"):
        seconds, info = oob_embree(m, meshes, poses)
    elif task == ("navigability", "shapely"):
        seconds, info = navigability_shapely(m, meshes, poses, args.resolution)
    elif task == ("accessibility", "shapely"):
        seconds, info = accessibility_shapely(m, meshes, poses)
    else:
        sys.exit(f"unknown task/peer {task}")
    print(
        json.dumps(
            {
                "manifest": args.manifest,
                "objects": len(m["objects"]),
                "task": args.task,
                "peer": args.peer,
                "seconds": seconds,
                "peak_mb": peak_mb(),
                **info,
            }
        )
    )


if __name__ == "__main__":
    main()
