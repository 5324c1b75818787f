"""sceneeval.stats against the implementations reviewers know: scikit-learn's Cohen's kappa,
statsmodels' Fleiss' kappa, Holm adjustment and McNemar test, SciPy's Wilcoxon signed-rank test;
on seeded random cases and the edge cases (docs/formats.md, "Statistics")."""

import ast
import inspect
import math
import warnings
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from sklearn.metrics import cohen_kappa_score
from statsmodels.stats.contingency_tables import mcnemar as sm_mcnemar
from statsmodels.stats.inter_rater import fleiss_kappa as sm_fleiss_kappa
from statsmodels.stats.multitest import multipletests

import sceneeval
import sceneeval.stats
from conftest import scipy_wilcoxon
from sceneeval import stats

STUB = Path(sceneeval.__file__).with_name("stats.pyi")


def words(text):
    return " ".join((text or "").split())


def test_the_module_its_stubs_and_docstrings():
    from sceneeval.stats import wilcoxon  # noqa: F401  (the submodule imports by name)

    assert sceneeval.stats is stats is sceneeval._sceneeval.stats
    tree = ast.parse(STUB.read_text())
    functions = [node for node in tree.body if isinstance(node, ast.FunctionDef)]
    names = {node.name for node in functions}
    exported = {n for n in dir(stats) if not n.startswith("_")}
    assert names == exported
    for node in functions:
        assert words(ast.get_docstring(node)) == words(inspect.getdoc(getattr(stats, node.name))), node.name
        runtime = inspect.signature(getattr(stats, node.name))
        assert [p.arg for p in node.args.args] == [
            p for p in runtime.parameters if runtime.parameters[p].kind is inspect.Parameter.POSITIONAL_OR_KEYWORD
        ], node.name
        for arg, default in zip(node.args.kwonlyargs, node.args.kw_defaults):
            assert runtime.parameters[arg.arg].default == ast.literal_eval(default), (node.name, arg.arg)


# Cohen's kappa -------------------------------------------------------------------------------


def sklearn_kappa(a, b):
    """scikit-learn's kappa on the items both judged; None where it is NaN (undefined)."""
    pairs = [(x, y) for x, y in zip(a, b) if x is not None and y is not None]
    if not pairs:
        return None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        k = cohen_kappa_score([x for x, _ in pairs], [y for _, y in pairs])
    return None if np.isnan(k) else float(k)


def exact_cohen(a, b):
    """Cohen's kappa as an exact fraction over the items both judged (None where undefined)."""
    pairs = [(x, y) for x, y in zip(a, b) if x is not None and y is not None]
    n = len(pairs)
    labels = {x for p in pairs for x in p}
    chance = sum(sum(1 for x, _ in pairs if x == c) * sum(1 for _, y in pairs if y == c) for c in labels)
    if n == 0 or chance == n * n:
        return None
    agreed = sum(1 for x, y in pairs if x == y)
    return Fraction(n * agreed - chance, n * n - chance)


def exact_fleiss(table):
    """Fleiss' kappa as an exact fraction (None where undefined), from its definition."""
    items, r = len(table), sum(table[0])
    m = items * r
    p_bar = Fraction(sum(sum(c * (c - 1) for c in row) for row in table), items * r * (r - 1))
    p_e = sum(Fraction(sum(row[j] for row in table), m) ** 2 for j in range(len(table[0])))
    return None if p_e == 1 else (p_bar - p_e) / (1 - p_e)


def random_verdicts(rng, n, p_null, p_true):
    out = []
    for _ in range(n):
        if rng.random() < p_null:
            out.append(None)
        else:
            out.append(bool(rng.random() < p_true))
    return out


def test_cohen_kappa_equals_scikit_learn_on_random_binary_verdicts():
    rng = np.random.default_rng(36)
    compared = undefined = 0
    for case in range(400):
        n = int(rng.integers(0, 60))
        p_true = rng.choice([0.02, 0.3, 0.5, 0.9, 0.98])
        a = random_verdicts(rng, n, rng.choice([0.0, 0.1, 0.4]), p_true)
        # b agrees with a with some probability, else draws on its own.
        agree = rng.random()
        b = [x if (x is not None and rng.random() < agree) else random_verdicts(rng, 1, 0.1, p_true)[0] for x in a]
        got = stats.cohen_kappa(a, b)
        expected = sklearn_kappa(a, b)
        judged = sum(1 for x, y in zip(a, b) if x is not None and y is not None)
        assert got["n"] == judged and got["left_out"] == n - judged, case
        if expected is None:
            assert got["kappa"] is None, (case, a, b, got)
            assert got["undefined"] in ("no_items", "one_class") and got["reason"]
            undefined += 1
        else:
            # Correctly rounded (exact integers, one division); scikit-learn's float
            # arithmetic is within a few units in the last place of it.
            assert got["kappa"] == float(exact_cohen(a, b)), (case, a, b)
            assert got["kappa"] == pytest.approx(expected, rel=1e-12, abs=1e-14), (case, a, b)
            assert got["undefined"] is None and got["reason"] is None
            compared += 1
    assert compared > 250 and undefined > 5


def test_cohen_kappa_equals_scikit_learn_on_nominal_labels():
    rng = np.random.default_rng(37)
    for case in range(200):
        k = int(rng.integers(2, 6))
        labels = [f"class {c}" for c in range(k)] if case % 2 else list(range(-1, k - 1))
        n = int(rng.integers(1, 50))
        a = [labels[int(i)] for i in rng.integers(0, k, n)]
        b = [x if rng.random() < 0.6 else labels[int(rng.integers(0, k))] for x in a]
        got = stats.cohen_kappa(a, b)
        expected = sklearn_kappa(a, b)
        if expected is None:
            assert got["kappa"] is None and got["undefined"] == "one_class"
        else:
            assert got["kappa"] == float(exact_cohen(a, b)), case
            assert got["kappa"] == pytest.approx(expected, rel=1e-12, abs=1e-14), case
        assert got["labels"] == sorted(set(a) | set(b))
        assert sum(map(sum, got["confusion"])) == n


def test_cohen_kappa_edge_cases():
    # Perfect agreement, both classes: exactly 1.
    assert stats.cohen_kappa([True, False, True], [True, False, True])["kappa"] == 1.0
    # One rater all true, the other all false: 0, as scikit-learn gives.
    r = stats.cohen_kappa([True] * 5, [False] * 5)
    assert r["kappa"] == 0.0 == cohen_kappa_score([True] * 5, [False] * 5)
    assert r["agreement"] == 0.0 and r["expected_agreement"] == 0.0
    assert r["confusion"] == [[0, 0], [5, 0]]
    # One class on both sides: undefined (scikit-learn: NaN), with the reason.
    r = stats.cohen_kappa([True] * 4, [True] * 4)
    assert r["kappa"] is None and r["undefined"] == "one_class" and "one class" in r["reason"]
    assert r["agreement"] == 1.0
    # All null: no items.
    r = stats.cohen_kappa([None, True, None], [False, None, None])
    assert (r["n"], r["left_out"], r["kappa"], r["undefined"]) == (0, 3, None, "no_items")
    assert r["agreement"] is None and r["interval"] is None
    # Chance: p_o = p_e = 0.5.
    a = [True] * 6 + [False] * 4
    b = [True, True, True, False, False, False, True, True, False, False]
    assert stats.cohen_kappa(a, b)["kappa"] == 0.0
    # NumPy input.
    assert stats.cohen_kappa(np.array([True, False, True]), np.array([True, False, False]))["kappa"] == pytest.approx(
        cohen_kappa_score([True, False, True], [True, False, False])
    )
    assert stats.cohen_kappa(np.array([1, 2, 2]), np.array([1, 2, 1]))["labels"] == [1, 2]
    # Bad input names the argument.
    with pytest.raises(ValueError, match="differ in length"):
        stats.cohen_kappa([True], [True, False])
    with pytest.raises(ValueError, match="one kind only"):
        stats.cohen_kappa([True, 1], [True, 1])
    with pytest.raises(ValueError, match=r"b\[1\]: a label is a bool, an int, a str or None, got a float"):
        stats.cohen_kappa([1, 2], [1, 2.5])


def test_cohen_kappa_bootstrap_interval():
    rng = np.random.default_rng(5)
    a = random_verdicts(rng, 80, 0.0, 0.6)
    b = [x if rng.random() < 0.8 else not x for x in a]
    r = stats.cohen_kappa(a, b, bootstrap=1000)
    ci = r["interval"]
    assert ci["low"] <= r["kappa"] <= ci["high"]
    assert (ci["level"], ci["resamples"], ci["undefined_resamples"]) == (0.95, 1000, 0)
    # Seeded: the same again; another seed or level, another interval.
    assert stats.cohen_kappa(a, b, bootstrap=1000)["interval"] == ci
    assert stats.cohen_kappa(a, b, bootstrap=1000, seed=1)["interval"] != ci
    narrow = stats.cohen_kappa(a, b, bootstrap=1000, level=0.5)["interval"]
    assert ci["low"] <= narrow["low"] <= narrow["high"] <= ci["high"]
    # Two agreeing items of different classes: half the resamples draw one class only.
    r = stats.cohen_kappa([True, False], [True, False], bootstrap=1000)
    assert r["interval"]["low"] == r["interval"]["high"] == 1.0
    assert 400 < r["interval"]["undefined_resamples"] < 600
    r = stats.cohen_kappa([True] * 3, [True] * 3, bootstrap=100)
    assert r["interval"]["low"] is None and r["interval"]["undefined"] == "every_resample"
    with pytest.raises(ValueError, match="confidence level"):
        stats.cohen_kappa(a, b, bootstrap=10, level=1.5)
    with pytest.raises(ValueError, match="at least one resample"):
        stats.cohen_kappa(a, b, bootstrap=0)


# Fleiss' kappa -------------------------------------------------------------------------------


def test_fleiss_kappa_equals_statsmodels_on_random_tables():
    rng = np.random.default_rng(360)
    compared = 0
    for case in range(300):
        items = int(rng.integers(1, 40))
        categories = int(rng.integers(2, 5))
        raters = int(rng.integers(2, 9))
        weights = rng.dirichlet(np.ones(categories) * rng.choice([0.2, 1.0, 5.0]))
        table = np.array([rng.multinomial(raters, weights) for _ in range(items)])
        got = stats.fleiss_kappa(table.tolist())
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            expected = sm_fleiss_kappa(table, method="fleiss")
        assert (got["items"], got["raters"]) == (items, raters)
        if np.isnan(expected):
            assert got["kappa"] is None and got["undefined"] == "one_class", case
        else:
            # Correctly rounded; statsmodels subtracts two rounded agreements, so near kappa 0
            # it is off by up to about 1e-14 (absolute).
            assert got["kappa"] == float(exact_fleiss(table.tolist())), (case, table)
            assert got["kappa"] == pytest.approx(expected, rel=1e-12, abs=1e-13), (case, table)
            compared += 1
    assert compared > 250


def test_fleiss_kappa_edge_cases():
    # 3 items x 2 categories by hand: 0.2 (the crate's worked case).
    assert stats.fleiss_kappa([[4, 0], [2, 2], [1, 3]])["kappa"] == pytest.approx(0.2, abs=1e-15)
    assert stats.fleiss_kappa([[3, 0], [0, 3]])["kappa"] == 1.0
    r = stats.fleiss_kappa([[3, 0], [3, 0]])
    assert r["kappa"] is None and r["undefined"] == "one_class"
    assert stats.fleiss_kappa([[1, 0], [0, 1]])["undefined"] == "too_few_raters"
    assert stats.fleiss_kappa([])["undefined"] == "no_items"
    assert stats.fleiss_kappa(np.array([[2, 1], [0, 3]]))["kappa"] == pytest.approx(
        sm_fleiss_kappa(np.array([[2, 1], [0, 3]]))
    )
    with pytest.raises(ValueError, match="item 1 has 2 ratings but item 0 has 3"):
        stats.fleiss_kappa([[2, 1], [1, 1]])


# Wilcoxon ------------------------------------------------------------------------------------


def random_differences(rng, case):
    n = int(rng.integers(0, 90))
    kind = case % 5
    if kind == 0:  # continuous: no ties, no zeros
        return rng.normal(rng.normal(0, 0.3), 1, n)
    if kind == 1:  # metric percentages: coarse, many ties and zeros
        return (rng.integers(0, 6, n) - rng.integers(0, 6, n)) * 12.5
    if kind == 2:  # small shifts with floating-point noise around ties and zero
        base = rng.integers(-3, 4, n) * 0.1
        return base + rng.choice([0.0, 1e-12, -1e-13], n)
    if kind == 3:  # one-sided
        return np.abs(rng.normal(0, 1, n)) + 0.01
    return rng.standard_t(2, n) * 10.0  # heavy tails, large |z| possible


def test_wilcoxon_equals_scipy_on_random_differences():
    rng = np.random.default_rng(37)
    methods = {"exact": 0, "normal": 0, "none": 0}
    for case in range(600):
        d = random_differences(rng, case)
        got = stats.wilcoxon(d.tolist())
        methods[got["method"]] += 1
        res, exact, n, zeros = scipy_wilcoxon(d)
        assert (got["n"], got["zeros"]) == (n, zeros), case
        if n < 2:
            assert got["p_value"] is None and got["undefined"] == "too_few_differences"
            assert got["method"] == "none" and got["reason"]
            continue
        assert got["method"] == ("exact" if exact else "normal"), case
        rounded = np.round(d, 9)
        assert got["ties"] == (len(np.unique(np.abs(rounded[rounded != 0]))) < n), case
        assert got["statistic"] == res.statistic, case
        assert got["r_plus"] + got["r_minus"] == n * (n + 1) / 2
        if exact:
            assert got["p_value"] == res.pvalue, (case, d)  # the same dyadic rational
            assert got["z"] is None
        else:
            assert got["p_value"] == pytest.approx(res.pvalue, rel=1e-14, abs=1e-300), (case, d)
            assert -abs(got["z"]) == pytest.approx(res.zstatistic, rel=1e-15), case
    assert methods["exact"] > 100 and methods["normal"] > 100 and methods["none"] > 5, methods


def test_wilcoxon_edge_cases():
    # n = 1, all zero, empty: no p-value, with the reason.
    r = stats.wilcoxon([0.0, 2.5, 0.0])
    assert (r["n"], r["zeros"], r["p_value"], r["undefined"]) == (1, 2, None, "too_few_differences")
    assert stats.wilcoxon([0.0] * 5)["n"] == 0
    assert stats.wilcoxon([])["p_value"] is None
    # Worked by hand: |d| ranks 1..4, R+ = 9: p = 2 * 2/16.
    r = stats.wilcoxon([-1.0, 2.0, 3.0, 4.0])
    assert (r["statistic"], r["method"], r["p_value"]) == (1.0, "exact", 0.25)
    # All equal: ties, the normal approximation (SciPy's value).
    r = stats.wilcoxon([0.2] * 6)
    res, exact, _, _ = scipy_wilcoxon([0.2] * 6)
    assert not exact and r["method"] == "normal" and r["ties"]
    assert r["p_value"] == pytest.approx(res.pvalue, rel=1e-14)
    # Symmetric under negation.
    d = [0.3, -0.1, 0.7, 0.7, -0.2, 0.05]
    assert stats.wilcoxon(d)["p_value"] == stats.wilcoxon([-x for x in d])["p_value"]
    with pytest.raises(ValueError, match="differences: value 1 is not a finite number"):
        stats.wilcoxon([1.0, float("nan")])


# Paired differences and the bootstrap --------------------------------------------------------


def test_paired_combines_the_mean_its_interval_and_wilcoxon():
    rng = np.random.default_rng(11)
    for case in range(50):
        n = int(rng.integers(0, 40))
        a = rng.uniform(0, 1, n)
        b = np.clip(a + rng.normal(0.05, 0.1, n), 0, 1)
        r = stats.paired(a.tolist(), b.tolist())
        assert r["n"] == n
        if n == 0:
            assert r["mean_difference"] is None and r["interval"]["undefined"] == "no_items"
            continue
        assert r["mean_difference"] == pytest.approx(np.mean(b - a), rel=1e-12, abs=1e-15)
        assert r["wilcoxon"] == stats.wilcoxon((b - a).tolist())
        assert r["interval"] == stats.bootstrap_mean((b - a).tolist())
        assert r["interval"]["low"] <= r["mean_difference"] <= r["interval"]["high"] or n < 3
    with pytest.raises(ValueError, match="differ in length"):
        stats.paired([1.0], [1.0, 2.0])


def test_bootstrap_mean():
    r = stats.bootstrap_mean([40.0, 40.0, 40.0])
    assert (r["low"], r["high"], r["resamples"], r["undefined_resamples"]) == (40.0, 40.0, 1000, 0)
    rng = np.random.default_rng(3)
    values = rng.normal(50, 10, 200).tolist()
    r = stats.bootstrap_mean(values)
    # The percentile interval of a mean of 200 normal values: about mean +- 1.96 sd / sqrt(n).
    half = 1.96 * np.std(values) / math.sqrt(len(values))
    assert r["low"] == pytest.approx(np.mean(values) - half, abs=0.4 * half)
    assert r["high"] == pytest.approx(np.mean(values) + half, abs=0.4 * half)
    assert stats.bootstrap_mean(values, resamples=200, seed=9) == stats.bootstrap_mean(values, resamples=200, seed=9)
    assert stats.bootstrap_mean([])["undefined"] == "no_items"


# Holm, McNemar, majority ---------------------------------------------------------------------


def test_holm_equals_statsmodels(monkeypatch):
    # multipletests runs gc.collect() on every call (0.15 s each with SciPy and pandas loaded);
    # it frees memory and changes no result.
    import gc

    monkeypatch.setattr(gc, "collect", lambda *args: 0)
    rng = np.random.default_rng(34)
    for case in range(300):
        m = int(rng.integers(0, 25))
        p = rng.choice([rng.uniform(0, 1), rng.uniform(0, 0.05), 1.0, 0.0], m).tolist() if case % 3 == 0 else rng.uniform(0, 0.2, m).tolist()
        if case % 4 == 0 and m:
            p[int(rng.integers(0, m))] = p[0]  # ties
        with_none = [None if rng.random() < 0.2 else x for x in p]
        got = stats.holm(with_none)
        present = [x for x in with_none if x is not None]
        assert [g is None for g in got] == [x is None for x in with_none]
        if present:
            expected = multipletests(present, method="holm")[1].tolist()
            assert [g for g in got if g is not None] == expected, case  # the same bits
    with pytest.raises(ValueError, match="p_values: p-value 0 is 1.5"):
        stats.holm([1.5])


def exact_mcnemar(b, c):
    """min(1, 2 P(X <= min(b, c))), X ~ Binomial(b + c, 1/2), as an exact fraction."""
    n, coefficient, total = b + c, 1, 0
    for i in range(min(b, c) + 1):
        if i:
            coefficient = coefficient * (n - i + 1) // i
        total += coefficient
    return min(Fraction(2 * total, 2**n), 1)


def test_mcnemar_equals_statsmodels():
    rng = np.random.default_rng(3636)
    cases = [(0, 0), (0, 1), (1, 1), (0, 6), (5, 5), (3, 30), (250, 310), (1000, 1150), (4000, 3800)]
    cases += [tuple(int(x) for x in rng.integers(0, 80, 2)) for _ in range(150)]
    cases += [tuple(int(x) for x in rng.integers(0, 3000, 2)) for _ in range(50)]
    for b, c in cases:
        got = stats.mcnemar(b, c)
        exact = float(exact_mcnemar(b, c))
        expected = sm_mcnemar([[7, b], [c, 3]], exact=True).pvalue
        assert got["statistic"] == min(b, c)
        if exact > 1e-300:  # below, subnormal numbers carry fewer digits
            assert got["p_value"] == pytest.approx(exact, rel=1e-14), (b, c)
        if exact > 1e-250:  # SciPy's binom.cdf returns 0 below about 1e-267
            assert got["p_value"] == pytest.approx(expected, rel=1e-12), (b, c)
    assert stats.mcnemar(0, 0)["p_value"] == 1.0
    # Far out (about 1e-296), where SciPy's binom.cdf gives 0: still exact to 1e-14.
    assert stats.mcnemar(14, 1073)["p_value"] == pytest.approx(float(exact_mcnemar(14, 1073)), rel=1e-14)


def test_majority():
    assert stats.majority([True, None, False, True])["verdict"] is True
    r = stats.majority([True, False, None])
    assert (r["verdict"], r["decision"], r["yes"], r["no"], r["abstained"]) == (None, "tie", 1, 1, 1)
    assert stats.majority([None, None])["decision"] == "no_votes"
    assert stats.majority([])["verdict"] is None
    assert stats.majority([False, False, True])["decision"] == "false"
