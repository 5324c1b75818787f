"""Type stubs of ``sceneeval.stats`` (the extension's submodule ``sceneeval._sceneeval.stats``).

The docstrings here are the functions' runtime docstrings (a test checks that they agree).
Results are plain dicts; a statistic that is undefined for the input is ``None`` with
``undefined`` (a code: ``no_items``, ``one_class``, ``too_few_raters``, ``too_few_differences``,
``every_resample``) and ``reason`` (a sentence).
"""

from typing import Any, Dict, List, Optional, Sequence, Union

Label = Union[bool, int, str, None]

def cohen_kappa(
    a: Sequence[Label],
    b: Sequence[Label],
    *,
    bootstrap: Optional[int] = None,
    seed: int = 20261121,
    level: float = 0.95,
) -> Dict[str, Any]:
    """Cohen's kappa of two raters on the same items, equal to scikit-learn's cohen_kappa_score(a, b) (unweighted). a and b hold one label per item: bool, int or str (one kind), None where that rater gave no verdict (the item is left out and counted in left_out). Returns a dict: n (items both judged), left_out, labels (the categories, sorted), confusion (rows: a's label, columns: b's), agreement, expected_agreement, kappa (None when undefined: no items, or both raters used one and the same class, with undefined and reason), and with bootstrap=N the percentile interval of kappa over N resamples of the items (seeded; resamples where kappa is undefined are left out and counted in undefined_resamples)."""

def fleiss_kappa(table: Sequence[Sequence[int]]) -> Dict[str, Any]:
    """Fleiss' kappa of several raters, equal to statsmodels' fleiss_kappa(table, method='fleiss'). table: items x categories counts (how many raters chose each category for the item), the same number of ratings on every item. Returns a dict: items, raters, agreement (mean observed agreement), expected_agreement, kappa (None when undefined: no items, fewer than two raters, or every rating in one category, with undefined and reason)."""

def bootstrap_mean(
    values: Sequence[float],
    *,
    resamples: int = 1000,
    seed: int = 20261121,
    level: float = 0.95,
) -> Dict[str, Any]:
    """The percentile bootstrap interval of the mean of values (one per item): resamples of the items drawn with replacement from the seeded Xoshiro256++ generator, quantiles (1 - level)/2 and (1 + level)/2 interpolated linearly. Returns a dict: low, high (None without values, with undefined and reason), level, resamples, undefined_resamples."""

def wilcoxon(differences: Sequence[float]) -> Dict[str, Any]:
    """The two-sided Wilcoxon signed-rank test of paired differences (b - a per item): differences rounded to 1e-9, zeros dropped and counted, average ranks of |d|; the exact distribution with at most 50 non-zero differences and no ties among their |d|, else the normal approximation with tie and continuity correction. Equal to SciPy's wilcoxon(np.round(d, 9), zero_method='wilcox', correction=True, method='exact' or 'asymptotic'). Returns a dict: statistic (min(R+, R-)), r_plus, r_minus, n (non-zero differences), zeros, ties, method ('exact', 'normal' or 'none'), z (normal only), p_value (None with fewer than two non-zero differences, with undefined and reason)."""

def paired(
    a: Sequence[float],
    b: Sequence[float],
    *,
    resamples: int = 1000,
    seed: int = 20261121,
    level: float = 0.95,
) -> Dict[str, Any]:
    """A paired comparison of b with a on the same items (`a[i]` and `b[i]` the same item): n, the mean difference b - a, its percentile bootstrap interval (pairs resampled, seeded) and the Wilcoxon signed-rank test of the differences. Returns a dict: n, mean_difference (None without pairs), interval (as bootstrap_mean gives it) and wilcoxon (as wilcoxon gives it)."""

def holm(p_values: Sequence[Optional[float]]) -> List[Optional[float]]:
    """Holm's step-down adjustment, equal to statsmodels' `multipletests(p, method='holm')[1]`: the i-th smallest (from 0) of the m p-values becomes min(1, max over j <= i of (m - j) p_(j)), returned in the input's order. None entries stay None and are not counted in m."""

def mcnemar(b: int, c: int) -> Dict[str, Any]:
    """McNemar's exact test on the discordant counts of paired binary outcomes: b items true in the first and false in the second, c the other way round. The two-sided p-value is min(1, 2 P(X <= min(b, c))) for X ~ Binomial(b + c, 1/2), equal to statsmodels' mcnemar([[a, b], [c, d]], exact=True).pvalue; 1 without discordant items. Returns a dict: b, c, statistic (min(b, c)), p_value."""

def majority(votes: Sequence[Optional[bool]]) -> Dict[str, Any]:
    """The majority of verdicts (True, False or None for no verdict; None ignored). Returns a dict: verdict (True, False, or None for a tie or without votes), decision ('true', 'false', 'tie' or 'no_votes'), yes, no, abstained."""
