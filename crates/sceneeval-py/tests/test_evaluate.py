"""sceneeval.evaluate writes the same files as `sceneeval evaluate` on fixture scenes."""

import json
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


def test_plans_as_the_cli_reads_them(scenes_dir, tmp_path):
    assets = {"fixture": FIXTURES / "assets"}
    plan = tmp_path / "plan.json"
    plan.write_text('{"preset": "reference", "metrics": ["collision", "out_of_bounds"]}')
    run = sceneeval.evaluate(scenes_dir, assets=assets, out=tmp_path / "a", plan=str(plan))
    assert run["failed"] == 0 and run["note"] is None
    assert "Preset: `reference`" in (tmp_path / "a" / "summary.md").read_text()
    # preset= replaces the file's preset, as --preset does.
    sceneeval.evaluate(scenes_dir, assets=assets, out=tmp_path / "b", plan=str(plan), preset="default")
    assert "Preset: `default`" in (tmp_path / "b" / "summary.md").read_text()
    # A metric list, with a preset; and metrics= overriding the plan's list.
    run = sceneeval.evaluate(scenes_dir, assets=assets, out=tmp_path / "c", plan="collision, support", preset="reference")
    record = json.loads((tmp_path / "c" / "scene_0" / "eval.json").read_text())
    assert record["report"]["metrics"] == ["collision", "support"]
    run = sceneeval.evaluate(scenes_dir, assets=assets, out=tmp_path / "d", plan="geometry", metrics=["navigability"])
    record = json.loads((tmp_path / "d" / "scene_0" / "eval.json").read_text())
    assert record["report"]["metrics"] == ["navigability"]
    # A preset name as the plan (the spelling of earlier versions) still works, as that preset
    # with the default plan, and warns that the preset is its own keyword.
    with pytest.warns(DeprecationWarning, match=r'plan="reference" is a preset name: pass preset="reference"'):
        run = sceneeval.evaluate(scenes_dir, assets=assets, out=tmp_path / "f", plan="reference")
    assert "Preset: `reference`" in (tmp_path / "f" / "summary.md").read_text()
    record = json.loads((tmp_path / "f" / "scene_0" / "eval.json").read_text())
    assert record["report"]["metrics"] == ["collision", "support", "navigability", "accessibility", "out_of_bounds", "opening_clearance"]
    with pytest.raises(ValueError, match=r'plan="reference" names a preset, and preset="default" another'):
        sceneeval.evaluate(scenes_dir, assets=assets, out=tmp_path / "g", plan="reference", preset="default")
    with pytest.raises(ValueError, match=r'^plan: "refrence" is not geometry, full, a plan file or a metric list: '
                                         r'unknown metric "refrence"'):
        sceneeval.evaluate(scenes_dir, assets={}, out=tmp_path / "e", plan="refrence")
    with pytest.raises(ValueError, match=r"unknown preset \"refrence\""):
        sceneeval.evaluate(scenes_dir, assets={}, out=tmp_path / "e", preset="refrence")
    with pytest.raises(ValueError, match=r"unknown metric"):
        sceneeval.evaluate(scenes_dir, assets={}, out=tmp_path / "e", metrics=["colision"])
    # The text-fidelity metrics need annotations, as with the CLI.
    with pytest.raises(ValueError, match=r"^annotations: is needed: the plan runs text-fidelity metrics \(cnt, atr, oor, oar\)"):
        sceneeval.evaluate(scenes_dir, assets={}, out=tmp_path / "e", plan="full")


def test_the_full_plan_runs_without_a_vlm_as_the_cli_does(sceneeval_bin, scenes_dir, tmp_path):
    annotations = FIXTURES / "annotations" / "fixture_scenes.csv"
    cli_out, py_out = tmp_path / "cli", tmp_path / "py"
    done = subprocess.run(
        [str(sceneeval_bin), "evaluate", str(scenes_dir), "--assets", f"fixture={FIXTURES / 'assets'}",
         "--out", str(cli_out), "--annotations", str(annotations), "--plan", "full", "--preset", "reference",
         "--no-progress"],
        check=True, capture_output=True, text=True,
    )
    with pytest.warns(UserWarning, match=r"no VLM configured .*: fidelity runs with labels matching and the lexicon relation mapping \(matching by labels, relations mapped by the lexicon instead of the VLM\); ATR is not judged\."):
        run = sceneeval.evaluate(scenes_dir, assets={"fixture": FIXTURES / "assets"}, out=py_out,
                                 annotations=annotations, plan="full", preset="reference")
    cli_note = next(line for line in done.stderr.splitlines() if line.startswith("note: no VLM configured"))
    assert cli_note.split("): ", 1)[1] == run["note"].split("): ", 1)[1]
    assert run["failed"] == 0
    for name in SCENES:
        stem = name[:-5]
        assert (py_out / stem / "eval.json").read_bytes() == (cli_out / stem / "eval.json").read_bytes(), stem
    assert (py_out / "summary.csv").read_text() == (cli_out / "summary.csv").read_text()
    assert "CNT" in (py_out / "summary.csv").read_text().splitlines()[0]


def test_failures_are_recorded_and_unusable_input_raises(scenes_dir, tmp_path):
    # Without the asset folder every scene fails to load; the run records it and goes on.
    run = sceneeval.evaluate(scenes_dir, assets=None, out=tmp_path / "out")
    assert run["failed"] == 3 and len(run["failures"]) == 3
    assert "fixture." in run["failures"][0]["error"] + " ".join(run["failures"][0]["causes"])
    with pytest.raises(sceneeval.SceneEvalError, match="no scene_<ID>.json files"):
        sceneeval.evaluate(tmp_path / "out", assets=None, out=tmp_path / "o2")
    with pytest.raises(sceneeval.SceneEvalError):
        sceneeval.evaluate(tmp_path / "missing", assets=None, out=tmp_path / "o3")


def test_matching_relation_mapping_and_time_budget_as_the_cli(sceneeval_bin, scenes_dir, tmp_path):
    annotations = FIXTURES / "annotations" / "fixture_scenes.csv"
    assets = {"fixture": FIXTURES / "assets"}
    # A reference-shaped matching folder for scene 1 that calls the chair a sofa: CNT sees two
    # sofas (eq,1,sofa fails) and no chair (eq,1,chair fails). Scenes 0 and 3 have no file.
    scene1 = sceneeval.load_scene(FIXTURES / "scenes" / "scene_1.json", assets=assets)
    per_category = {}
    for o in scene1.objects:
        category = o["category"].replace(" ", "_")
        per_category.setdefault(category, {})[o["id"]] = ""
    per_category["sofa"]["idx8_fixture.chair"] = per_category.pop("chair")["idx8_fixture.chair"]
    per_category["chair"] = {}
    matching = tmp_path / "matching"
    (matching / "scene_1").mkdir(parents=True)
    (matching / "scene_1" / "obj_matching_result.json").write_text(json.dumps(
        {"per_category": per_category, "not_matched_objs": {}, "actual_categories": {}}))
    cli_out, py_out = tmp_path / "cli", tmp_path / "py"
    subprocess.run(
        [str(sceneeval_bin), "evaluate", str(scenes_dir), "--assets", f"fixture={FIXTURES / 'assets'}",
         "--out", str(cli_out), "--annotations", str(annotations), "--plan", "full", "--matching", str(matching),
         "--relation-mapping", "lexicon", "--no-progress"],
        capture_output=True, text=True,
    )
    with pytest.warns(UserWarning, match=r"fidelity runs with matching from .*matching and the lexicon relation mapping; ATR is not judged\.$"):
        run = sceneeval.evaluate(scenes_dir, assets=assets, out=py_out, annotations=annotations, plan="full",
                                 matching=matching, relation_mapping="lexicon")
    for name in SCENES:
        stem = name[:-5]
        assert (py_out / stem / "eval.json").read_bytes() == (cli_out / stem / "eval.json").read_bytes(), stem
    record = json.loads((py_out / "scene_1" / "eval.json").read_text())
    assert record["status"] == "ok"
    assert record["report"]["fidelity"]["cnt"]["score"] == pytest.approx(8 / 10)
    # Scenes without a matching file keep their geometry metrics; their fidelity metrics are
    # listed as not computed, naming the file (status partial).
    assert (run["failed"], run["partial"]) == (0, 2)
    assert {m["metric"] for m in run["incomplete"]} == {"cnt", "atr", "oor", "oar"}
    assert all(not m["vlm"] for m in run["incomplete"])
    assert all("obj_matching_result.json" in m["error"] + " ".join(m["causes"]) for m in run["incomplete"])
    with pytest.raises(ValueError, match=r'relation_mapping: "vlm2": expected vlm or lexicon'):
        sceneeval.evaluate(scenes_dir, assets=assets, out=tmp_path / "e", annotations=annotations, plan="full",
                           relation_mapping="vlm2")

    # A scene over its time budget is recorded as failed; the run goes on.
    run = sceneeval.evaluate(scenes_dir, assets=assets, out=tmp_path / "budget", time_budget_s=1e-9)
    assert run["failed"] == 3
    assert "time budget" in run["failures"][0]["error"]
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match=r"^time_budget_s: .* is not a number of seconds \(0 for no budget\)"):
            sceneeval.evaluate(scenes_dir, assets=assets, out=tmp_path / "e", time_budget_s=bad)
