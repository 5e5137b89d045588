"""Shared fixtures: colour-science is the independent oracle."""
import warnings

import numpy as np
import pytest

warnings.filterwarnings("ignore")
import colour  # noqa: E402

WL = np.arange(360.0, 831.0)


@pytest.fixture(scope="session")
def wl():
    return WL


@pytest.fixture(scope="session")
def cie_cmfs():
    """colour-science's CIE 1931 2° observer at 1 nm, 360-830 nm, shape (471, 3)."""
    return colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].values


@pytest.fixture(scope="session")
def rng():
    return np.random.default_rng(20261123)
