import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("GYROCOMP_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture
def golden_dir():
    return SOURCE_DIR / "tests" / "golden"


@pytest.fixture
def cli():
    path = os.environ.get("GYROCOMP_CLI", "")
    if not path or not os.path.exists(path):
        pytest.skip("the gyrocomp CLI is not built (GYROCOMP_CLI unset)")
    return path
