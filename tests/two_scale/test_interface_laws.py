"""The tabulated interface law: monotone, continuous, invertible, and the micro tables behind it."""

import numpy as np
import pytest

from tribobem.elasticity import periodic_operator
from tribobem.geometry.rough import gaussian_surface
from tribobem.grid import Grid
from tribobem.materials import ContactPair, Material
from tribobem.solvers.normal import solve_normal
from tribobem.two_scale.laws import NormalInterfaceLaw
from tribobem.two_scale.micro import MicroWindows, interface_law

PAIR = ContactPair(Material(410e9, 0.14), Material(130e9, 0.28))


def law_of(ps=None):
    ps = np.geomspace(1e5, 1e9, 12) if ps is None else ps
    gs = 3e-9 - 0.4e-9 * np.log(ps / 1e5)
    return NormalInterfaceLaw(ps, gs, 4e-9, np.linspace(1e-4, 0.1, ps.size), ps * 1e3, np.zeros(ps.size),
                              np.zeros(ps.size))


def test_the_law_is_monotone_continuous_and_invertible():
    law = law_of()
    p = np.concatenate([[0.0], np.geomspace(1e2, 5e9, 400)])
    g = law.gap(p)
    assert g[0] == pytest.approx(4e-9)
    assert np.all(np.diff(g) < 0)
    # continuous at the table's first pressure (Hertz branch meets the table)
    assert law.gap(np.array([1e5 * (1 - 1e-9)]))[0] == pytest.approx(law.gap(np.array([1e5]))[0], rel=1e-8)
    # the inverse law
    assert np.allclose(law.pressure(g[1:]), p[1:], rtol=2e-3)
    assert law.pressure(np.array([4.1e-9]))[0] == 0.0
    # compliance = -dg/dp (central differences, on the table, the Hertz branch and beyond it)
    for p0 in (3e4, 2e6, 3e8, 3e9):
        dp = 1e-5 * p0
        num = -(law.gap(np.array([p0 + dp]))[0] - law.gap(np.array([p0 - dp]))[0]) / (2 * dp)
        assert law.compliance(np.array([p0]))[0] == pytest.approx(num, rel=1e-4)
    assert law.beyond_table(np.array([2e9])) and not law.beyond_table(np.array([1e9]))


def test_a_table_that_is_not_a_law_is_refused():
    ps = np.geomspace(1e5, 1e9, 5)
    with pytest.raises(ValueError, match="decrease"):
        NormalInterfaceLaw(ps, np.array([1, 2, 3, 4, 5.0]) * 1e-9, 6e-9, np.zeros(5), ps, np.zeros(5), np.zeros(5))
    with pytest.raises(ValueError, match="increasing"):
        NormalInterfaceLaw(ps[::-1], np.arange(5.0)[::-1], 6.0, np.zeros(5), ps, np.zeros(5), np.zeros(5))
    assert NormalInterfaceLaw.from_dict(law_of().as_dict()).gap(np.array([1e7])) == pytest.approx(
        law_of().gap(np.array([1e7])))


def windows(k=2, n=64):
    grid = Grid(n, n, 1e-6, 1e-6, periodic=True)
    gaps = []
    for seed in range(k):
        z = gaussian_surface(grid, 1.5e-9, 50e-9, seed=seed)
        gaps.append(z.max() - z)
    return MicroWindows(grid, PAIR, gaps)


def test_the_table_is_the_windows_mean_gap_and_the_realisations_average(tmp_path):
    w = windows()
    ps = np.geomspace(1e6, 1e8, 5)
    law = interface_law(w, ps, cache=False)
    # an independent solve of each window at the middle pressure: the mean gap of its mean planes
    op = periodic_operator(w.grid, PAIR)
    direct = [solve_normal(op, g, force=ps[2] * w.grid.lx * w.grid.ly, tol=1e-8).mean_gap for g in w.gaps]
    assert law.gaps[2] == pytest.approx(np.mean(direct), rel=1e-5)
    assert law.gap_spread[2] == pytest.approx(np.std(direct), rel=1e-3)
    assert law.touch_gap == pytest.approx(np.mean([g.mean() for g in w.gaps]))
    assert law.realisations == 2 and law.converged


def test_tables_are_cached_and_dask_gives_the_same_numbers(tmp_path):
    w = windows()
    ps = np.geomspace(1e6, 1e8, 5)
    first = interface_law(w, ps, cache_dir=tmp_path)
    assert first.info["cached"] == 0 and len(list(tmp_path.glob("*.json"))) == 2
    again = interface_law(w, ps, cache_dir=tmp_path, scheduler="threads")
    assert again.info["cached"] == 2
    np.testing.assert_array_equal(again.gaps, first.gaps)
    # another pressure ladder is another table
    other = interface_law(w, ps * 1.01, cache_dir=tmp_path)
    assert other.info["cached"] == 0


def test_a_table_being_computed_elsewhere_is_waited_for_not_computed_twice(tmp_path):
    import threading
    import time

    from tribobem.two_scale.micro import _cached_call

    calls = []

    def slow(x):
        calls.append(x)
        time.sleep(1.0)
        return {"value": x}

    out = []
    threads = [threading.Thread(target=lambda: out.append(_cached_call(slow, {"x": 3}, "k", str(tmp_path))))
               for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert calls == [3] and sorted(o["cached"] for o in out) == [False, True, True]
    assert all(o["value"] == 3 for o in out) and not list(tmp_path.glob("*.lock"))


def test_a_lock_left_by_a_killed_run_is_taken_over(tmp_path):
    import socket
    import subprocess
    import sys
    import time

    from tribobem.two_scale.micro import _cached_call

    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    (tmp_path / "k.lock").write_text(f"{socket.gethostname()} {int(dead.stdout)}")
    t = time.perf_counter()
    out = _cached_call(lambda x: {"value": x}, {"x": 5}, "k", str(tmp_path))
    # computed at once, not after the hour a lock of unknown holder is waited for
    assert out["value"] == 5 and not out["cached"] and time.perf_counter() - t < 5.0
    assert not (tmp_path / "k.lock").exists()
