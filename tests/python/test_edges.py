"""Records built from arrays are held to the bounds every record file is read
within (issue 56): a time step of at least 1e-6 s, a duration of at most
1e5 s, accelerations within 100 g, each refused naming the argument."""
import numpy as np
import pytest

import rocking


def test_a_record_step_below_a_microsecond_is_refused_naming_dt():
    with pytest.raises(ValueError, match=r"^Record: dt 1e-300: must be at least 1e-06 s"):
        rocking.Record(np.ones(100) * 0.1, 1e-300)


def test_a_record_longer_than_the_bound_is_refused_naming_dt():
    with pytest.raises(ValueError, match=r"^Record: dt 10000: .*at most 100000 s"):
        rocking.Record(np.ones(100) * 0.1, 1e4)


def test_accelerations_beyond_100_g_are_refused_naming_the_sample():
    with pytest.raises(ValueError, match=r"^Record: acc\[0\] = 1e\+308 g: beyond 100 g"):
        rocking.Record(np.ones(100) * 1e308, 0.01)
    with pytest.raises(ValueError, match=r"^Record: acc\[3\] = 2000 m/s2: beyond 100 g"):
        rocking.Record(np.array([0.0, 1.0, 2.0, 2000.0]), 0.01, units="m/s2")


def test_a_record_within_the_bounds_is_kept_with_its_measures():
    r = rocking.Record(np.ones(100) * 0.1, 1e-6)
    assert r.dt == pytest.approx(1e-6, rel=1e-12)
