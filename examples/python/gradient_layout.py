#!/usr/bin/env python3
"""A layout optimised by gradient from Python: the predicates' analytic gradients
(``sceneeval.relation_batch(..., grad=True)``) wrapped in a ``torch.autograd.Function``, and
Adam placing a bed, two nightstands and a desk in a 4 x 5 m bedroom (the room and goals of
``examples/layout_optimizer.rs``, with "no overlap" as ``outside_of``).

The scores of every goal and their derivatives with respect to every box are computed by
``goal_scores`` with numpy alone; ``GoalScores`` (defined only when torch is installed) is a
``torch.autograd.Function`` around it, so that the goals can sit in any torch loss: its
backward pass is the vector-Jacobian product of the derivatives ``relation_batch`` returned.
torch is optional: without it (or with ``--numpy``) the same Adam steps run in numpy. Every
100 steps without a layout that meets every goal, the objects of the failing goals start again
from random places.

    python examples/python/gradient_layout.py [--seed 1] [--max-steps 4000] [--numpy]
"""

import argparse
import sys
import time

import numpy as np

import sceneeval

try:  # torch is optional: the example, and its test, run without it.
    import torch
except ImportError:  # pragma: no cover - depends on the environment
    torch = None

# A 4 x 5 m bedroom, 2.8 m walls, a door in wall 0 (the wall along y = 0) at x in [2.6, 3.5].
ROOM = {
    "floor": [[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]],
    "height": 2.8,
    "wall_thickness": 0.1,
    "openings": [{"kind": "door", "wall": 0, "along": [2.6, 3.5], "height": [0.0, 2.1]}],
}
NAMES = ["bed", "left nightstand", "right nightstand", "desk"]
HALF = np.array([[0.8, 1.0, 0.3], [0.25, 0.2, 0.3], [0.25, 0.2, 0.3], [0.6, 0.3, 0.375]])
BED, LEFT, RIGHT, DESK = range(4)
# The columns optimised: x, y and yaw of each box (z keeps it on the floor, sizes are fixed).
FREE = [0, 1, 6]

# Goals: (relation, target, anchor or None for the room, score it must exceed). Relations hold
# above 0.5; "no overlap" is outside_of (the share of the smaller box outside the larger one)
# of at least 0.99.
GOALS = (
    [
        ("against_wall", BED, None, 0.5),
        ("side_of(left)", LEFT, BED, 0.5),
        ("next_to", LEFT, BED, 0.5),
        ("against_wall", LEFT, None, 0.5),
        ("side_of(right)", RIGHT, BED, 0.5),
        ("next_to", RIGHT, BED, 0.5),
        ("against_wall", RIGHT, None, 0.5),
        ("against_wall", DESK, None, 0.5),
        ("across_from", DESK, BED, 0.5),
    ]
    + [("inside_room", k, None, 0.5) for k in range(4)]
    + [("outside_of", t, a, 0.99) for t, a in [(LEFT, BED), (RIGHT, BED), (DESK, BED), (LEFT, RIGHT), (LEFT, DESK), (RIGHT, DESK)]]
)


def boxes_of(placements):
    """The boxes (K, 7) of placements (K, 3) = (x, y, yaw), standing on the floor."""
    k = len(placements)
    boxes = np.zeros((k, 7))
    boxes[:, FREE] = placements
    boxes[:, 2] = HALF[:, 2]
    boxes[:, 3:6] = HALF
    return boxes


def goal_scores(boxes):
    """Every goal's score (G,) and its derivatives (G, K, 7) with respect to every box.

    Goals of one relation are scored together, one ``relation_batch`` call per relation: the
    targets' (and anchors') rows stacked, the derivatives of each score scattered back to the
    boxes it depends on."""
    scores = np.zeros(len(GOALS))
    jac = np.zeros((len(GOALS), len(boxes), 7))
    by_relation = {}
    for g, (name, _, anchor, _) in enumerate(GOALS):
        by_relation.setdefault((name, anchor is None), []).append(g)
    for (name, in_room), goals in by_relation.items():
        targets = np.array([boxes[GOALS[g][1]] for g in goals])
        if in_room:
            s, d_t = sceneeval.relation_batch(name, targets, room=ROOM, grad=True)
            d_a = None
        else:
            anchors = np.array([boxes[GOALS[g][2]] for g in goals])
            s, d_t, d_a = sceneeval.relation_batch(name, targets, anchors, grad=True)
        for row, g in enumerate(goals):
            scores[g] = s[row]
            jac[g, GOALS[g][1]] += d_t[row]
            if d_a is not None:
                jac[g, GOALS[g][2]] += d_a[row]
    return scores, jac


def energy_and_gradient(placements):
    """The energy (the sum of the goals' missing scores, 1 - score) and its gradient with
    respect to the placements (K, 3), from ``goal_scores`` (numpy only)."""
    scores, jac = goal_scores(boxes_of(placements))
    return float(np.sum(1.0 - scores)), -jac.sum(axis=0)[:, FREE], scores


def all_hold(scores):
    return all(s > goal[3] for s, goal in zip(scores, GOALS))


if torch is not None:

    class GoalScores(torch.autograd.Function):
        """The goals' scores of boxes (K, 7) as a differentiable torch function: forward
        calls ``goal_scores`` on the boxes' values, backward multiplies the upstream gradient
        (G,) into the saved derivatives (G, K, 7)."""

        @staticmethod
        def forward(ctx, boxes):
            scores, jac = goal_scores(boxes.detach().cpu().double().numpy())
            ctx.save_for_backward(torch.from_numpy(jac).to(boxes))
            return torch.from_numpy(scores).to(boxes)

        @staticmethod
        def backward(ctx, grad_scores):
            (jac,) = ctx.saved_tensors
            return torch.einsum("g,gkc->kc", grad_scores, jac)


RATE = np.array([0.04, 0.04, 0.08])  # Adam step sizes: metres along x and y, radians of yaw.
RESTART_AFTER = 100  # Steps from one start before the objects of failing goals start again.


def random_start(rng):
    return np.column_stack([rng.uniform(0, 4, 4), rng.uniform(0, 5, 4), rng.uniform(0, 2 * np.pi, 4)])


def restart(rng, p, scores):
    """The placements with the objects of the goals that fail moved to random places (the
    others stay where the descent put them), as examples/layout.rs restarts."""
    p = p.copy()
    fresh = random_start(rng)
    for (_, t, a, need), s in zip(GOALS, scores):
        if s <= need:
            for k in (t, a):
                if k is not None:
                    p[k] = fresh[k]
    return p


def keep_in_room(p):
    p[:, 0] = np.clip(p[:, 0], 0.0, 4.0)
    p[:, 1] = np.clip(p[:, 1], 0.0, 5.0)
    p[:, 2] = np.mod(p[:, 2], 2 * np.pi)
    return p


def optimise_numpy(seed, max_steps):
    """Adam in numpy on the energy from a random layout; every RESTART_AFTER steps the objects
    of the goals that fail start again from random places, until every goal holds. Returns
    (placements, solved, steps, starts)."""
    rng = np.random.default_rng(seed)
    p, steps, starts = random_start(rng), 0, 0
    while steps < max_steps:
        m, v = np.zeros((4, 3)), np.zeros((4, 3))
        starts += 1
        for t in range(1, RESTART_AFTER + 1):
            _, grad, scores = energy_and_gradient(p)
            steps += 1
            if all_hold(scores):
                return p, True, steps, starts
            if steps >= max_steps:
                return p, False, steps, starts
            m = 0.9 * m + 0.1 * grad
            v = 0.999 * v + 0.001 * grad * grad
            p = keep_in_room(p - RATE * (m / (1 - 0.9**t)) / (np.sqrt(v / (1 - 0.999**t)) + 1e-8))
        p = restart(rng, p, goal_scores(boxes_of(p))[0])
    return p, False, steps, starts


def optimise_torch(seed, max_steps):
    """The same descent with torch.optim.Adam on a loss built from GoalScores. Adam's step
    does not depend on the gradient's scale, so the per-column step sizes are a change of
    variables: Adam with rate 1 moves q, and the placements are q * RATE."""
    rng = np.random.default_rng(seed)
    fixed = torch.from_numpy(boxes_of(np.zeros((4, 3))))
    rate = torch.from_numpy(RATE)
    p, steps, starts = random_start(rng), 0, 0
    while steps < max_steps:
        q = torch.tensor(p / RATE, requires_grad=True)
        opt = torch.optim.Adam([q], lr=1.0, betas=(0.9, 0.999), eps=1e-8)
        starts += 1
        for _ in range(RESTART_AFTER):
            boxes = fixed.clone()
            boxes[:, FREE] = q * rate
            scores = GoalScores.apply(boxes)
            steps += 1
            if all_hold(scores.detach().numpy()):
                return (q * rate).detach().numpy(), True, steps, starts
            if steps >= max_steps:
                return (q * rate).detach().numpy(), False, steps, starts
            opt.zero_grad()
            (1.0 - scores).sum().backward()
            opt.step()
            with torch.no_grad():
                q.copy_(torch.from_numpy(keep_in_room((q * rate).numpy()) / RATE))
        p = (q * rate).detach().numpy()
        p = restart(rng, p, goal_scores(boxes_of(p))[0])
    return p, False, steps, starts


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--max-steps", type=int, default=4000)
    parser.add_argument("--numpy", action="store_true", help="use numpy's Adam even if torch is installed")
    args = parser.parse_args(argv)
    use_torch = torch is not None and not args.numpy
    start = time.perf_counter()
    optimise = optimise_torch if use_torch else optimise_numpy
    p, solved, steps, starts = optimise(args.seed, args.max_steps)
    elapsed = time.perf_counter() - start
    print(
        f"{'torch' if use_torch else 'numpy'} Adam: {steps} steps ({steps * len(GOALS)} goal scores with "
        f"gradients) in {starts} descents in {elapsed:.2f} s; "
        + ("every goal holds" if solved else "not every goal holds")
    )
    scores, _ = goal_scores(boxes_of(p))
    for name, (x, y, yaw) in zip(NAMES, p):
        print(f"  {name}: x {x:.2f} m, y {y:.2f} m, yaw {np.degrees(yaw):.0f} deg")
    for (relation, t, a, need), s in zip(GOALS, scores):
        other = "the room" if a is None else NAMES[a]
        print(f"  {'ok ' if s > need else 'NO '} {NAMES[t]} {relation} {other}: {s:.3f}")
    return 0 if solved else 1


if __name__ == "__main__":
    sys.exit(main())
