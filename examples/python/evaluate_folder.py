#!/usr/bin/env python3
"""Evaluates a folder of sceneState scenes (scene_<ID>.json) with sceneeval.evaluate, which
writes the same files as `sceneeval evaluate`, and prints the summary table and any failures.

    python examples/python/evaluate_folder.py fixtures/scenes --assets fixture=fixtures/assets \\
        --out target/py-eval [--annotations fixtures/annotations/fixture_scenes.csv] \\
        [--plan geometry|full|LIST|FILE] [--preset reference]
"""

import argparse
import sys
from pathlib import Path

import sceneeval


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", type=Path, help="folder holding the scene_<ID>.json files")
    parser.add_argument("--assets", action="append", default=[], metavar="PREFIX=DIR",
                        help="asset folder of a model id prefix (repeatable)")
    parser.add_argument("--out", type=Path, required=True, help="output folder")
    parser.add_argument("--annotations", type=Path, help="SceneEval-500 annotation CSV")
    parser.add_argument("--plan", help="geometry (default), full, a metric list or a plan file, as for sceneeval evaluate")
    parser.add_argument("--preset", help="parameter preset: default or reference")
    args = parser.parse_args(argv)

    assets = {}
    for spec in args.assets:
        prefix, sep, folder = spec.partition("=")
        if not sep:
            parser.error(f"--assets {spec!r}: expected PREFIX=DIR")
        assets[prefix] = folder
    try:
        run = sceneeval.evaluate(args.scenes, assets=assets, out=args.out,
                                 annotations=args.annotations, plan=args.plan, preset=args.preset)
    except (ValueError, sceneeval.SceneEvalError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    print((args.out / "summary.md").read_text(), end="")
    print(f"{run['scenes']} scenes: {run['evaluated']} evaluated, {run['reused']} kept from an "
          f"earlier run, {run['failed']} failed; results in {run['out']}")
    for failure in run["failures"]:
        print(f"failed: {failure['scene']}: {failure['error']}", file=sys.stderr)
    return 1 if run["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
