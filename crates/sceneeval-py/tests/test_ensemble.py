"""sceneeval.ensemble writes the run folder `sceneeval ensemble` writes, from the same runs."""

import shutil
import subprocess

import pytest

import sceneeval
from conftest import FIXTURES

SCENES = ["scene_0.json", "scene_1.json", "scene_3.json"]
ANNOTATIONS = FIXTURES / "annotations" / "fixture_scenes.csv"


def evaluate(sceneeval_bin, scenes, out):
    """`sceneeval evaluate` with the full plan (no VLM: matching by labels, ATR not judged)."""
    subprocess.run(
        [str(sceneeval_bin), "evaluate", str(scenes), "--assets", f"fixture={FIXTURES / 'assets'}",
         "--out", str(out), "--annotations", str(ANNOTATIONS), "--plan", "full", "--no-progress"],
        check=True, capture_output=True,
    )
    return out


def files(folder):
    """Every file below `folder` but the lock, by its path inside it."""
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file() and p.name != ".sceneeval.lock"
    }


def test_ensemble_writes_what_the_cli_writes(sceneeval_bin, tmp_path):
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    for name in SCENES:
        shutil.copy(FIXTURES / "scenes" / name, scenes / name)
    runs = [evaluate(sceneeval_bin, scenes, tmp_path / name) for name in ["judge_a", "judge_b"]]
    cli_out, py_out = tmp_path / "cli", tmp_path / "py"
    subprocess.run(
        [str(sceneeval_bin), "ensemble", *map(str, runs), "--out", str(cli_out), "--annotations", str(ANNOTATIONS)],
        check=True, capture_output=True,
    )
    done = sceneeval.ensemble([str(r) for r in runs], py_out, annotations=ANNOTATIONS)

    # The same folder, byte for byte: plan.json with the sources, each eval.json, the first
    # run's matching.json, the summaries.
    ours, theirs = files(py_out), files(cli_out)
    assert sorted(ours) == sorted(theirs)
    for name in theirs:
        assert ours[name] == theirs[name], name
    assert "plan.json" in ours and "summary.csv" in ours
    for name in SCENES:
        stem = name[:-5]
        assert f"{stem}/eval.json" in ours
        assert ours[f"{stem}/matching.json"] == (runs[0] / stem / "matching.json").read_bytes()
    # What the command prints: the runs, the scenes, no ties (two equal judges), no geometry
    # difference; the summary as evaluate returns it, per difficulty with the annotations.
    assert done["runs"] == ["judge_a", "judge_b"]
    assert (done["scenes"], done["ties"], done["differences"]) == (3, 0, [])
    assert done["summary"]["groups"][0]["group"] == "all"
    assert len(done["summary"]["groups"]) > 1


def test_bad_runs_raise(sceneeval_bin, tmp_path):
    with pytest.raises(ValueError, match=r"^runs: an ensemble combines at least two runs; 1 given"):
        sceneeval.ensemble([tmp_path / "a"], tmp_path / "out")
    with pytest.raises(sceneeval.SceneEvalError, match="plan.json|cannot read"):
        sceneeval.ensemble([tmp_path / "a", tmp_path / "b"], tmp_path / "out")
