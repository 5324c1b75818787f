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
    scene = sceneeval.Scene.from_boxes(two_tables(2.0), ROOM, categories=["table", "desk"], ids=["t", "d"], name="scene_7")
    assert len(scene) == 2 and scene.name == "scene_7"
    assert repr(scene) == 'Scene(name="scene_7", objects=2, rooms=1)'
    # The old spellings of the name warn and still work.
    with pytest.warns(DeprecationWarning, match=r"^Scene.id is deprecated: use Scene.name"):
        assert scene.id == "scene_7"
    with pytest.warns(DeprecationWarning, match=r"from_boxes\(id=...\) is deprecated: pass name="):
        assert sceneeval.Scene.from_boxes(two_tables(2.0), ROOM, id="scene_8").name == "scene_8"
    with pytest.raises(ValueError, match="give the scene's name once"):
        sceneeval.Scene.from_boxes(two_tables(2.0), ROOM, id="a", name="b")
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
    assert report["schema"] == "sceneeval.scene-report/2"
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
    assert overlapping.plausibility(preset="reference")["summary"]["col_sc"] is True
    # A plan as for evaluate: a metric list here.
    assert overlapping.plausibility(plan="collision,support")["metrics"] == ["collision", "support"]
    with pytest.raises(ValueError, match="unknown metric"):
        overlapping.plausibility(metrics=["colision"])
    with pytest.raises(ValueError, match=r'^plan: "refrence" is not geometry, full, a plan file or a metric list'):
        overlapping.plausibility(plan="refrence")
    with pytest.raises(ValueError, match=r"unknown preset"):
        overlapping.plausibility(preset="refrence")
    with pytest.raises(ValueError, match=r"runs text-fidelity metrics .* Scene.plausibility runs the geometry metrics only"):
        overlapping.plausibility(plan="full")


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
    assert scene.name == "scene_1"
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


def test_several_rooms_with_their_ids():
    rooms = [
        {"id": "bedroom", "floor": [[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]]},
        {"floor": [[4.0, 0.0], [7.0, 0.0], [7.0, 5.0], [4.0, 5.0]], "height": 2.5},
    ]
    # One table in each room.
    boxes = np.array([[1.0, 2.0, 0.4, 0.5, 0.5, 0.4, 0.0], [5.5, 2.0, 0.4, 0.5, 0.5, 0.4, 0.0]])
    scene = sceneeval.Scene.from_boxes(boxes, rooms=rooms)
    assert [r["id"] for r in scene.rooms] == ["bedroom", "room_1"]
    assert [r["floor_area"] for r in scene.rooms] == [pytest.approx(20.0), pytest.approx(15.0)]
    assert repr(scene) == "Scene(name=None, objects=2, rooms=2)"
    # Each table is in some room; in the other room alone it is not.
    assert scene.relation("inside_room", "box_1") == 1.0
    assert scene.relation("inside_room", "box_1", floors=["bedroom"]) == 0.0
    assert scene.relation("inside_room", "box_1", floors=["room_1"]) == 1.0
    # OOB is the share of objects out of bounds: none with both rooms, the second table
    # (1 of 2) with the bedroom only.
    assert scene.plausibility(metrics=["out_of_bounds"])["summary"]["oob"] == 0.0
    one = sceneeval.Scene.from_boxes(boxes, rooms=rooms[:1])
    assert one.plausibility(metrics=["out_of_bounds"])["summary"]["oob"] == 0.5
    # room= keeps working, with the id "room".
    assert [r["id"] for r in sceneeval.Scene.from_boxes(boxes, ROOM).rooms] == ["room"]


def test_bad_rooms_are_named_by_their_position():
    boxes = two_tables(2.0)
    with pytest.raises(ValueError, match=r"room \(one room\) or rooms \(a list of rooms\), not both"):
        sceneeval.Scene.from_boxes(boxes, ROOM, rooms=[ROOM])
    with pytest.raises(ValueError, match=r"^rooms\[1\]\.floor\[0\]\[0\] is not finite$"):
        sceneeval.Scene.from_boxes(boxes, rooms=[ROOM, {"floor": [[np.nan, 0.0], [1.0, 0.0], [1.0, 1.0]]}])
    with pytest.raises(ValueError, match=r"^rooms\[1\]: room: "):
        sceneeval.Scene.from_boxes(boxes, rooms=[ROOM, {"floor": [[0.0, 0.0], [1.0, 0.0]]}])
    with pytest.raises(ValueError, match=r"^rooms must be a list of room dicts$"):
        sceneeval.Scene.from_boxes(boxes, rooms=ROOM)
    with pytest.raises(ValueError, match=r"^rooms\[0\] must be a dict"):
        sceneeval.Scene.from_boxes(boxes, rooms=[[0, 1]])
    with pytest.raises(ValueError, match=r"^rooms\[0\]: unknown field `flor`"):
        sceneeval.Scene.from_boxes(boxes, rooms=[{"flor": []}])
    with pytest.raises(ValueError, match=r"rooms\[0\].id must be a string"):
        sceneeval.Scene.from_boxes(boxes, rooms=[{**ROOM, "id": 3}])
    with pytest.raises(ValueError, match=r'room id "a" is used twice'):
        sceneeval.Scene.from_boxes(boxes, rooms=[{**ROOM, "id": "a"}, {**ROOM, "id": "a"}])


def test_moved_objects_change_relations_and_plausibility():
    # Tables 1 m wide, 1.3 m apart centre to centre: a 0.3 m gap, next_to 1, no collision.
    scene = sceneeval.Scene.from_boxes(two_tables(1.3), ROOM)
    assert scene.relation("next_to", "box_0", "box_1") == 1.0
    assert scene.plausibility(metrics=["collision"])["summary"]["col_sc"] is False
    # Moved to x = 3.5: a 1.5 m gap, 1 m beyond next_to's [0, 0.5] m band (sigma 0.25 m):
    # exp(-1^2 / (2 * 0.25^2)) = exp(-8); inside near's [0.5, 1.5] m band.
    scene.set_pose("box_1", (3.5, 2.0, 0.4), 0.0)
    assert scene.boxes()[1].tolist() == [3.5, 2.0, 0.4, 0.5, 0.5, 0.4, 0.0]
    assert scene.relation("next_to", "box_0", "box_1") == pytest.approx(np.exp(-8.0), rel=1e-12)
    assert scene.relation("near", "box_0", "box_1") == 1.0
    # By index, onto the other table: a 0.5 m overlap, both collide (COL_ob = 2/2).
    scene.set_pose(1, np.array([1.5, 2.0, 0.4]), 0.0)
    report = scene.plausibility(metrics=["collision"])
    assert report["summary"]["col_ob"] == 1.0 and report["summary"]["col_sc"] is True
    # Out of the room (x = 10): 1 of 2 objects out of bounds.
    scene.set_pose("box_1", [10.0, 2.0, 0.4], 0.0)
    assert scene.plausibility(metrics=["out_of_bounds"])["summary"]["oob"] == 0.5
    assert scene.objects[1]["center"] == [10.0, 2.0, 0.4]
    # Turned a quarter: the table's front (local -y) now faces +x, away from box_0 at x = 1.
    scene.set_pose("box_1", [3.0, 2.0, 0.4], np.pi / 2)
    assert scene.boxes()[1][6] == pytest.approx(np.pi / 2, abs=1e-12)
    assert scene.relation("face_to", "box_1", "box_0") == 0.0
    scene.set_pose("box_1", [3.0, 2.0, 0.4], -np.pi / 2)
    # Facing -x, straight at box_0: score 1.
    assert scene.relation("face_to", "box_1", "box_0") == pytest.approx(1.0, abs=1e-9)


def test_all_objects_move_at_once_or_not_at_all():
    scene = sceneeval.Scene.from_boxes(two_tables(1.3), ROOM)
    b = scene.boxes()
    b[:, 0] += 0.1
    scene.set_boxes(b)
    assert np.allclose(scene.boxes(), b, atol=1e-15)
    assert scene.relation("next_to", "box_0", "box_1") == 1.0
    # Table 1 moved 1.2 m further: a 1.5 m gap again, next_to exp(-8).
    b[1, 0] += 1.2
    scene.set_boxes(b)
    assert scene.relation("next_to", "box_0", "box_1") == pytest.approx(np.exp(-8.0), rel=1e-9)
    before = scene.boxes()
    bad = before.copy()
    bad[0, 0] = 0.0
    bad[1, 4] = 0.7
    with pytest.raises(ValueError, match=r"boxes\[1\]: half extents .* objects cannot be resized"):
        scene.set_boxes(bad)
    bad = before.copy()
    bad[0, 0] = 0.0
    bad[1, 6] = np.nan
    with pytest.raises(ValueError, match=r"^boxes\[1\]\.yaw is not finite$"):
        scene.set_boxes(bad)
    with pytest.raises(ValueError, match="boxes has 1 rows, the scene has 2 objects"):
        scene.set_boxes(before[:1])
    with pytest.raises(ValueError, match=r"boxes must be a numpy float64 array of shape \(N, 7\)"):
        scene.set_boxes(before.tolist())
    assert np.array_equal(scene.boxes(), before), "nothing moved"


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda s: s.set_pose("nope", (0, 0, 0), 0.0), r'no object with id "nope" in the scene'),
        (lambda s: s.set_pose(2, (0, 0, 0), 0.0), r"no object at index 2: the scene has 2"),
        (lambda s: s.set_pose(-1, (0, 0, 0), 0.0), r"no object at index -1: the scene has 2"),
        (lambda s: s.set_pose(1.0, (0, 0, 0), 0.0), r"object must be an id \(str\) or an index \(int\)"),
        (lambda s: s.set_pose(0, (0, 0), 0.0), r"center must be a sequence of 3 numbers"),
        (lambda s: s.set_pose(0, (0, np.inf, 0), 0.0), r"^center is not finite$"),
        (lambda s: s.set_pose(0, (0, 0, 0), np.nan), r"^yaw is not finite$"),
    ],
)
def test_bad_moves_raise_value_error_and_move_nothing(call, message):
    scene = sceneeval.Scene.from_boxes(two_tables(1.3), ROOM)
    before = scene.boxes()
    with pytest.raises(ValueError, match=message):
        call(scene)
    assert np.array_equal(scene.boxes(), before)


def test_mesh_objects_move_by_their_box_centre():
    scene = sceneeval.load_scene(FIXTURES / "scenes" / "scene_1.json", {"fixture": FIXTURES / "assets"})
    row = scene.boxes()[0]
    target = row[:3] + [0.5, -0.25, 0.0]
    scene.set_pose(0, target, row[6] + 0.3)
    moved = scene.boxes()[0]
    assert np.allclose(moved[:3], target, atol=1e-12)
    assert np.allclose(moved[3:6], row[3:6], atol=1e-12)
    assert moved[6] == pytest.approx(row[6] + 0.3, abs=1e-12)
    # Moved back: where it was (the fixture's objects stand upright).
    scene.set_pose(scene.objects[0]["id"], row[:3], row[6])
    assert np.allclose(scene.boxes()[0], row, atol=1e-12)


def test_a_scene_is_shared_between_threads():
    # Moves from several threads while others compute: every result is one of the poses.
    import threading

    scene = sceneeval.Scene.from_boxes(two_tables(1.3), ROOM)
    seen = set()

    def move(i):
        for k in range(200):
            scene.set_pose("box_1", (2.3 if (i + k) % 2 else 3.5, 2.0, 0.4), 0.0)

    def score():
        for _ in range(200):
            seen.add(round(scene.relation("next_to", "box_0", "box_1"), 12))
            scene.plausibility(metrics=["collision"])

    threads = [threading.Thread(target=move, args=(i,)) for i in range(2)] + [threading.Thread(target=score) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert seen <= {1.0, round(np.exp(-8.0), 12)}


def test_stability_reports_the_fallen_crate_and_settle_lands_it():
    # A desk resting on the floor and a 0.4 m crate 5 cm above it; the crate falls 5 cm
    # (over the 1 cm limit): 1 of the 2 free objects is unstable.
    boxes = np.array([[1.0, 2.0, 0.4, 0.5, 0.5, 0.4, 0.0], [3.0, 2.0, 0.25, 0.2, 0.2, 0.2, 0.0]])
    scene = sceneeval.Scene.from_boxes(boxes, ROOM, categories=["desk", "box"], ids=["desk", "crate"])
    report = scene.stability()
    assert report["weld"] == "architectural"
    desk, crate = report["objects"]
    assert desk["stable"] and not desk["welded"] and desk["weld_reason"] is None
    assert not crate["stable"] and crate["displacement_m"] == pytest.approx(0.05, abs=5e-3)
    assert report["frac_unstable"] == 0.5
    assert np.array_equal(scene.boxes(), boxes), "stability() does not move the scene"
    settled, again = scene.settle(weld="none")
    assert again["weld"] == "none" and again["frac_unstable"] == 0.5
    # The crate's centre came down to 0.2 m; the desk stayed.
    assert settled.boxes()[1, 2] == pytest.approx(0.2, abs=1e-3)
    assert settled.boxes()[0, 2] == pytest.approx(0.4, abs=1e-3)
    assert settled.stability()["frac_unstable"] == 0.0
    json.dumps(report)  # plain values only


def test_stability_of_a_fixture_room_and_its_errors(tmp_path):
    scene = sceneeval.load_scene(FIXTURES / "scenes" / "scene_0.json", {"fixture": FIXTURES / "assets"})
    report = scene.stability()
    # The tidy bedroom: the painting (wall) and the ceiling lamp are welded, the rest stays.
    assert [o["weld_reason"] for o in report["objects"] if o["welded"]] == ["wall", "ceiling"]
    assert report["frac_unstable"] == 0.0
    with pytest.raises(ValueError, match="weld: unknown weld mode"):
        scene.stability(weld="glued")
    plan = tmp_path / "plan.json"
    plan.write_text('{"stability": {"duration_s": -1}}')
    with pytest.raises(ValueError, match="stability.duration_s"):
        scene.settle(plan=plan)
    roomless = sceneeval.Scene.from_boxes(np.array([[1.0, 1.0, 0.2, 0.2, 0.2, 0.2, 0.0]]), rooms=[])
    with pytest.raises(sceneeval.SceneEvalError, match="has no room"):
        roomless.stability()
