"""What the tests share: the repository's files, Pinocchio's reference values
(codegen/tests/fixtures, the files the Rust tests read), the tolerance, the robots."""

import json
from pathlib import Path

import numpy as np
import pytest

import dyngen

#: The repository this package is built from.
REPO = Path(__file__).resolve().parents[2]
FIXTURES = REPO / "codegen" / "tests" / "fixtures"
#: Pinocchio's values hold to this relative error (the Rust tests' tolerance).
TOL = 1e-9


def fixture(name):
    """A Pinocchio fixture file, e.g. "panda", "frames/ur5", "floating/solo12"."""
    return json.loads((FIXTURES / f"{name}.json").read_text())


def relative_error(actual, expected):
    """Largest entry-wise difference relative to the largest entry of `expected` (at least 1),
    as tests/testkit's `relative_error`."""
    actual, expected = np.asarray(actual, dtype=float), np.asarray(expected, dtype=float)
    assert actual.shape == expected.shape, f"shape {actual.shape}, expected {expected.shape}"
    return np.abs(actual - expected).max() / max(np.abs(expected).max(), 1.0)


def assert_close(what, actual, expected, tol=TOL):
    error = relative_error(actual, expected)
    assert error <= tol, f"{what}: relative error {error:.3e} > {tol:.0e}"


def stacked(states, key):
    """Field `key` of every fixture state, as one batch-first array."""
    return np.array([s[key] for s in states], dtype=float)


#: The committed descriptions of the fixtures' robots (the same model Pinocchio built).
DESCRIPTIONS = {"panda": REPO / "robots" / "panda.yaml", "ur5": REPO / "robots" / "ur5.yaml"}


@pytest.fixture(scope="session")
def robots():
    return {name: dyngen.Robot.load(path) for name, path in DESCRIPTIONS.items()}
