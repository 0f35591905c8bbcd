"""Shared helpers of the Python tests: the references are built here from the definitions in
docs/ (never from coopdyn's own results)."""

import numpy as np
import pytest


def skew(v):
    """S(v), with S(v) u = v x u (docs/conventions.md)."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def axis_angle(axis, angle):
    """The rotation matrix of `angle` about the unit `axis` (Rodrigues)."""
    k = skew(np.asarray(axis, dtype=float))
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def quaternion_exp(v):
    """[x, y, z, w] of the rotation by the vector v (angle |v|, docs/conventions.md's order)."""
    angle = np.linalg.norm(v)
    if angle == 0.0:
        return np.array([0.0, 0.0, 0.0, 1.0])
    return np.r_[np.sin(angle / 2) * v / angle, np.cos(angle / 2)]


def quaternion_product(a, b):
    """a (x) b, both [x, y, z, w]."""
    va, wa, vb, wb = a[:3], a[3], b[:3], b[3]
    return np.r_[wa * vb + wb * va + np.cross(va, vb), wa * wb - va @ vb]


def grasp_block(r_i):
    """G_i = [[I, 0], [S(r_i), I]] of (24) (docs/model.md)."""
    g = np.eye(6)
    g[3:, :3] = skew(r_i)
    return g


def grasp_by_hand(r):
    return np.hstack([grasp_block(r[:, i]) for i in range(r.shape[1])])


def constraint_by_hand(r, omega):
    """A and b of the grasp constraint A xdd = b, (11)-(12) (docs/model.md, "Rigid grasp kinematics"): per arm i,
    -a_o + S(r_i) alpha_o + a_i = w x (w x r_i) and -alpha_o + alpha_i = 0, over the stacked
    accelerations [object; arm 1; ...; arm N]."""
    n = r.shape[1]
    A = np.zeros((6 * n, 6 * (n + 1)))
    b = np.zeros(6 * n)
    for i in range(n):
        A[6 * i:6 * i + 3, 0:3] = -np.eye(3)
        A[6 * i:6 * i + 3, 3:6] = skew(r[:, i])
        A[6 * i + 3:6 * i + 6, 3:6] = -np.eye(3)
        A[6 * i:6 * i + 6, 6 * (i + 1):6 * (i + 2)] = np.eye(6)
        b[6 * i:6 * i + 3] = np.cross(omega, np.cross(omega, r[:, i]))
    return A, b


def random_spd(rng, n, scale=1.0):
    a = rng.standard_normal((n, n))
    return scale * (a @ a.T + n * np.eye(n))


def block_diag(*blocks):
    n = sum(b.shape[0] for b in blocks)
    out = np.zeros((n, n))
    k = 0
    for b in blocks:
        out[k:k + b.shape[0], k:k + b.shape[0]] = b
        k += b.shape[0]
    return out


@pytest.fixture
def rng():
    return np.random.default_rng(20261127)
