"""sceneeval.evaluate writes the same files as `sceneeval evaluate` on fixture scenes."""

import shutil
import subprocess

import pytest

import sceneeval
from conftest import FIXTURES

SCENES = ["scene_0.json", "scene_1.json", "scene_3.json"]


@pytest.fixture
def scenes_dir(tmp_path):
    d = tmp_path / "scenes"
    d.mkdir()
    for name in SCENES:
        shutil.copy(FIXTURES / "scenes" / name, d / name)
    (d / "scene_x.json").write_text("{}")  # looks like a scene, is skipped
    return d


def test_evaluate_writes_what_the_cli_writes(sceneeval_bin, scenes_dir, tmp_path):
    annotations = FIXTURES / "annotations" / "fixture_scenes.csv"
    cli_out, py_out = tmp_path / "cli", tmp_path / "py"
    subprocess.run(
        [str(sceneeval_bin), "evaluate", str(scenes_dir), "--assets", f"fixture={FIXTURES / 'assets'}",
         "--out", str(cli_out), "--annotations", str(annotations), "--no-progress"],
        check=True, capture_output=True,
    )
    run = sceneeval.evaluate(scenes_dir, assets={"fixture": FIXTURES / "assets"}, out=py_out, annotations=annotations)
    assert (run["scenes"], run["evaluated"], run["reused"], run["failed"]) == (3, 3, 0, 0)
    assert [s["path"].endswith("scene_x.json") for s in run["skipped"]] == [True]
    for name in SCENES:
        stem = name[:-5]
        assert (py_out / stem / "eval.json").read_bytes() == (cli_out / stem / "eval.json").read_bytes(), stem
        assert (py_out / stem / "timing.json").exists()
    assert (py_out / "summary.csv").read_text() == (cli_out / "summary.csv").read_text()
    assert (py_out / "summary.md").read_text() == (cli_out / "summary.md").read_text()
    assert run["summary"]["groups"][0]["group"] == "all"
    # A re-run reuses every result.
    again = sceneeval.evaluate(scenes_dir, assets={"fixture": FIXTURES / "assets"}, out=py_out, annotations=annotations)
    assert (again["evaluated"], again["reused"]) == (0, 3)


def test_plans_by_preset_name_or_file(scenes_dir, tmp_path):
    plan = tmp_path / "plan.json"
    plan.write_text('{"preset": "reference", "metrics": ["collision", "out_of_bounds"]}')
    run = sceneeval.evaluate(scenes_dir, assets={"fixture": FIXTURES / "assets"}, out=tmp_path / "a", plan=str(plan))
    assert run["failed"] == 0
    assert "Preset: `reference`" in (tmp_path / "a" / "summary.md").read_text()
    run = sceneeval.evaluate(scenes_dir, assets={"fixture": FIXTURES / "assets"}, out=tmp_path / "b", plan="reference")
    assert run["evaluated"] == 3
    with pytest.raises(ValueError, match="not a preset name"):
        sceneeval.evaluate(scenes_dir, assets={}, out=tmp_path / "c", plan="refrence")


def test_failures_are_recorded_and_unusable_input_raises(scenes_dir, tmp_path):
    # Without the asset folder every scene fails to load; the run records it and goes on.
    run = sceneeval.evaluate(scenes_dir, assets=None, out=tmp_path / "out")
    assert run["failed"] == 3 and len(run["failures"]) == 3
    assert "fixture." in run["failures"][0]["error"] + " ".join(run["failures"][0]["causes"])
    with pytest.raises(sceneeval.SceneEvalError, match="no scene_<ID>.json files"):
        sceneeval.evaluate(tmp_path / "out", assets=None, out=tmp_path / "o2")
    with pytest.raises(sceneeval.SceneEvalError):
        sceneeval.evaluate(tmp_path / "missing", assets=None, out=tmp_path / "o3")
