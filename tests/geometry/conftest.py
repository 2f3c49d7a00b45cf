"""Fixtures of the geometry tests."""

from pathlib import Path

import pytest

from tribobem.data import topography_dir as _topography_dir

#: Values of tribobem/data/topographies/README.md: grid, size (m), rms height after
#: detrend("center") (m), rms slope (-).
TOPOGRAPHY_FILES = {
    "example_ps.tiff": ((512, 512), (1e-6, 1e-6), 3.933e-9, 0.385),
    "di-3.di": ((256, 256), (10e-6, 10e-6), 226.4e-9, 0.207),
    "spot_1-1000nm.ibw": ((256, 256), (20.08e-6, 20.08e-6), 89.45e-9, 0.0625),
    "plu-1.plu": ((768, 576), (1274.9e-6, 956.2e-6), 2.834e-6, 0.00898),
}

#: Values of the same README after the default detrend("height") (the least-squares plane): rms
#: height (m), rms slope (-), correlation length (m; the radial ACF's 10 % level).
TOPOGRAPHY_PLANE = {
    "example_ps.tiff": (3.933e-9, 0.385, 40.00e-9),
    "di-3.di": (35.22e-9, 0.1923, 1.511e-6),
    "spot_1-1000nm.ibw": (9.552e-9, 0.06069, 945.2e-9),
    "plu-1.plu": (18.28e-9, 0.004626, 185.9e-6),
}


@pytest.fixture(scope="session")
def topography_dir() -> Path:
    """Folder of the measured example topographies: the copy shipped with tribobem
    (:func:`tribobem.data.topography_dir`; ``$TRIBOBEM_DATA_DIR`` replaces it).  No skip: the
    files are package data, always there."""
    return _topography_dir()
