import os

import numpy as np
import pytest

import quatnav


def test_version_and_filters_exist():
    assert quatnav.__version__
    for cls in (quatnav.QuaternionEKF, quatnav.EulerEKF):
        for dtype in (np.float64, np.float32):
            f = cls(dtype=dtype)
            assert not f.initialized


def test_command_line_turns_huge_pages_off_unless_told(monkeypatch, capsys):
    mm = pytest.importorskip("numpy._core.multiarray")
    from quatnav.cli import main
    before = mm._set_madvise_hugepage(True)  # returns the previous setting
    try:
        monkeypatch.delenv("NUMPY_MADVISE_HUGEPAGE", raising=False)
        monkeypatch.delenv("ARROW_DEFAULT_MEMORY_POOL", raising=False)
        assert main(["--version"]) == 0
        assert mm._set_madvise_hugepage(True) is False
        assert os.environ["ARROW_DEFAULT_MEMORY_POOL"] == "system"
        monkeypatch.setenv("NUMPY_MADVISE_HUGEPAGE", "1")
        monkeypatch.setenv("ARROW_DEFAULT_MEMORY_POOL", "mimalloc")
        assert main(["--version"]) == 0
        assert mm._set_madvise_hugepage(True) is True
        assert os.environ["ARROW_DEFAULT_MEMORY_POOL"] == "mimalloc"
    finally:
        mm._set_madvise_hugepage(before)
