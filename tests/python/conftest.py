import os
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DATA = Path(os.environ.get("QUATNAV_DATA", REPO.parent / "shared" / "data"))


@pytest.fixture(scope="session")
def data_dir():
    """The shared data folder; tests that need it skip when it is absent."""
    if not DATA.is_dir():
        pytest.skip(f"shared data not found at {DATA} (set QUATNAV_DATA)")
    return DATA
