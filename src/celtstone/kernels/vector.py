"""Three-vector algebra on tuples ``(x, y, z)``; 3x3 matrices are 9-tuples, row-major."""

from __future__ import annotations

import math

from celtstone.kernels._jit import kernel

Vec = tuple[float, float, float]
Mat = tuple[float, float, float, float, float, float, float, float, float]

NAN3: Vec = (math.nan, math.nan, math.nan)  # what a kernel returns for a vector it cannot give


@kernel
def cross(a: Vec, b: Vec) -> Vec:
    """Cross product a x b."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@kernel
def dot(a: Vec, b: Vec) -> float:
    """Scalar product a . b."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@kernel
def regularised_norm(a: Vec, floor: float) -> float:
    """sqrt(|a|² + floor²): |a| kept away from zero by ``floor`` (same unit as a)."""
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + floor * floor)


@kernel
def add(a: Vec, b: Vec) -> Vec:
    """Sum a + b."""
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@kernel
def sub(a: Vec, b: Vec) -> Vec:
    """Difference a - b."""
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@kernel
def scale(s: float, a: Vec) -> Vec:
    """Product s a of a scalar and a vector."""
    return (s * a[0], s * a[1], s * a[2])


@kernel
def matvec(m: Mat, v: Vec) -> Vec:
    """Matrix-vector product M v, M row-major."""
    return (
        m[0] * v[0] + m[1] * v[1] + m[2] * v[2],
        m[3] * v[0] + m[4] * v[1] + m[5] * v[2],
        m[6] * v[0] + m[7] * v[1] + m[8] * v[2],
    )


@kernel
def add_outer(m: Mat, s: float, u: Vec, v: Vec) -> Mat:
    """M + s u v^T."""
    return (
        m[0] + s * u[0] * v[0],
        m[1] + s * u[0] * v[1],
        m[2] + s * u[0] * v[2],
        m[3] + s * u[1] * v[0],
        m[4] + s * u[1] * v[1],
        m[5] + s * u[1] * v[2],
        m[6] + s * u[2] * v[0],
        m[7] + s * u[2] * v[1],
        m[8] + s * u[2] * v[2],
    )


@kernel
def solve3(m: Mat, b: Vec) -> tuple[Vec, float]:
    """Solve M x = b by the adjugate; returns (x, det M). x is zero when det M == 0."""
    c00 = m[4] * m[8] - m[5] * m[7]
    c01 = m[5] * m[6] - m[3] * m[8]
    c02 = m[3] * m[7] - m[4] * m[6]
    det = m[0] * c00 + m[1] * c01 + m[2] * c02
    if det == 0.0:
        return (0.0, 0.0, 0.0), det
    c10 = m[2] * m[7] - m[1] * m[8]
    c11 = m[0] * m[8] - m[2] * m[6]
    c12 = m[1] * m[6] - m[0] * m[7]
    c20 = m[1] * m[5] - m[2] * m[4]
    c21 = m[2] * m[3] - m[0] * m[5]
    c22 = m[0] * m[4] - m[1] * m[3]
    inv = 1.0 / det
    return (
        (c00 * b[0] + c10 * b[1] + c20 * b[2]) * inv,
        (c01 * b[0] + c11 * b[1] + c21 * b[2]) * inv,
        (c02 * b[0] + c12 * b[1] + c22 * b[2]) * inv,
    ), det


@kernel
def rotate(q: tuple[float, float, float, float], v: Vec) -> Vec:
    """Rotate v by the unit quaternion q = (w, x, y, z): R(q) v."""
    w, x, y, z = q
    # t = 2 q_vec x v ; v' = v + w t + q_vec x t
    tx = 2.0 * (y * v[2] - z * v[1])
    ty = 2.0 * (z * v[0] - x * v[2])
    tz = 2.0 * (x * v[1] - y * v[0])
    return (
        v[0] + w * tx + (y * tz - z * ty),
        v[1] + w * ty + (z * tx - x * tz),
        v[2] + w * tz + (x * ty - y * tx),
    )


@kernel
def tangent_basis(n: Vec) -> tuple[Vec, Vec, Vec]:
    """(u, t1, t2): u = n/|n| and an orthonormal basis t1, t2 of the plane ⊥ n, t1 × t2 = u.

    t1 = u × e_k / |u × e_k|, e_k the body axis of the smallest |u_k| (the first on a tie);
    t2 = u × t1. At n = e3: t1 = e2, t2 = −e1.
    """
    norm = math.sqrt(dot(n, n))
    u = (n[0] / norm, n[1] / norm, n[2] / norm)
    k = 0
    if abs(u[1]) < abs(u[k]):
        k = 1
    if abs(u[2]) < abs(u[k]):
        k = 2
    axis = (1.0 if k == 0 else 0.0, 1.0 if k == 1 else 0.0, 1.0 if k == 2 else 0.0)
    t1 = cross(u, axis)
    length = math.sqrt(dot(t1, t1))
    t1 = (t1[0] / length, t1[1] / length, t1[2] / length)
    return u, t1, cross(u, t1)
