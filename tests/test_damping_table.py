"""The damping tables shipped with the package (rigid/engine/damping_tables.npz) are the ones the
source computes: a run with materials reads them instead of spending ~0.5 s a scheme at start-up."""
import numpy as np
import pytest

from rigid.engine import damping_table as dt


def test_the_shipped_tables_were_made_by_this_source():
    with np.load(dt.SHIPPED) as tables:
        assert str(tables["fingerprint"]) == dt._fingerprint(), \
            "rigid/engine/damping_table.py changed: run python -m rigid.engine.damping_table"
        assert set(tables.files) == {"fingerprint", *dt.SCHEMES}


@pytest.mark.parametrize("scheme", dt.SCHEMES)
def test_the_shipped_table_is_the_computed_one(scheme):
    computed = dt.compute_damping_table(scheme)
    assert computed.shape == (dt.NUM_E, dt.NUM_H, dt.NUM_B)
    with np.load(dt.SHIPPED) as tables:
        np.testing.assert_allclose(tables[scheme], computed, rtol=1e-12, atol=0)  # (bit for bit here; another libm may differ in an ulp)
    dt.damping_table.cache_clear()
    assert np.array_equal(dt.damping_table(scheme), np.load(dt.SHIPPED)[scheme])


def test_a_stale_copy_is_not_used(monkeypatch):
    calls = []
    monkeypatch.setattr(dt, "_fingerprint", lambda: "another source")
    monkeypatch.setattr(dt, "compute_damping_table", lambda scheme: calls.append(scheme) or np.zeros(1))
    dt.damping_table.cache_clear()
    try:
        assert dt.damping_table("euler").tolist() == [0.0] and calls == ["euler"]
    finally:
        dt.damping_table.cache_clear()
