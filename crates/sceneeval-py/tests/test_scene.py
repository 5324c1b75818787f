"""Scenes from boxes and from sceneState files: inspection as plain values, plausibility as in
eval.json, relations by object id, and loading errors that name the file and the place."""

import json
import shutil

import numpy as np
import pytest

import sceneeval
from conftest import FIXTURES

ROOM = {
    "floor": [[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]],
    "openings": [{"kind": "door", "wall": 0, "along": [1.0, 1.9], "height": [0.0, 2.1]}],
}


def two_tables(dx):
    # Two 1 x 1 x 0.8 m tables standing on the floor, dx apart centre to centre.
    return np.array([[1.0, 2.0, 0.4, 0.5, 0.5, 0.4, 0.0], [1.0 + dx, 2.0, 0.4, 0.5, 0.5, 0.4, 0.0]])


def test_a_scene_from_boxes_inspects_as_plain_values():
    scene = sceneeval.Scene.from_boxes(two_tables(2.0), ROOM, categories=["table", "desk"], ids=["t", "d"], id="scene_7")
    assert len(scene) == 2 and scene.id == "scene_7"
    assert repr(scene) == 'Scene(id="scene_7", objects=2, rooms=1)'
    t = scene.objects[0]
    assert (t["id"], t["category"], t["is_box"], t["index"]) == ("t", "table", True, 0)
    assert t["center"] == [1.0, 2.0, 0.4] and t["size"] == [1.0, 1.0, 0.8] and t["yaw"] == 0.0
    room = scene.rooms[0]
    assert room["floor_area"] == pytest.approx(20.0)
    assert len(room["walls"]) == 4
    assert room["walls"][0]["openings"][0]["kind"] == "door"
    assert room["walls"][0]["length"] == pytest.approx(4.0)
    assert scene.info()["objects"] == scene.objects
    assert np.array_equal(scene.boxes(), two_tables(2.0))
    json.dumps(scene.info())  # plain values only


def test_plausibility_reports_collisions_with_per_object_evidence():
    apart = sceneeval.Scene.from_boxes(two_tables(2.0), ROOM, categories=["table", "table"])
    report = apart.plausibility()
    assert report["schema"] == "sceneeval.scene-report/1"
    assert report["summary"]["col_ob"] == 0.0 and report["summary"]["col_sc"] is False
    assert report["summary"]["oob"] == 0.0
    # 0.5 m overlap: both tables collide, COL_ob = 2/2.
    overlapping = sceneeval.Scene.from_boxes(two_tables(0.5), ROOM, categories=["table", "table"])
    report = overlapping.plausibility(metrics=["collision"])
    assert report["metrics"] == ["collision"]
    assert report["summary"]["col_ob"] == 1.0 and report["summary"]["col_sc"] is True
    assert report["collision"] is not None and report["navigability"] is None
    evidence = json.dumps(report["collision"])
    assert "box_0" in evidence and "box_1" in evidence
    assert overlapping.plausibility(plan="reference")["summary"]["col_sc"] is True
    with pytest.raises(ValueError, match="unknown metric"):
        overlapping.plausibility(metrics=["colision"])
    with pytest.raises(ValueError, match="not a preset name"):
        overlapping.plausibility(plan="refrence")


def test_relations_by_object_id_match_the_box_form():
    boxes = two_tables(1.3)
    scene = sceneeval.Scene.from_boxes(boxes, ROOM)
    for name in ["next_to", "near", "side_of(right)", "face_to", "on_top"]:
        assert scene.relation(name, "box_0", "box_1") == sceneeval.relation(name, tuple(boxes[0]), tuple(boxes[1]))
    assert scene.relation("inside_room", "box_0") == sceneeval.relation("inside_room", tuple(boxes[0]), room=ROOM)
    with pytest.raises(ValueError, match='no object with id "nope"'):
        scene.relation("near", "nope", "box_1")


def test_bad_scene_input_raises_value_error():
    with pytest.raises(ValueError, match=r"boxes\[1\]\.half_size is not finite"):
        bad = two_tables(2.0)
        bad[1, 4] = np.nan
        sceneeval.Scene.from_boxes(bad, ROOM)
    with pytest.raises(ValueError, match="categories has 1 entries, boxes has 2 rows"):
        sceneeval.Scene.from_boxes(two_tables(2.0), ROOM, categories=["table"])
    with pytest.raises(ValueError, match=r"room.openings\[0\].kind \"hatch\""):
        sceneeval.Scene.from_boxes(two_tables(2.0), {**ROOM, "openings": [{**ROOM["openings"][0], "kind": "hatch"}]})


def test_a_fixture_scene_loads_with_its_assets():
    scene = sceneeval.load_scene(FIXTURES / "scenes" / "scene_1.json", {"fixture": FIXTURES / "assets"})
    assert scene.id == "scene_1"
    expected = json.loads((FIXTURES / "expected.json").read_text())
    mine = next(s for s in expected["scenes"] if s["file"].endswith("scene_1.json"))
    assert [o["id"] for o in scene.objects] == [o["id"] for o in mine["objects"]]
    assert not any(o["is_box"] for o in scene.objects)
    assert [r["id"] for r in scene.rooms] == [r["id"] for r in mine["rooms"]]


def test_loading_errors_name_the_file_and_the_place(tmp_path):
    with pytest.raises(sceneeval.SceneEvalError, match="missing.json"):
        sceneeval.load_scene(tmp_path / "missing.json")
    broken = tmp_path / "scene_0.json"
    broken.write_text('{"format": "sceneState", "scene": {"object": [ }')
    with pytest.raises(sceneeval.SceneEvalError, match="scene_0.json"):
        sceneeval.load_scene(broken)
    # An asset that no folder provides: the error names the model id.
    src = json.loads((FIXTURES / "scenes" / "scene_1.json").read_text())
    shutil.copy(FIXTURES / "scenes" / "scene_1.json", tmp_path / "scene_1.json")
    with pytest.raises(sceneeval.SceneEvalError) as err:
        sceneeval.load_scene(tmp_path / "scene_1.json")
    model_id = src["scene"]["object"][0]["modelId"]
    assert model_id in str(err.value) and "/scene/object/0" in str(err.value)
    with pytest.raises(ValueError, match="is not a directory"):
        sceneeval.load_scene(tmp_path / "scene_1.json", {"fixture": tmp_path / "nowhere"})
