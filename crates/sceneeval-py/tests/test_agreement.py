"""sceneeval.agreement against scikit-learn's cohen_kappa_score and statsmodels' fleiss_kappa on
the same items, with label files the test writes (docs/judge.md, docs/formats.md "Agreement
tables"); and the same rows as `sceneeval agreement --format csv`."""

import csv
import io
import json
import subprocess
import warnings

import numpy as np
import pytest
from sklearn.metrics import cohen_kappa_score
from statsmodels.stats.inter_rater import fleiss_kappa

import sceneeval

METRICS = ["cnt", "atr", "oor", "oar"]


def write_labels(path, rows):
    """rows: (annotator, scene, metric, index, verdict or None); JSON Lines."""
    with open(path, "w") as f:
        for annotator, scene, metric, index, verdict in rows:
            line = {
                "scene": scene,
                "metric": metric,
                "index": index,
                "spec": f"{metric} spec {index} of {scene}",
                "satisfied": verdict,
                "annotator": annotator,
            }
            f.write(json.dumps(line) + "\n")


def random_verdicts(rng, truth, flip, null):
    """truth with a share `flip` of verdicts flipped and a share `null` made None."""
    out = {}
    for item, v in truth.items():
        r = rng.random()
        out[item] = None if r < null else (not v if r < null + flip else v)
    return out


def sk_kappa(pairs):
    if not pairs:
        return None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        k = cohen_kappa_score([a for a, _ in pairs], [b for _, b in pairs])
    return None if np.isnan(k) else float(k)


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_kappas_equal_scikit_learn_and_statsmodels(tmp_path, seed):
    rng = np.random.default_rng(seed)
    items = [(f"scene_{s}", m, k) for s in range(12) for m in METRICS for k in range(int(rng.integers(1, 4)))]
    truth = {item: bool(rng.random() < 0.7) for item in items}
    people = {name: random_verdicts(rng, truth, 0.1, 0.05) for name in ["alice", "bob", "carol"]}
    # carol skipped a few items altogether: Fleiss uses the items all three judged.
    for item in items[::7]:
        del people["carol"][item]
    judges = {"gpt": random_verdicts(rng, truth, 0.1, 0.02), "local": random_verdicts(rng, truth, 0.3, 0.1)}
    reference = tmp_path / "people.jsonl"
    write_labels(reference, [(p, *item, v) for p, vs in people.items() for item, v in vs.items()])
    judge_file = tmp_path / "judges.jsonl"
    write_labels(judge_file, [(j, *item, v) for j, vs in judges.items() for item, v in vs.items()])

    rows = sceneeval.agreement([str(judge_file)], reference=str(reference), bootstrap=0)
    by_key = {(r["kind"], r["a"], r["b"], r["metric"]): r for r in rows}

    def in_scope(item, metric):
        return metric == "all" or item[1] == metric

    # The reference: the majority of the people who judged an item; ties and no votes left out.
    majority = {}
    for item in items:
        votes = [vs[item] for vs in people.values() if item in vs and vs[item] is not None]
        yes, no = votes.count(True), votes.count(False)
        if yes != no:
            majority[item] = yes > no
    for judge, verdicts in judges.items():
        for metric in METRICS + ["all"]:
            pairs = [
                (verdicts[i], majority[i])
                for i in items
                if in_scope(i, metric) and i in majority and verdicts[i] is not None
            ]
            row = by_key[("judge", judge, "reference", metric)]
            assert row["n"] == len(pairs)
            expected = sk_kappa(pairs)
            if expected is None:
                assert row["kappa"] is None and row["undefined"]
            else:
                assert row["kappa"] == pytest.approx(expected, rel=1e-12, abs=1e-14)
            assert row["agreement"] == pytest.approx(np.mean([a == b for a, b in pairs]))
            assert row["tt"] + row["tf"] + row["ft"] + row["ff"] == len(pairs)
    names = list(people)
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            for metric in METRICS + ["all"]:
                pairs = [
                    (people[a][it], people[b][it])
                    for it in items
                    if in_scope(it, metric)
                    and people[a].get(it) is not None
                    and people[b].get(it) is not None
                ]
                row = by_key[("annotators", a, b, metric)]
                assert row["n"] == len(pairs)
                assert row["kappa"] == pytest.approx(sk_kappa(pairs), rel=1e-12, abs=1e-14)
    for metric in METRICS + ["all"]:
        table = []
        for it in items:
            votes = [people[p].get(it) for p in names]
            if in_scope(it, metric) and all(v is not None for v in votes):
                table.append([votes.count(False), votes.count(True)])
        row = by_key[("fleiss", "*", "*", metric)]
        assert row["n"] == len(table)
        assert row["agreement"] is None
        assert row["kappa"] == pytest.approx(fleiss_kappa(np.array(table), method="fleiss"), rel=1e-12, abs=1e-14)


def test_hand_computed_cases_and_the_command_line(tmp_path, sceneeval_bin):
    # Perfect, chance and one class on oor, cnt and oar.
    people = [("alice", "s", "oor", k, v) for k, v in enumerate([True, False, True, False])]
    people += [("alice", "s", "cnt", k, v) for k, v in enumerate([True, False, True, False])]
    people += [("alice", "s", "oar", k, True) for k in range(3)]
    judge = [("vlm", "s", "oor", k, v) for k, v in enumerate([True, False, True, False])]
    judge += [("vlm", "s", "cnt", k, v) for k, v in enumerate([True, True, False, False])]
    judge += [("vlm", "s", "oar", k, True) for k in range(3)]
    write_labels(tmp_path / "ref.jsonl", people)
    write_labels(tmp_path / "vlm.jsonl", judge)
    rows = sceneeval.agreement([tmp_path / "vlm.jsonl"], reference=[tmp_path / "ref.jsonl"], seed=3)
    by_metric = {r["metric"]: r for r in rows if r["kind"] == "judge"}
    assert by_metric["oor"]["kappa"] == 1.0
    assert by_metric["cnt"]["kappa"] == 0.0
    assert by_metric["oar"]["kappa"] is None
    assert by_metric["oar"]["undefined"].startswith("one class only")
    # The command line gives the same rows (full precision in CSV).
    out = subprocess.run(
        [sceneeval_bin, "agreement", "--reference", tmp_path / "ref.jsonl", tmp_path / "vlm.jsonl",
         "--format", "csv", "--seed", "3"],
        check=True, capture_output=True, text=True,
    ).stdout
    for line in csv.DictReader(io.StringIO(out)):
        row = next(r for r in rows if (r["kind"], r["a"], r["b"], r["metric"]) ==
                   (line["kind"], line["a"], line["b"], line["metric"]))
        for key in ["kappa", "kappa_low", "kappa_high", "agreement"]:
            assert (float(line[key]) if line[key] else None) == row[key], key
        assert int(line["n"]) == row["n"]
    with pytest.raises(ValueError, match="at least two"):
        sceneeval.agreement([tmp_path / "vlm.jsonl"])
    (tmp_path / "bad.jsonl").write_text('{"scene": "s"}\n')
    with pytest.raises(sceneeval.SceneEvalError, match="bad.jsonl:1: not a label"):
        sceneeval.agreement([tmp_path / "bad.jsonl"], reference=tmp_path / "ref.jsonl")
