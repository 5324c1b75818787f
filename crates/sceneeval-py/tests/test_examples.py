"""The Python examples run (small sizes, so that they finish in seconds)."""

import json
import subprocess
import sys

from conftest import FIXTURES, REPO

EXAMPLES = REPO / "examples" / "python"


def test_layout_sampler_keeps_only_layouts_that_pass(tmp_path):
    out = tmp_path / "layouts.json"
    done = subprocess.run(
        [sys.executable, str(EXAMPLES / "layout_sampler.py"), "--candidates", "300", "--keep", "2",
         "--seed", "1", "--out", str(out)],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert "2 kept" in done.stdout
    layouts = json.loads(out.read_text())["layouts"]
    assert len(layouts) == 2
    # Check the kept layouts again, independently of the sampler's own filter.
    import numpy as np
    import sceneeval

    sys.path.insert(0, str(EXAMPLES))
    import layout_sampler as ls

    for layout in layouts:
        boxes = np.array(layout)
        assert ls.relations_hold(boxes[None])[0]
        scene = sceneeval.Scene.from_boxes(boxes, ls.ROOM)
        summary = scene.plausibility(metrics=["collision", "out_of_bounds"])["summary"]
        assert summary["col_sc"] is False and summary["oob"] == 0.0


def test_evaluate_folder_script(tmp_path):
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    for name in ["scene_0.json", "scene_2.json"]:
        (scenes / name).write_bytes((FIXTURES / "scenes" / name).read_bytes())
    done = subprocess.run(
        [sys.executable, str(EXAMPLES / "evaluate_folder.py"), str(scenes), "--assets",
         f"fixture={FIXTURES / 'assets'}", "--out", str(tmp_path / "out")],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.startswith("| group | scenes |")
    assert "2 scenes: 2 evaluated" in done.stdout
    assert (tmp_path / "out" / "scene_2" / "eval.json").exists()


def test_the_readme_example_runs():
    text = (REPO / "README.md").read_text()
    start = text.index("```python\n", text.index("## Python")) + len("```python\n")
    code = text[start : text.index("```", start)]
    done = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[0] == "1.0"
