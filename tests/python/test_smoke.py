import numpy as np

import quatnav


def test_version_and_filters_exist():
    assert quatnav.__version__
    for cls in (quatnav.QuaternionEKF, quatnav.EulerEKF):
        for dtype in (np.float64, np.float32):
            f = cls(dtype=dtype)
            assert not f.initialized
