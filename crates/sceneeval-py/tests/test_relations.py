"""The predicates from Python agree with `sceneeval relate` (the Rust result) on the same boxes,
the batch form equals calls one by one, and bad arguments raise ValueError with clear
messages."""

import json
import subprocess
import threading

import numpy as np
import pytest

import sceneeval
from conftest import ROOM, random_boxes


def as_dict(row):
    return {"center": list(map(float, row[0:3])), "half_size": list(map(float, row[3:6])), "yaw": float(row[6])}


def test_there_are_23_relations_in_42_forms():
    assert len(sceneeval.OBJECT_OBJECT_RELATIONS) == 13
    assert len(sceneeval.OBJECT_ARCHITECTURE_RELATIONS) == 10
    # 13 object-object names expand to 24 forms (6 sides x 2, long/short), 10 architecture
    # names to 18 (wall/door/window for the 4 distance relations).
    assert len(sceneeval.relation_names()) == 24 + 18


def test_every_predicate_agrees_with_sceneeval_relate(sceneeval_bin, rng):
    boxes = random_boxes(rng, 24)
    queries, expected = [], []
    for name in sceneeval.relation_names():
        for k in range(4):
            t, a = boxes[2 * k], boxes[2 * k + 1]
            # Some pairs close together so that the scores are not all 0.
            if k % 2 == 0:
                t = t.copy()
                t[0:2] = a[0:2] + rng.uniform(-1.0, 1.0, 2)
            q = {"id": len(queries), "relation": name}
            if name == "surround":
                ts = [boxes[8 + i] for i in range(3 + k)]
                q.update(anchor=as_dict(a), targets=[as_dict(x) for x in ts])
                ours = sceneeval.relation(name, None, tuple(a), targets=[tuple(x) for x in ts])
            elif name in sceneeval.relation_names()[24:]:
                q.update(target=as_dict(t), room=ROOM)
                ours = sceneeval.relation(name, tuple(t), room=ROOM)
            else:
                q.update(target=as_dict(t), anchor=as_dict(a))
                ours = sceneeval.relation(name, tuple(t), tuple(a))
            queries.append(q)
            expected.append(ours)
    for reference in (False, True):
        args = [str(sceneeval_bin), "relate"] + (["--reference"] if reference else [])
        text = "\n".join(json.dumps(q) for q in queries) + "\n"
        done = subprocess.run(args, input=text, capture_output=True, text=True, check=True)
        answers = [json.loads(line) for line in done.stdout.splitlines()]
        assert len(answers) == len(queries)
        for q, answer in zip(queries, answers):
            assert "error" not in answer, answer
            if reference:
                ours = call_like(q, reference=True)
            else:
                ours = expected[q["id"]]
            # The same Rust code on the same numbers (JSON floats round-trip exactly).
            assert answer["score"] == ours, (q["relation"], answer, ours)
    # Not every score is 0 or 1: the comparison exercises the fall-offs too.
    assert any(0.0 < s < 1.0 for s in expected)
    assert any(s == 1.0 for s in expected)


def call_like(q, **kw):
    if "targets" in q:
        return sceneeval.relation(q["relation"], None, q["anchor"], targets=q["targets"], **kw)
    if "room" in q:
        return sceneeval.relation(q["relation"], q["target"], room=q["room"], **kw)
    return sceneeval.relation(q["relation"], q["target"], q["anchor"], **kw)


def test_dict_and_tuple_boxes_are_the_same_box():
    t, a = (0.3, 0.1, 0.5, 0.2, 0.3, 0.5, 0.4), (1.0, 0.0, 0.5, 0.5, 0.5, 0.5, -0.2)
    assert sceneeval.relation("near", t, a) == sceneeval.relation("near", as_dict(t), as_dict(a))
    # A yaw and the equivalent rotation matrix: the same box up to rounding.
    c, s = np.cos(0.4), np.sin(0.4)
    rotated = {"center": [0.3, 0.1, 0.5], "half_size": [0.2, 0.3, 0.5], "rotation": [[c, -s, 0], [s, c, 0], [0, 0, 1]]}
    assert sceneeval.relation("side_of", rotated, a, side="left") == pytest.approx(
        sceneeval.relation("side_of", t, a, side="left"), abs=1e-12
    )


def test_hand_computed_scores():
    table = (0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0)
    # A lamp resting on the table's top face (z = 1): all of it is above, on_top = 1.
    assert sceneeval.relation("on_top", (0.0, 0.0, 1.1, 0.1, 0.1, 0.1, 0.0), table) == 1.0
    # Sunk halfway into the table: the top-face plane (ours, moved out by the 1e-6 m tolerance)
    # sees (0.1 + 1e-6) / 0.2 = 0.500005 of it above; the reference's centre plane (z = 0.5)
    # sees all of it above, 1.
    sunk = (0.0, 0.0, 1.0, 0.1, 0.1, 0.1, 0.0)
    assert sceneeval.relation("on_top", sunk, table) == pytest.approx(0.500005, abs=1e-12)
    assert sceneeval.relation("on_top", sunk, table, reference=True) == 1.0
    assert sceneeval.relation("on_top", sunk, table, on_top_plane="centre_plane") == 1.0
    # Unit cubes 2.25 m apart centre to centre: a 1.25 m gap, in near's [0.5, 1.5] m band.
    a, b = (0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0), (2.25, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0)
    assert sceneeval.relation("near", a, b) == 1.0
    # With the band moved to [0, 1] m (sigma 0.25): 0.25 m beyond it, exp(-0.25^2 / (2 * 0.25^2)).
    assert sceneeval.relation("near", a, b, near=(0.0, 1.0, 0.25)) == pytest.approx(np.exp(-0.5), abs=1e-15)
    assert sceneeval.relation("near", a, b, near={"min_m": 0.0, "max_m": 1.0, "sigma_m": 0.25}) == pytest.approx(
        np.exp(-0.5), abs=1e-15
    )
    assert sceneeval.relation_params(reference=True)["on_top_plane"] == "centre_plane"
    assert sceneeval.relation_params()["far"]["max_m"] is None  # unbounded


def test_names_before_the_unit_suffix_rule_read_with_a_deprecation_warning():
    # A plan file's old names (sceneeval_eval::RENAMED_KEYS) read as the new ones, as in a plan.
    a, b = (0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0), (2.25, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0)
    with pytest.warns(DeprecationWarning) as warned:
        old = sceneeval.relation("near", a, b, near={"min": 0.0, "max": 1.0, "sigma": 0.25})
    assert [str(w.message) for w in warned] == [
        f"near.{n} is deprecated: write near.{n}_m (the unit-suffix rule)" for n in ("min", "max", "sigma")
    ]
    assert old == pytest.approx(np.exp(-0.5), abs=1e-15)
    with pytest.warns(DeprecationWarning, match=r"^middle_of_sigma is deprecated: write middle_of_sigma_m"):
        params = sceneeval.relation_params(middle_of_sigma=0.5)
    assert params["middle_of_sigma_m"] == 0.5 and "middle_of_sigma" not in params
    # Both names at once: an error naming both.
    with pytest.raises(ValueError, match=r"`middle_of_sigma` and as `middle_of_sigma_m`"):
        sceneeval.relation_params(middle_of_sigma=0.5, middle_of_sigma_m=0.5)


def test_batch_equals_one_by_one(rng):
    targets, anchors = random_boxes(rng, 50), random_boxes(rng, 50)
    anchors[:25, 0:2] = targets[:25, 0:2] + rng.uniform(-1, 1, (25, 2))
    for name in sceneeval.relation_names():
        if name == "surround":
            continue
        if name in sceneeval.relation_names()[24:]:
            got = sceneeval.relation_batch(name, targets, room=ROOM)
            want = [sceneeval.relation(name, tuple(t), room=ROOM) for t in targets]
        else:
            got = sceneeval.relation_batch(name, targets, anchors)
            want = [sceneeval.relation(name, tuple(t), tuple(a)) for t, a in zip(targets, anchors)]
        assert got.dtype == np.float64 and got.shape == (50,)
        assert got.tolist() == want, name
    # One anchor for every target, a non-contiguous view, and the reference's parameters.
    view = targets[::2]
    got = sceneeval.relation_batch("side_of", view, anchors[:1], side="front", reference=True)
    want = [sceneeval.relation("side_of", tuple(t), tuple(anchors[0]), side="front", reference=True) for t in view]
    assert got.tolist() == want
    assert sceneeval.relation_batch("near", np.empty((0, 7)), np.empty((0, 7))).shape == (0,)


@pytest.mark.parametrize("grad", [False, True])
def test_batch_from_several_threads_gives_the_same_scores(rng, grad):
    # The GIL is released while Rust computes (scores, and scores with gradients): several
    # Python threads may score at once.
    targets, anchors = random_boxes(rng, 2000), random_boxes(rng, 2000)
    want = sceneeval.relation_batch("next_to", targets, anchors, grad=grad)
    results = [None] * 4

    def work(i):
        results[i] = sceneeval.relation_batch("next_to", targets, anchors, grad=grad)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in results:
        assert all(np.array_equal(a, b) for a, b in zip(r, want)) if grad else np.array_equal(r, want)


BOX = np.zeros((3, 7)) + [0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0]


@pytest.mark.parametrize(
    "targets, anchors, message",
    [
        (BOX[:, :6], BOX, r"targets must be a numpy float64 array of shape \(N, 7\), got shape \(3, 6\)"),
        (BOX[0], BOX, r"got shape \(7\)"),
        (BOX, BOX[:, :, None], r"anchors must be .* got shape \(3, 7, 1\)"),
        (BOX.astype(np.float32), BOX, r"got dtype float32 \(convert with targets.astype\(numpy.float64\)\)"),
        (BOX.astype(np.int64), BOX, r"got dtype int64"),
        (BOX.tolist(), BOX, r"targets must be .* got a list"),
        (BOX, BOX[:2], r"anchors has 2 rows: expected 3 \(one per target\) or 1"),
    ],
)
def test_bad_arrays_raise_value_error(targets, anchors, message):
    with pytest.raises(ValueError, match=message):
        sceneeval.relation_batch("near", targets, anchors)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
@pytest.mark.parametrize("column, field", [(1, "center"), (4, "half_size"), (6, "yaw")])
def test_non_finite_numbers_name_the_row_and_field(bad, column, field):
    targets = BOX.copy()
    targets[2, column] = bad
    with pytest.raises(ValueError, match=rf"^targets\[2\]\.{field} is not finite$"):
        sceneeval.relation_batch("near", targets, BOX)
    with pytest.raises(ValueError, match=rf"target\.{field} is not finite"):
        sceneeval.relation("near", tuple(targets[2]), tuple(BOX[0]))


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: sceneeval.relation("beside", BOX[0], BOX[1]), r'unknown relation "beside": expected one of inside_of'),
        (lambda: sceneeval.relation("side_of", BOX[0], BOX[1]), r"relation side_of needs a side"),
        (lambda: sceneeval.relation("side_of", BOX[0], BOX[1], side="up"), r"side_of.*\"up\""),
        (lambda: sceneeval.relation("near", BOX[0], BOX[1], side="left"), r"its argument is an architecture element"),
        (lambda: sceneeval.relation("near", BOX[0]), r'relation near needs "anchor"'),
        (lambda: sceneeval.relation("near", BOX[0], room=ROOM), r'"arch" \(wall, door or window\)'),
        (lambda: sceneeval.relation("on_wall", BOX[0], BOX[1], room=ROOM), r'does not use "anchor"'),
        (lambda: sceneeval.relation("near", (1, 2, 3), BOX[1]), r"target must be a sequence of 7 numbers"),
        (lambda: sceneeval.relation("near", {"center": [0, 0, 0]}, BOX[1]), r"target: missing field `half_size`"),
        (lambda: sceneeval.relation("inside_room", BOX[0], room={"floor": [[0, 0], [1, 0]]}), r"^room: "),
        (lambda: sceneeval.relation("near", BOX[0], BOX[1], bogus=1.0), r'unknown parameter "bogus"'),
        (lambda: sceneeval.relation("near", BOX[0], BOX[1], middle_of_sigma_m=-1.0), r"middle_of_sigma_m"),
        (lambda: sceneeval.relation_batch("surround", BOX, BOX), r"targets must be a numpy float64 array of shape \(N, K, 7\) for surround"),
        (lambda: sceneeval.relation_batch("surround", BOX[None], BOX, room=ROOM), r"give anchors, not room"),
        (lambda: sceneeval.relation_batch("on_wall", BOX), r"needs room"),
        (lambda: sceneeval.relation_batch("near", BOX), r"needs anchors"),
        (lambda: sceneeval.relation_batch("near", BOX, BOX, room=ROOM), r"give anchors, not room"),
    ],
)
def test_bad_arguments_raise_value_error(call, message):
    with pytest.raises(ValueError, match=message):
        call()


BED = (2.0, -3.0, 0.3, 0.8, 1.0, 0.3, 0.0)


@pytest.mark.parametrize(
    "call, message",
    [
        # Issue 29: a room in the anchor's place said "anchor: unknown field `floor`".
        (
            lambda: sceneeval.relation("against_wall", BED, ROOM),
            r'^anchor is a room \(a dict with "floor"\), not a box: give a room as room=, as in '
            r'relation\("against_wall", target, room=room\)$',
        ),
        (lambda: sceneeval.relation("inside_room", ROOM, room=ROOM), r'^target is a room \(a dict with "floor"\)'),
        (lambda: sceneeval.relation("against_wall", BED, room=BED), r"^room is a box \(7 numbers\), not a room: "),
        (
            lambda: sceneeval.relation("against_wall", BED, room=as_dict(BED)),
            r'^room is a box \(a dict with "center"\), not a room: a room is a dict with the keys floor',
        ),
        (
            lambda: sceneeval.relation("surround", [BED, BED, BED], BED),
            r"^target is a list of boxes, not a box: surround takes its boxes as targets=\[\.\.\.\]",
        ),
        # Keys at fault are named with the object, as `relate` names them.
        (
            lambda: sceneeval.relation("near", {"center": [0, 0, 0], "half_size": [1, 1]}, BED),
            r"^target\.half_size: invalid length 2, expected an array of length 3$",
        ),
        (
            lambda: sceneeval.relation("near", BED, {"center": [0, 0, "x"], "half_size": [1, 1, 1]}),
            r"^anchor\.center\[2\]: invalid type",
        ),
        (
            lambda: sceneeval.relation("inside_room", BED, room={"floor": [[0, 0], [4, 0, 1], [4, 5]]}),
            r"^room\.floor\[1\]: invalid length 3",
        ),
    ],
)
def test_misplaced_operands_and_bad_keys_are_named(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_the_right_places_answer():
    # The bed (y from -4 to -2) against wall 0 (y = -4) of conftest's room, once given as room=.
    assert sceneeval.relation("against_wall", BED, room=ROOM) > 0.5


def test_a_bad_row_beyond_the_first_chunk_is_named_by_its_index():
    targets = np.tile(BOX[0], (3000, 1))
    targets[2500, 0] = np.nan
    with pytest.raises(ValueError, match=r"^targets\[2500\]\.center is not finite$"):
        sceneeval.relation_batch("on_wall", targets, room={"floor": [[0, 0], [4, 0], [4, 3], [0, 3]]})


def test_surround_batch_equals_one_group_at_a_time(rng):
    # 40 groups of 5 chairs around 40 tables; half of them evenly around (the scores reach 1).
    n, k = 40, 5
    anchors = random_boxes(rng, n)
    targets = np.empty((n, k, 7))
    for i in range(n):
        targets[i] = random_boxes(rng, k)
        if i % 2 == 0:
            angles = 2 * np.pi * np.arange(k) / k + rng.uniform(-0.2, 0.2, k)
            targets[i, :, 0] = anchors[i, 0] + 1.2 * np.cos(angles)
            targets[i, :, 1] = anchors[i, 1] + 1.2 * np.sin(angles)
    for reference in (False, True):
        got = sceneeval.relation_batch("surround", targets, anchors, reference=reference)
        want = [
            sceneeval.relation("surround", None, tuple(a), targets=[tuple(t) for t in group], reference=reference)
            for group, a in zip(targets, anchors)
        ]
        assert got.dtype == np.float64 and got.shape == (n,)
        assert got.tolist() == want
    assert max(want) > 0.9 and min(want) < 0.6
    # One anchor for every group, and a non-contiguous view of the groups.
    view = targets[::3, ::2]
    got = sceneeval.relation_batch("surround", view, anchors[:1])
    want = [sceneeval.relation("surround", None, tuple(anchors[0]), targets=[tuple(t) for t in g]) for g in view]
    assert got.tolist() == want
    # Fewer than three targets score 0; no group at all gives no score.
    assert sceneeval.relation_batch("surround", targets[:, :2], anchors).tolist() == [0.0] * n
    assert sceneeval.relation_batch("surround", np.empty((0, 4, 7)), np.empty((0, 7))).shape == (0,)


def test_surround_batch_hand_computed():
    # Four chairs 1 m from the table at 90-degree gaps: every deviation 0, score 1. Four chairs
    # at one place: equal distances (distance terms 1, weight 0.5), every gap 0 against the
    # ideal 90 degrees (angle terms 0, weight 0.5): 0.5.
    chair = lambda x, y: [x, y, 0.4, 0.25, 0.25, 0.4, 0.0]  # noqa: E731
    around = [chair(1, 0), chair(0, 1), chair(-1, 0), chair(0, -1)]
    together = [chair(1, 0)] * 4
    table = np.array([[0.0, 0.0, 0.4, 0.5, 0.5, 0.4, 0.0]])
    scores = sceneeval.relation_batch("surround", np.array([around, together]), table)
    assert scores.tolist() == [1.0, 0.5]


@pytest.mark.parametrize(
    "targets, anchors, message",
    [
        (np.zeros((2, 4, 6)), np.zeros((2, 7)), r"targets must be .* shape \(N, K, 7\) for surround .* got shape \(2, 4, 6\)"),
        (np.zeros((2, 4, 7, 1)), np.zeros((2, 7)), r"got shape \(2, 4, 7, 1\)"),
        (np.zeros((2, 4, 7), dtype=np.float32), np.zeros((2, 7)), r"got dtype float32"),
        (np.zeros((2, 4, 7)), np.zeros((3, 7)), r"anchors has 3 rows: expected 2 \(one per group of targets\) or 1"),
        (np.zeros((2, 4, 7)), np.zeros((2, 4, 7)), r"anchors must be a numpy float64 array of shape \(N, 7\), got shape \(2, 4, 7\)"),
        (np.zeros((2, 4, 7)), None, r"relation surround needs anchors"),
    ],
)
def test_bad_surround_arrays_raise_value_error(targets, anchors, message):
    with pytest.raises(ValueError, match=message):
        sceneeval.relation_batch("surround", targets, anchors)


def test_bad_surround_rows_name_the_group_and_the_target():
    targets = np.tile(BOX[0], (3, 4, 1))
    targets[2, 1, 4] = np.nan
    with pytest.raises(ValueError, match=r"^targets\[2\]\[1\]\.half_size is not finite$"):
        sceneeval.relation_batch("surround", targets, BOX)
    anchors = BOX.copy()
    anchors[1, 6] = np.inf
    with pytest.raises(ValueError, match=r"^anchors\[1\]\.yaw is not finite$"):
        sceneeval.relation_batch("surround", np.tile(BOX[0], (3, 4, 1)), anchors)
    # The reference surround compares every pair: it refuses more than its limit of targets.
    many = np.tile(BOX[0], (1, 2049, 1))
    with pytest.raises(ValueError, match=r"accepts at most"):
        sceneeval.relation_batch("surround", many, BOX[:1], reference=True)


def test_rooms_are_found_by_their_content():
    # A 1 x 1 x 0.8 m box centred on x = 2 in a room 4 m wide is inside it (1); in a room
    # 2 m wide it straddles the wall x = 2 by half its width (0.5). The same dict object edited
    # between calls is a new room, not the one prepared for its old content.
    box = (2.0, 1.0, 0.4, 0.5, 0.5, 0.4, 0.0)
    room = {"floor": [[0, 0], [4, 0], [4, 3], [0, 3]]}
    assert sceneeval.relation("inside_room", box, room=room) == 1.0
    room["floor"] = [[0, 0], [2, 0], [2, 3], [0, 3]]
    assert sceneeval.relation("inside_room", box, room=room) == pytest.approx(0.5, abs=1e-5)
    room["floor"] = [[0, 0], [4, 0], [4, 3], [0, 3]]
    assert sceneeval.relation("inside_room", box, room=room) == 1.0
    batch = sceneeval.relation_batch("inside_room", np.array([box]), room={"floor": [[0, 0], [2, 0], [2, 3], [0, 3]]})
    assert batch[0] == pytest.approx(0.5, abs=1e-5)
    # More distinct rooms than are kept: each still scores as its own room.
    for i in range(70):
        width = 1.5 + 0.01 * i
        score = sceneeval.relation("inside_room", box, room={"floor": [[0, 0], [width, 0], [width, 3], [0, 3]]})
        # The box spans x in [1.5, 2.5]: the part left of x = width is inside.
        assert score == pytest.approx(width - 1.5, abs=1e-5), width
