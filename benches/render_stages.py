#!/usr/bin/env python3
"""Instructions per render of the render-profile example under valgrind, split by stage.

Runs `render-profile --renders 1` and `--renders 3` under callgrind with LP_NUM_THREADS=0 (Mesa's
software driver rasterises on its queue thread, so the profile is attributable) and prints half
of the difference: the cost of one render without device set-up. Instruction counts do not
depend on the machine's load, unlike wall-clock time. LLVM's shader compilation varies between
runs and is left out.

Stages (docs/performance.md, Rendering):
- rasteriser: everything under llvmpipe's function that executes the binned commands
  (rasterize_scene; found by its address in the driver build named below, or given with
  --rasterizer);
  - fragment shader: the JIT-compiled code that function's callees call (depth test, shading
    and colour store of 4x4 blocks);
  - coverage and tiles: the rest (edge tests per sample and block, clears, tile work);
- driver outside the rasteriser: vertex fetch, vertex shader, clipping, triangle setup,
  binning, resolve, copies;
- application: the example binary itself (wgpu, camera fitting, readback, un-premultiplying).

Usage (after `cargo build --profile bench -p sceneeval-benches --example render-profile`):

    python3 benches/render_stages.py --samples 4 --scene cylinders
    python3 benches/render_stages.py --samples 4 --scene tubes --keep /tmp/cg

Needs valgrind and Mesa's lavapipe; takes about two minutes per call on 2 cores.
"""

import argparse
import collections
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

# rasterize_scene in Debian 12's libvulkan_lvp.so (mesa-vulkan-drivers 22.3.6-1+deb12u2, build
# id 24e14fcfbc653ef35e1a154015265e7d2b20d61e), identified from the call graph: called at the
# end of every render pass and when the scene fills up, and calling the triangle commands.
KNOWN_RASTERIZERS = {"24e14fcfbc653ef35e1a154015265e7d2b20d61e": 0x2800B0}
LAVAPIPE = "libvulkan_lvp.so"


def parse(path):
    """Self costs per (object, function), and inclusive call costs and counts per edge."""
    names = {"ob": {}, "fn": {}}
    ob = fn = cob = cfn = None
    self_cost = collections.Counter()
    calls = collections.Counter()
    call_counts = collections.Counter()
    pending = None

    def resolve(kind, value):
        m = re.match(r"\((\d+)\)(?:\s+(.*))?", value)
        if not m:
            return value
        if m.group(2) is not None:
            names[kind][m.group(1)] = m.group(2)
        return names[kind].get(m.group(1), "?")

    with open(path, errors="replace") as f:
        for line in f:
            line = line.rstrip("\n")
            if not line:
                continue
            if line[0].isdigit() or line[0] in "+-*":
                parts = line.split()
                if pending is not None:
                    if len(parts) >= 2:
                        calls[((ob, fn), pending)] += int(parts[-1])
                    pending = None
                elif len(parts) >= 2:
                    self_cost[(ob, fn)] += int(parts[-1])
                continue
            if "=" not in line:
                continue
            key, value = line.split("=", 1)
            if key == "ob":
                ob, cob = resolve("ob", value), None
            elif key == "fn":
                fn, cob = resolve("fn", value), None
            elif key == "cob":
                cob = resolve("ob", value)
            elif key == "cfn":
                cfn = resolve("fn", value)
            elif key == "calls":
                pending = (cob if cob is not None else ob, cfn)
                call_counts[((ob, fn), pending)] += int(value.split()[0])
    return self_cost, calls, call_counts


def stages(path, rasterizer):
    self_cost, calls, call_counts = parse(path)
    compiling = lambda o: o is not None and ("libLLVM" in o or "libz3" in o)
    total = sum(v for (o, _), v in self_cost.items() if not compiling(o))
    app = sum(v for (o, _), v in self_cost.items() if o and "render-profile" in o)
    out = {"total": total, "application": app}
    entry = next((k for k in self_cost if k[0] and k[0].endswith(LAVAPIPE) and k[1] == rasterizer), None)
    if entry is None:
        return out
    callees = collections.defaultdict(set)
    for (a, b) in calls:
        callees[a].add(b)
    inclusive = self_cost[entry] + sum(v for (a, b), v in calls.items() if a == entry and b != entry)
    inside, todo = {entry}, [entry]
    while todo:
        for b in callees[todo.pop()]:
            if b not in inside:
                inside.add(b)
                todo.append(b)
    fs = [(v, call_counts[(a, b)]) for (a, b), v in calls.items()
          if a in inside and a[0] and a[0].endswith(LAVAPIPE) and b[0] == "???"]
    out["rasteriser"] = inclusive
    out["fragment shader"] = sum(v for v, _ in fs)
    out["fragment shader calls"] = sum(n for _, n in fs)
    out["coverage and tiles"] = inclusive - out["fragment shader"]
    out["driver outside the rasteriser"] = total - inclusive - app
    return out


def build_id(library):
    note = subprocess.run(["readelf", "-n", library], capture_output=True, text=True).stdout
    m = re.search(r"Build ID:\s*([0-9a-f]+)", note)
    return m.group(1) if m else None


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--samples", default="4")
    p.add_argument("--scene", default="cylinders", help="cylinders, tubes or fixtures")
    p.add_argument("--size", default="512", help="image side in pixels")
    p.add_argument("--binary", default="target/release/examples/render-profile")
    p.add_argument("--rasterizer", help="address of llvmpipe's rasterize_scene (hex)")
    p.add_argument("--keep", help="directory for the callgrind files (default: a temporary one)")
    args = p.parse_args()

    library = "/usr/lib/x86_64-linux-gnu/" + LAVAPIPE
    rasterizer = int(args.rasterizer, 16) if args.rasterizer else KNOWN_RASTERIZERS.get(build_id(library) or "")
    directory = Path(args.keep or tempfile.mkdtemp(prefix="render-stages-"))
    directory.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, LP_NUM_THREADS="0", XDG_RUNTIME_DIR=os.environ.get("XDG_RUNTIME_DIR", "/tmp"))
    runs = {}
    for renders in (1, 3):
        out = directory / f"callgrind.{args.scene}.{args.size}.s{args.samples}.n{renders}"
        cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", args.binary,
               "--samples", args.samples, "--renders", str(renders), "--scene", args.scene,
               "--size", args.size]
        subprocess.run(cmd, env=env, check=True, capture_output=True)
        runs[renders] = stages(out, None if rasterizer is None else f"0x{rasterizer:016x}")
    print(f"{args.scene}, {args.size} x {args.size}, {args.samples} sample(s) per pixel: instructions per render "
          f"(half of 3 renders minus 1; files in {directory})")
    for key in runs[3]:
        diff = (runs[3][key] - runs[1].get(key, 0)) / 2
        print(f"  {key:32} {diff:12,.0f}" if "calls" in key else f"  {key:32} {diff / 1e6:10.1f} M")
    if rasterizer is None:
        print("  (unknown lavapipe build: pass --rasterizer to split the stages)", file=sys.stderr)


if __name__ == "__main__":
    main()
