"""open_chain against the closed form of tests/oracles.py along a sweep of all its inputs."""

import numpy as np
import pytest
from hypothesis import given, strategies as st

import planar
from planar.mechanisms import open_chain
from tests.oracles import open_chain as chain_oracle
from tests.test_mechanisms_four_bar import FAST, SWEEPS, assert_close

length = st.floats(0.2, 5.0)
value = st.floats(-3.0, 3.0, allow_subnormal=False)


@SWEEPS
@given(data=st.data(), n=st.integers(1, 4), relative=st.booleans())
def test_matches_closed_form(data, n, relative):
    r = data.draw(st.lists(length, min_size=n, max_size=n))
    start, turn, w, a = (np.array(data.draw(st.lists(value, min_size=n, max_size=n))) for _ in range(4))
    values = start + np.linspace(0, 1, 15)[:, None] * turn  # every input moves at once
    m = open_chain(r, start=start, driver="relative" if relative else "absolute")
    res = m.sweep(values, velocity=w, acceleration=a, **FAST)
    assert res.ok.all()
    # relative inputs add up to absolute angles, and so do their rates
    to_abs = (lambda x: np.cumsum(x, axis=-1)) if relative else (lambda x: x)
    th, wa, aa = to_abs(values), to_abs(w), to_abs(a)
    o = chain_oracle(r, th, wa, aa)
    L = sum(r)
    for k in range(n):
        assert_close(np.angle(np.exp(1j * (res.angle(f"link{k + 1}") - th[:, k]))), 0.0, 1.0, 1e-9, f"link{k + 1}")
    assert_close(res.position("tip"), o["tip"], L, 1e-9, "tip")
    assert_close(res.velocity("tip"), o["tip_vel"], L * np.abs(wa).max() + 1e-300, 1e-8, "tip velocity")
    assert_close(res.acceleration("tip"), o["tip_acc"], L * (np.abs(aa).max() + np.abs(wa).max() ** 2) + 1e-300,
                 1e-8, "tip acceleration")


@pytest.mark.parametrize("kw, match", [(dict(lengths=[]), "lengths"), (dict(lengths=[1, -1]), r"lengths\[1\]"),
                                       (dict(lengths=[1, 2], start=[0.0]), "start"),
                                       (dict(driver="tip"), "driver")])
def test_bad_arguments_are_refused_by_name(kw, match):
    with pytest.raises(planar.ModelError, match=match):
        open_chain(**kw)
