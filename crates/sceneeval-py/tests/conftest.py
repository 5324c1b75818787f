"""Shared fixtures of the Python package's tests: the repository, the `sceneeval` CLI binary the
tests compare against, and seeded random boxes."""

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]
FIXTURES = REPO / "fixtures"


def _target_dir() -> Path:
    return Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))


@pytest.fixture(scope="session")
def sceneeval_bin() -> Path:
    """The `sceneeval` binary: $SCENEEVAL_BIN, else target/debug/sceneeval (built by
    `cargo test --workspace`, or here with `cargo build -p sceneeval-cli` when missing)."""
    given = os.environ.get("SCENEEVAL_BIN")
    if given:
        return Path(given)
    path = _target_dir() / "debug" / "sceneeval"
    if not path.exists():
        cargo = shutil.which("cargo")
        assert cargo, "the tests compare with the sceneeval CLI: build it with cargo build -p sceneeval-cli"
        subprocess.run([cargo, "build", "-p", "sceneeval-cli"], cwd=REPO, check=True)
    return path


def random_boxes(rng: np.random.Generator, n: int, spread: float = 3.0) -> np.ndarray:
    """`n` boxes (cx, cy, cz, hx, hy, hz, yaw) in a `spread` m cube around the origin."""
    boxes = np.empty((n, 7))
    boxes[:, 0:2] = rng.uniform(-spread, spread, (n, 2))
    boxes[:, 2] = rng.uniform(0.1, 1.5, n)
    boxes[:, 3:6] = rng.uniform(0.05, 0.8, (n, 3))
    boxes[:, 6] = rng.uniform(-np.pi, np.pi, n)
    return boxes


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261124)


ROOM = {
    "floor": [[-4.0, -4.0], [4.0, -4.0], [4.0, 3.0], [0.0, 3.0], [0.0, 4.0], [-4.0, 4.0]],
    "height": 2.6,
    "openings": [
        {"kind": "door", "wall": 0, "along": [1.0, 1.9], "height": [0.0, 2.1]},
        {"kind": "window", "wall": 1, "along": [2.0, 4.0], "height": [0.9, 2.0]},
    ],
}


def scipy_wilcoxon(d):
    """SciPy's Wilcoxon signed-rank test under our rule: differences rounded to 1e-9, zeros
    dropped, the exact distribution when at most 50 non-zero differences remain with untied
    |d|, else the normal approximation with tie and continuity correction. Returns SciPy's
    result, whether it was exact, the number of non-zero differences and of zeros (SciPy is
    imported here, so that only the tests that compare with it need it)."""
    import warnings

    import scipy.stats

    rounded = np.round(np.asarray(d, dtype=float), 9)
    nonzero = rounded[rounded != 0]
    exact = len(nonzero) <= 50 and len(np.unique(np.abs(nonzero))) == len(nonzero)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = scipy.stats.wilcoxon(
            rounded, zero_method="wilcox", correction=True, alternative="two-sided",
            method="exact" if exact else "asymptotic",
        )
    return res, exact, len(nonzero), len(rounded) - len(nonzero)
