"""solve_qp against a brute-force KKT solve in numpy: every subset of rows is tried as the active
set, the KKT system solved, and the feasible point with non-negative multipliers kept (the
minimiser of a strictly convex QP is unique, and so are its multipliers when the active rows are
independent)."""

import itertools

import numpy as np
import pytest

import coopdyn


def brute_force_qp(H, g, C, d, tol=1e-9):
    n, m = H.shape[0], C.shape[0]
    best = None
    for size in range(0, min(n, m) + 1):
        for active in itertools.combinations(range(m), size):
            A = C[list(active)]
            kkt = np.zeros((n + size, n + size))
            kkt[:n, :n] = H
            kkt[:n, n:] = A.T
            kkt[n:, :n] = A
            rhs = np.concatenate([-g, d[list(active)]])
            try:
                sol = np.linalg.solve(kkt, rhs)
            except np.linalg.LinAlgError:
                continue
            x, lam = sol[:n], sol[n:]
            if np.all(C @ x <= d + tol * (1 + np.abs(d))) and np.all(lam >= -tol):
                multipliers = np.zeros(m)
                multipliers[list(active)] = lam
                objective = 0.5 * x @ H @ x + g @ x
                if best is None or objective < best[2] - 1e-12:
                    best = (x, multipliers, objective)
    return best


@pytest.mark.parametrize("n,m", [(2, 3), (3, 5), (4, 6)])
def test_solve_qp_matches_brute_force_kkt(rng, n, m):
    solved = 0
    for _ in range(20):
        a = rng.standard_normal((n, n))
        H = a @ a.T + 0.5 * np.eye(n)
        g = rng.standard_normal(n)
        C = rng.standard_normal((m, n))
        d = rng.standard_normal(m) + 0.5
        reference = brute_force_qp(H, g, C, d)
        result = coopdyn.solve_qp(H, g, C, d)
        if reference is None:
            assert result.status == coopdyn.QpStatus.infeasible
            continue
        solved += 1
        assert result.status == coopdyn.QpStatus.solved
        np.testing.assert_allclose(result.x, reference[0], rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(result.multipliers, reference[1], rtol=1e-8, atol=1e-8)
        assert result.objective == pytest.approx(reference[2], rel=1e-9, abs=1e-9)
        assert result.iterations >= 0
        assert result.x.flags.owndata or result.x.base is not None  # a numpy array of its own
    assert solved > 0


def test_solve_qp_statuses():
    # x >= 1 and x <= -1: no feasible point.
    infeasible = coopdyn.solve_qp([[1.0]], [0.0], [[-1.0], [1.0]], [-1.0, -1.0])
    assert infeasible.status == coopdyn.QpStatus.infeasible
    indefinite = coopdyn.solve_qp([[1.0, 0.0], [0.0, -1.0]], [0.0, 0.0], np.zeros((0, 2)), np.zeros(0))
    assert indefinite.status == coopdyn.QpStatus.not_positive_definite
    # Without rows: the unconstrained minimum -H^-1 g.
    free = coopdyn.solve_qp(np.diag([2.0, 4.0]), [2.0, -4.0], np.zeros((0, 2)), np.zeros(0))
    np.testing.assert_allclose(free.x, [-1.0, 1.0])
    assert free.multipliers.shape == (0,)
    assert {s.name for s in coopdyn.QpStatus.__members__.values()} == {
        "solved", "infeasible", "iteration_limit", "not_positive_definite"}


def test_solve_qp_refuses_wrong_shapes():
    H = np.eye(3)
    with pytest.raises(coopdyn.InvalidArgument) as error:
        coopdyn.solve_qp(H, np.zeros(2), np.zeros((1, 3)), np.zeros(1))
    assert error.value.parameter == "g" and "(3,)" in str(error.value)
    with pytest.raises(ValueError) as error:
        coopdyn.solve_qp(H, np.zeros(3), np.zeros((1, 2)), np.zeros(1))
    assert error.value.parameter == "C" and "(m, 3)" in str(error.value)
    with pytest.raises(ValueError) as error:
        coopdyn.solve_qp(H, np.zeros(3), np.zeros((2, 3)), np.zeros(1))
    assert error.value.parameter == "d"
    with pytest.raises(ValueError) as error:
        coopdyn.solve_qp(np.zeros((2, 3)), np.zeros(3), np.zeros((2, 3)), np.zeros(2))
    assert error.value.parameter == "H"
    with pytest.raises(ValueError):
        coopdyn.solve_qp(H, [np.nan, 0, 0], np.zeros((1, 3)), np.zeros(1))


def test_solve_qp_releases_the_gil():
    """A Python thread keeps counting while solve_qp works on a large problem (~0.2 s): with the GIL
    held through the call it could count only in the switch intervals around it (5 ms each)."""
    import threading
    import time

    rng = np.random.default_rng(0)
    n, m = 300, 900
    H, g = np.eye(n), -1e3 * rng.standard_normal(n)
    C, d = rng.standard_normal((m, n)), rng.uniform(0.5, 1.0, m)
    counter = [0]
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            counter[0] += 1

    thread = threading.Thread(target=spin)
    thread.start()
    try:
        time.sleep(0.05)
        start_count, start = counter[0], time.perf_counter()
        time.sleep(0.01)  # the spinner's rate while the main thread sleeps (GIL free)
        rate = (counter[0] - start_count) / (time.perf_counter() - start)
        before, start = counter[0], time.perf_counter()
        result = coopdyn.solve_qp(H, g, C, d)
        elapsed = time.perf_counter() - start
        counted = counter[0] - before
    finally:
        stop.set()
        thread.join()
    assert result.status == coopdyn.QpStatus.solved
    assert elapsed > 0.05, "the problem solved too fast to tell"
    # Held GIL: at most about two switch intervals (10 ms) of counting. Released: most of the call.
    assert counted > 4 * 0.010 * rate, (counted, rate, elapsed)
