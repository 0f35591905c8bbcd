"""The grey-box identification (docs/analysis.md, "Identification") against a numpy simulation of
m pdd + d pd + k p = f: a fine fixed-step RK4 of the continuous force, sampled at 1 kHz. The
identified m, d, k must be the simulated ones; simulate_impedance must reproduce the samples."""

import numpy as np
import pytest

import coopdyn


def force(t):
    """A multisine that excites the axis around its resonance (smooth, so cubic interpolation holds)."""
    return 3.0 * np.sin(2 * np.pi * 0.7 * t) + 2.0 * np.sin(2 * np.pi * 2.3 * t + 0.4) + np.sin(2 * np.pi * 5.1 * t)


def simulate(m, d, k, duration=4.0, period=1e-3, substeps=20, p0=0.01, v0=-0.02):
    """RK4 with `substeps` steps per sample on the continuous force."""
    h = period / substeps
    n = int(round(duration / period))
    p, v = p0, v0
    out = np.empty(n)

    def accel(t, p_, v_):
        return (force(t) - d * v_ - k * p_) / m

    t = 0.0
    for i in range(n):
        out[i] = p
        for _ in range(substeps):
            k1p, k1v = v, accel(t, p, v)
            k2p, k2v = v + 0.5 * h * k1v, accel(t + 0.5 * h, p + 0.5 * h * k1p, v + 0.5 * h * k1v)
            k3p, k3v = v + 0.5 * h * k2v, accel(t + 0.5 * h, p + 0.5 * h * k2p, v + 0.5 * h * k2v)
            k4p, k4v = v + h * k3v, accel(t + h, p + h * k3p, v + h * k3v)
            p += h / 6 * (k1p + 2 * k2p + 2 * k3p + k4p)
            v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
            t += h
    return out, force(np.arange(n) * period)


def test_identify_impedance_recovers_the_simulated_axis():
    m, d, k = 21.75, 360.0, 600.0  # the paper's beam along x: (56) with two arms (docs/analysis.md)
    p, f = simulate(m, d, k)
    fit = coopdyn.identify_impedance(p, f, 1e-3)
    assert fit.converged
    assert fit.mass == pytest.approx(m, rel=1e-5)
    assert fit.damping == pytest.approx(d, rel=1e-5)
    assert fit.stiffness == pytest.approx(k, rel=1e-5)
    assert fit.initial_position == pytest.approx(0.01, rel=1e-5)
    assert fit.initial_velocity == pytest.approx(-0.02, rel=1e-4)
    # simulate_impedance reproduces the samples of the fine RK4.
    again = coopdyn.simulate_impedance(coopdyn.ImpedanceParameters(m, d, k), 0.01, -0.02, f, 1e-3)
    np.testing.assert_allclose(again, p, rtol=0, atol=1e-8 * np.abs(p).max())


def test_identify_diagonal_impedance_and_errors():
    rows = [(21.75, 360.0, 600.0), (4.255, 20.0, 100.0)]
    displacement = np.zeros((6, 4000))
    wrench = np.zeros((6, 4000))
    for axis, (m, d, k) in zip((0, 5), rows):
        displacement[axis], wrench[axis] = simulate(m, d, k)
    fit = coopdyn.identify_diagonal_impedance(displacement, wrench, 1e-3,
                                              axes=[True, False, False, False, False, True])
    assert fit.identified == [True, False, False, False, False, True]
    np.testing.assert_allclose(fit.inertia[[0, 5]], [21.75, 4.255], rtol=1e-5)
    np.testing.assert_allclose(fit.stiffness[[0, 5]], [600.0, 100.0], rtol=1e-5)
    np.testing.assert_allclose(np.diag(fit.matrices().damping)[[0, 5]], [360.0, 20.0], rtol=1e-5)
    with pytest.raises(coopdyn.InvalidArgument) as error:
        coopdyn.identify_impedance(np.zeros(100), np.zeros(99), 1e-3)
    assert error.value.parameter == "force"
    with pytest.raises(coopdyn.InvalidArgument) as error:
        coopdyn.identify_impedance(np.zeros(100), np.zeros(100), 1e-3)  # no excitation
    assert error.value.parameter in ("force", "position")
