"""relation_batch(..., grad=True): the scores of grad=False bit for bit, derivatives that agree
with central finite differences of the scores for every relation, the shapes and tuples the
API promises, and the numpy part of the torch example (examples/python/gradient_layout.py).
(Gradients from several threads: test_relations.py.)"""

import sys

import numpy as np
import pytest

import sceneeval
from conftest import REPO, ROOM, random_boxes

STEP = 1e-6
ARCH = set(sceneeval.relation_names()[24:])


def pairs(rng, n):
    """n random target and anchor boxes; half of the targets moved next to their anchors so
    that the scores are not all 0."""
    targets, anchors = random_boxes(rng, n), random_boxes(rng, n)
    targets[: n // 2, 0:2] = anchors[: n // 2, 0:2] + rng.uniform(-1.2, 1.2, (n // 2, 2))
    targets[: n // 4, 2] = anchors[: n // 4, 2] + rng.uniform(-0.5, 0.8, n // 4)
    return targets, anchors


class Tally:
    """Per relation: derivatives compared, compared and not 0, and skipped near a kink."""

    def __init__(self):
        self.counts = {}

    def compare(self, name, analytic, score, x, index):
        """Compares analytic[i] (the derivative of score i with respect to x[index] of row i)
        with central differences of score(x moved); a derivative whose forward and backward
        differences, or whose central differences with steps STEP and 4 STEP, disagree lies
        within a few micrometres of a kink or jump (one-sided there by design): not compared."""

        def moved(e):
            y = x.copy()
            y[index] += e
            return score(y)

        at, ahead, behind = moved(0.0), moved(STEP), moved(-STEP)
        fd = (ahead - behind) / (2 * STEP)
        wide = (moved(4 * STEP) - moved(-4 * STEP)) / (8 * STEP)
        tol = 1e-5 + 1e-3 * np.abs(fd)
        smooth = (np.abs(fd - wide) <= tol) & (np.abs((ahead - at) / STEP - (at - behind) / STEP) <= tol)
        bad = smooth & (np.abs(analytic - fd) > tol)
        assert not bad.any(), (name, index, np.flatnonzero(bad)[:5], analytic[bad][:5], fd[bad][:5])
        c = self.counts.setdefault(name, [0, 0, 0])
        c[0] += int(smooth.sum())
        c[1] += int((smooth & (np.abs(fd) > 1e-6)).sum())
        c[2] += int((~smooth).sum())

    def assert_mostly_compared(self):
        for name, (compared, moving, skipped) in self.counts.items():
            assert compared >= 0.9 * (compared + skipped), (name, compared, skipped)
        moving = [name for name, c in self.counts.items() if c[1] > 0]
        # Every relation but the few whose random configurations are all flat moves somewhere.
        assert len(moving) >= 0.8 * len(self.counts), sorted(set(self.counts) - set(moving))


def test_every_relation_matches_finite_differences(rng):
    tally = Tally()
    targets, anchors = pairs(rng, 60)
    for name in sceneeval.relation_names():
        if name == "surround":
            continue
        if name in ARCH:
            scores, d_targets = sceneeval.relation_batch(name, targets, room=ROOM, grad=True)
            assert scores.tolist() == sceneeval.relation_batch(name, targets, room=ROOM).tolist()
            for c in range(7):
                f = lambda t: sceneeval.relation_batch(name, t, room=ROOM)  # noqa: E731
                tally.compare(name, d_targets[:, c], f, targets, (slice(None), c))
            continue
        scores, d_targets, d_anchors = sceneeval.relation_batch(name, targets, anchors, grad=True)
        assert scores.tolist() == sceneeval.relation_batch(name, targets, anchors).tolist(), name
        for c in range(7):
            f = lambda t: sceneeval.relation_batch(name, t, anchors)  # noqa: E731
            tally.compare(name, d_targets[:, c], f, targets, (slice(None), c))
            f = lambda a: sceneeval.relation_batch(name, targets, a)  # noqa: E731
            tally.compare(name, d_anchors[:, c], f, anchors, (slice(None), c))
    tally.assert_mostly_compared()


def test_surround_matches_finite_differences(rng):
    tally = Tally()
    n, k = 30, 4
    anchors = random_boxes(rng, n)
    targets = np.empty((n, k, 7))
    for i in range(n):
        targets[i] = random_boxes(rng, k)
        angles = 2 * np.pi * np.arange(k) / k + rng.uniform(-0.6, 0.6, k)
        targets[i, :, 0] = anchors[i, 0] + rng.uniform(0.8, 1.6, k) * np.cos(angles)
        targets[i, :, 1] = anchors[i, 1] + rng.uniform(0.8, 1.6, k) * np.sin(angles)
    for reference in (False, True):
        name = "surround (reference)" if reference else "surround"
        scores, d_targets, d_anchors = sceneeval.relation_batch(
            "surround", targets, anchors, grad=True, reference=reference
        )
        assert d_targets.shape == (n, k, 7) and d_anchors.shape == (n, 7)
        assert scores.tolist() == sceneeval.relation_batch("surround", targets, anchors, reference=reference).tolist()
        for c in range(7):
            for j in range(k):
                f = lambda t: sceneeval.relation_batch("surround", t, anchors, reference=reference)  # noqa: E731
                tally.compare(name, d_targets[:, j, c], f, targets, (slice(None), j, c))
            f = lambda a: sceneeval.relation_batch("surround", targets, a, reference=reference)  # noqa: E731
            tally.compare(name, d_anchors[:, c], f, anchors, (slice(None), c))
    tally.assert_mostly_compared()


def test_hand_computed_gradients():
    # A 0.5 m cube half sunk into a 1 m table (z from 0.75 to 1.25; on_top's plane is the top
    # face, z = 1, moved out by its 1e-6 m tolerance): (0.25 + 1e-6) / 0.5 of it is above.
    # Raising the cube by dz raises that share by dz / 0.5; lowering the table raises it alike.
    cube = np.array([[0.0, 0.0, 1.0, 0.25, 0.25, 0.25, 0.0]])
    table = np.array([[0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.0]])
    s, d_t, d_a = sceneeval.relation_batch("on_top", cube, table, grad=True)
    assert s[0] == pytest.approx(0.500002, abs=1e-12)
    assert d_t[0, 2] == pytest.approx(2.0, abs=1e-9) and d_a[0, 2] == pytest.approx(-2.0, abs=1e-9)
    # middle_of: 0.25 m off along x with sigma 0.25, score exp(-0.5); d/dx = -score * 0.25 / 0.25^2.
    pillow = np.array([[1.25, 2.0, 0.7, 0.3, 0.2, 0.1, 0.0]])
    bed = np.array([[1.0, 2.0, 0.3, 0.8, 1.0, 0.3, 0.0]])
    s, d_t, d_a = sceneeval.relation_batch("middle_of", pillow, bed, grad=True)
    assert s[0] == pytest.approx(np.exp(-0.5), abs=1e-15)
    assert d_t[0].tolist() == pytest.approx([-4 * np.exp(-0.5), 0, 0, 0, 0, 0, 0], abs=1e-12)
    assert d_a[0, 0] == pytest.approx(4 * np.exp(-0.5), abs=1e-12)
    # A 1 x 1 box centred on the room's corner (-4, -4): a quarter of it over the floor. Moving
    # it by dx along +x puts dx more of its width over the floor, over half its depth: the
    # share grows by 0.5 dx / 1.
    corner = np.array([[-4.0, -4.0, 0.5, 0.5, 0.5, 0.5, 0.0]])
    s, d_t = sceneeval.relation_batch("inside_room", corner, room=ROOM, grad=True)
    assert s[0] == pytest.approx(0.25, abs=1e-9)
    assert d_t[0, 0] == pytest.approx(0.5, abs=1e-9) and d_t[0, 1] == pytest.approx(0.5, abs=1e-9)


def test_shapes_tuples_and_shared_anchors(rng):
    targets, anchors = pairs(rng, 20)
    out = sceneeval.relation_batch("near", targets, anchors, grad=True)
    assert isinstance(out, tuple) and len(out) == 3
    for a, shape in zip(out, [(20,), (20, 7), (20, 7)]):
        assert a.dtype == np.float64 and a.shape == shape
    out = sceneeval.relation_batch("against_wall", targets, room=ROOM, grad=True)
    assert isinstance(out, tuple) and len(out) == 2 and out[1].shape == (20, 7)
    # One anchor row for every target: one derivative row per score, as with the row repeated.
    shared = sceneeval.relation_batch("side_of", targets, anchors[:1], side="left", grad=True)
    repeated = sceneeval.relation_batch("side_of", targets, np.repeat(anchors[:1], 20, axis=0), side="left", grad=True)
    for a, b in zip(shared, repeated):
        assert np.array_equal(a, b)
    # Parameters and the reference switch apply to the gradients too.
    s, _, _ = sceneeval.relation_batch("near", targets, anchors, grad=True, near=(0.0, 1.0, 0.25))
    assert s.tolist() == sceneeval.relation_batch("near", targets, anchors, near=(0.0, 1.0, 0.25)).tolist()
    empty = sceneeval.relation_batch("near", np.empty((0, 7)), np.empty((0, 7)), grad=True)
    assert [a.shape for a in empty] == [(0,), (0, 7), (0, 7)]
    empty = sceneeval.relation_batch("surround", np.empty((0, 4, 7)), np.empty((0, 7)), grad=True)
    assert [a.shape for a in empty] == [(0,), (0, 4, 7), (0, 7)]
    # Bad input is refused as without gradients.
    bad = targets.copy()
    bad[3, 4] = np.nan
    with pytest.raises(ValueError, match=r"^targets\[3\]\.half_size is not finite$"):
        sceneeval.relation_batch("near", bad, anchors, grad=True)
    with pytest.raises(ValueError, match=r"needs room"):
        sceneeval.relation_batch("on_wall", targets, grad=True)


@pytest.fixture
def layout_example():
    sys.path.insert(0, str(REPO / "examples" / "python"))
    try:
        import gradient_layout

        yield gradient_layout
    finally:
        sys.path.pop(0)


def test_layout_example_gradients_match_finite_differences(layout_example, rng):
    # The Jacobian GoalScores' backward multiplies into: every goal's derivatives with respect
    # to every box, against central differences of the goals' scores.
    ex = layout_example
    tally = Tally()
    for _ in range(5):
        boxes = ex.boxes_of(ex.random_start(rng))
        _, jac = ex.goal_scores(boxes)
        for k in range(len(boxes)):
            for c in ex.FREE:
                tally.compare("goals", jac[:, k, c], lambda b: ex.goal_scores(b)[0], boxes, (k, c))
    tally.assert_mostly_compared()


def test_layout_example_places_the_bedroom(layout_example):
    placements, solved, steps, starts = layout_example.optimise_numpy(seed=3, max_steps=2000)
    assert solved, (steps, starts)
    scores, _ = layout_example.goal_scores(layout_example.boxes_of(placements))
    assert layout_example.all_hold(scores)
