"""sceneeval.compare(runs, paired=True) against SciPy's Wilcoxon signed-rank test and
statsmodels' Holm adjustment, on runs this test writes from records (issue 37).

The rule the p-values follow (docs/formats.md, "sceneeval compare --paired"): the per-scene
differences b - a in percent, rounded to 1e-9, zeros dropped, scipy.stats.wilcoxon(d,
zero_method='wilcox', correction=True, alternative='two-sided', method='exact' when at most 50
non-zero differences remain and their |d| have no ties, else 'asymptotic'); no p-value from
fewer than two non-zero differences; Holm across the columns of a pair:
statsmodels.stats.multitest.multipletests(p, method='holm')[1].
"""

import copy
import json
import warnings
from pathlib import Path

import numpy as np
import pytest
from statsmodels.stats.multitest import multipletests

import sceneeval
from conftest import scipy_wilcoxon

TEMPLATE = (
    Path(__file__).resolve().parents[2]
    / "sceneeval-cli/tests/golden/runs/geometry/scene_0/eval.json"
)
# The columns this test fills, their summary field and direction.
COLUMNS = [("SUP", "sup"), ("NAV", "nav"), ("OOB", "oob")]


def write_run(root, name, values, failed=()):
    """A run folder root/name: per scene k, values[k] = {field: share in [0, 1]} (None: the
    scene is missing); scenes in `failed` are written as failed."""
    template = json.loads(TEMPLATE.read_text())
    run = Path(root) / name
    for k, v in enumerate(values):
        if v is None and k not in failed:
            continue
        record = copy.deepcopy(template)
        record["scene"] = f"scene_{k}"
        record["scene_id"] = str(k)
        if k in failed:
            del record["report"]
            record["status"] = "failed"
            record["stage"] = "load"
            record["error"] = "crashed"
            record["causes"] = []
        else:
            report = record["report"]
            report["scene"] = f"scene_{k}"
            report["metrics"] = ["support", "navigability", "out_of_bounds"]
            report["summary"].update(sup=v["sup"], nav=v["nav"], oob=v["oob"])
            for section in ("collision", "support", "navigability", "accessibility", "out_of_bounds",
                            "opening_clearance"):
                report[section] = None
        (run / f"scene_{k}").mkdir(parents=True)
        (run / f"scene_{k}" / "eval.json").write_text(json.dumps(record))
    return run


def scipy_wilcoxon_p(d):
    """SciPy's p-value under the rule above and whether it was exact, or None with fewer than
    two non-zero differences."""
    if np.count_nonzero(np.round(np.asarray(d, dtype=float), 9)) < 2:
        return None
    res, exact, _, _ = scipy_wilcoxon(d)
    return res.pvalue, exact


def random_run(rng, n, coarse):
    """Shares for n scenes: continuous, or coarse steps of 1/8 (ties and zero differences)."""
    if coarse:
        return [{f: float(rng.integers(0, 9)) / 8 for _, f in COLUMNS} for _ in range(n)]
    return [{f: float(rng.uniform(0, 1)) for _, f in COLUMNS} for _ in range(n)]


def test_paired_rows_equal_scipy_and_statsmodels(tmp_path):
    rng = np.random.default_rng(37)
    methods = set()
    for case in range(12):
        n = int(rng.integers(1, 70))
        coarse = case % 2 == 1
        a = random_run(rng, n, coarse)
        b = random_run(rng, n, coarse)
        if case % 3 == 0:  # B misses some scenes: pairs use the scenes both have
            for k in rng.choice(n, size=n // 4, replace=False):
                b[k] = None
        root = tmp_path / f"case{case}"
        ra, rb = write_run(root, "A", a), write_run(root, "B", b)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rows = sceneeval.compare([ra, rb], paired=True)
        assert [r["metric"] for r in rows] == [c for c, _ in COLUMNS]
        p_values = []
        for row, (column, field) in zip(rows, COLUMNS):
            both = [k for k in range(n) if b[k] is not None]
            d = np.array([100 * b[k][field] - 100 * a[k][field] for k in both])
            assert (row["kind"], row["a"], row["b"], row["n"]) == ("paired", "A", "B", len(both))
            assert row["mean_diff"] == pytest.approx(d.mean(), rel=1e-12, abs=1e-9)
            assert row["diff_low"] <= row["diff_high"]
            expected = scipy_wilcoxon_p(d)
            if expected is None:
                assert row["p_value"] is None and row["method"] == "none"
                assert "a test needs at least two" in row["note"]
            else:
                p, exact = expected
                methods.add(row["method"])
                assert row["method"] == ("exact" if exact else "normal"), case
                if exact:
                    assert row["p_value"] == p, case
                else:
                    assert row["p_value"] == pytest.approx(p, rel=1e-13), case
            p_values.append(row["p_value"])
        present = [p for p in p_values if p is not None]
        if present:
            holm = iter(multipletests(present, method="holm")[1])
            for row, p in zip(rows, p_values):
                if p is None:
                    assert row["p_holm"] is None
                else:
                    assert row["p_holm"] == pytest.approx(next(holm), rel=1e-15), case
    assert methods == {"exact", "normal"}


def test_against_first_edge_cases_and_run_rows(tmp_path):
    # A: 50 % everywhere on 4 scenes. B: equal to A (every difference zero). C: scene_0 only
    # (+40 on SUP), scene_1 failed.
    half = {"sup": 0.5, "nav": 0.5, "oob": 0.0}
    ra = write_run(tmp_path, "A", [half] * 4)
    rb = write_run(tmp_path, "B", [half] * 4)
    rc = write_run(tmp_path, "C", [{"sup": 0.9, "nav": 0.5, "oob": 0.0}, None], failed=(1,))
    with pytest.warns(UserWarning) as caught:
        rows = sceneeval.compare([ra, rb, rc], paired=True, against_first=True)
    messages = [str(w.message) for w in caught]
    assert any(m.startswith("A and C: 3 scene(s) not evaluated by both") for m in messages), messages
    assert any(m.startswith("Compared on the 1 of 4 scenes") for m in messages), messages
    assert [(r["a"], r["b"]) for r in rows] == [("A", "B")] * 3 + [("A", "C")] * 3
    # All equal: mean 0, interval [0, 0], no p-value.
    assert (rows[0]["mean_diff"], rows[0]["diff_low"], rows[0]["diff_high"]) == (0.0, 0.0, 0.0)
    assert rows[0]["p_value"] is None and rows[0]["zeros"] == 4
    # n = 1: no p-value, with the reason.
    assert rows[3]["n"] == 1 and rows[3]["p_value"] is None
    assert rows[3]["mean_diff"] == pytest.approx(40.0)
    assert rows[3]["note"].startswith("no p-value: 1 non-zero difference(s) of 1 scene(s)")
    # Without paired: the per-run rows, the failed and missing scenes named.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        table = sceneeval.compare([ra, rc], failed="worst", rank="mean")
    c_sup = next(r for r in table if r["run"] == "C" and r["column"] == "SUP")
    # Worst: (90 + 0 * 3) / 4.
    assert c_sup["value"] == pytest.approx(22.5)
    assert (c_sup["missing"], c_sup["failed"]) == (["scene_2", "scene_3"], ["scene_1"])
    with pytest.raises(ValueError, match="rank: "):
        sceneeval.compare([ra, rb], rank="points")
    with pytest.raises(ValueError, match="against_first: needs paired=True"):
        sceneeval.compare([ra, rb], against_first=True)
