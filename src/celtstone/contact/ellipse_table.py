"""The table of the fast elliptic friction law: the exact elliptic law over the exact disk law.

``python -m celtstone.contact.ellipse_table`` writes the kernel's table
``kernels/friction_ellipse_table.npz`` (``kernels.friction_ellipse.TABLE_FILE``): the
ratios (d_par, r_perp, d_M) of ``kernels.friction_ellipse`` at the nodes of a uniform grid
in s = [atan(u/k) + atan(u)]/π, β = [α + atan2(k sin α, cos α)]/2 and q = ln k
(``docs/decisions.md`` §24, "Fast form"), computed with ``contact.ellipse`` (the
elliptic law, the exact entry's ``elliptic_reference`` in ``contact.laws.LAWS``) and
``kernels.friction_exact`` (the disk's closed forms). The ratios correct every law's
disk law alike. The kernel module reads the file at import and fits its B-spline, whose
coefficients the kernels read at run time; after regenerating it with other node counts
or ``ASPECT_MIN``, delete ``src/celtstone/kernels/__pycache__/*.nbi|*.nbc``: numba's cache
keys on the source files, not on those numbers, which it freezes into the compiled code
(§15's caveat).

Nodes where the exact law is not evaluated, in closed form:
- u = 0 (s = 0): F = −f N (C_xx u cos α, C_yy u sin α) + O(u³) with
  C_yy = (k²/2) R_D(0, 1, k²) and C_xx = (3/2) R_F(0, k², 1) − C_yy (the linearised
  slip direction e_θ + (V·e_r) e_r / (Ω_n r) integrated against the Hertz pressure;
  3π/8 each for the disk), so r_par = (C_xx cos²α + C_yy sin²α)/(3π/8),
  r_perp = (C_yy − C_xx) sin α cos α/(3π/8); M = −(3/8) f N A E(e): d_M = 0;
- u = ∞ (s = 1): F = −f N ŝ (d_par = r_perp = 0) and M ≈ −f N (A² cos²α + B² sin²α)/(5 V)
  (first order in A Ω_n/V, ∫ p x² dA = N A²/5), so r_M = cos²α + k² sin²α;
- k = 1: d_par = r_perp = d_M = 0.
"""

from __future__ import annotations

import math
import os
import sys
import tempfile
import time
from collections.abc import Callable
from multiprocessing import Pool
from pathlib import Path

import numpy as np
from scipy import optimize, special

from celtstone.contact.ellipse import elliptic_friction_functions, zero_slip_moment
from celtstone.contact.laws import law_code, unit_speeds
from celtstone.kernels.friction_ellipse import (
    TABLE_ADDRESS,
    TABLE_FILE,
    direction_coordinate,
    elliptic_contact_friction,
    slip_coordinate,
)
from celtstone.kernels.friction_exact import hertz_inside, hertz_outside

__all__ = [
    "ASPECT_MIN",
    "TABLE_FILE",
    "exact_ratios",
    "fast_friction_functions",
    "generate_table",
    "node_coordinates",
    "node_ratios",
    "small_slip_stiffness",
    "write_table",
]

ASPECT_MIN = 0.02  # smallest B/A tabulated; rattleback contacts have 0.05–0.3
SLIP_NODES = 45  # in s = [atan(u/k) + atan(u)]/π, s ∈ [0, 1]
DIRECTION_NODES = 25  # in β = [α + atan2(k sin α, cos α)]/2, β ∈ [0, π/2]
ASPECT_NODES = 11  # in ln k, k ∈ [ASPECT_MIN, 1]
_DISK_FORCE_SLOPE = 3.0 * math.pi / 8.0  # F/(fN u) of the disk at u -> 0


def fast_friction_functions(
    u: float, direction: float, aspect: float, law: str = "pade"
) -> tuple[np.ndarray, float]:
    """The fast form a run uses, in the convention of
    ``contact.ellipse.elliptic_friction_functions``: F/(fN) in the ellipse's axes and
    M/(fNA), for Ω_n > 0, u = |V|/(A|Ω_n|), the slip at ``direction`` [rad] from the
    major axis, ``aspect`` = B/A in [ASPECT_MIN, 1]; ``law``, a name in
    ``contact.laws.LAWS``, names the disk law that the tabulated ratios correct
    (``kernels.friction_ellipse``). Both speeds are at most 1 m/s
    (``contact.laws.unit_speeds``), so no finite u overflows."""
    code = law_code(law)
    slip_speed, spin_rate = unit_speeds(u)
    slip = (slip_speed * math.cos(direction), slip_speed * math.sin(direction), 0.0)
    force, moment = elliptic_contact_friction(
        slip, spin_rate, (0.0, 0.0, 1.0), (1.0, 0.0, 0.0), 1.0, aspect, 0.0,
        code, TABLE_ADDRESS,
    )  # fmt: skip
    return np.array(force[:2]), moment


def node_coordinates(
    slip_nodes: int = SLIP_NODES,
    direction_nodes: int = DIRECTION_NODES,
    aspect_nodes: int = ASPECT_NODES,
    aspect_min: float = ASPECT_MIN,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The grid: s [1], β [rad] and k = B/A [1] at the nodes (k = 1 exactly last)."""
    slips = np.linspace(0.0, 1.0, slip_nodes)
    directions = np.linspace(0.0, 0.5 * math.pi, direction_nodes)
    aspects = np.exp(np.linspace(math.log(aspect_min), 0.0, aspect_nodes))
    aspects[-1] = 1.0
    return slips, directions, aspects


def small_slip_stiffness(aspect: float) -> tuple[float, float]:
    """(C_xx, C_yy): F/(fN) = −(C_xx u cos α, C_yy u sin α) + O(u³) as u -> 0 [1]."""
    k2 = aspect * aspect
    across = 0.5 * k2 * float(special.elliprd(0.0, 1.0, k2))
    along = 1.5 * float(special.elliprf(0.0, k2, 1.0)) - across
    return along, across


def _disk(u: float) -> tuple[float, float]:
    """F/(fN) and M/(fNA) of the exact disk law (magnitudes, > 0)."""
    if u <= 1.0:
        return hertz_inside(u)
    return hertz_outside(1.0 / u)


def exact_ratios(u: float, direction: float, aspect: float) -> tuple[float, float, float]:
    """(d_par, r_perp, d_M) of the exact elliptic law at 0 < u < ∞, α, k [1]."""
    force, moment = elliptic_friction_functions(u, direction, aspect)
    disk_force, disk_moment = _disk(u)
    cos_a, sin_a = math.cos(direction), math.sin(direction)
    parallel = -(force[0] * cos_a + force[1] * sin_a) / disk_force
    across = -(-force[0] * sin_a + force[1] * cos_a) / disk_force
    moment_ratio = -moment / disk_moment / (zero_slip_moment(aspect) / (3.0 * math.pi / 16.0))
    return parallel - 1.0, across, moment_ratio - 1.0


def node_ratios(slip: float, beta: float, aspect: float) -> tuple[float, float, float]:
    """(d_par, r_perp, d_M) at the node (s, β, k), closed forms at the ends (module notes)."""
    if aspect == 1.0:
        return 0.0, 0.0, 0.0
    direction = _inverse(
        lambda a: direction_coordinate(math.cos(a), math.sin(a), aspect), beta, 0.5 * math.pi
    )
    cos_a, sin_a = math.cos(direction), math.sin(direction)
    if slip == 0.0:
        along, across = small_slip_stiffness(aspect)
        parallel = (along * cos_a * cos_a + across * sin_a * sin_a) / _DISK_FORCE_SLOPE
        turned = (across - along) * sin_a * cos_a / _DISK_FORCE_SLOPE
        return parallel - 1.0, turned, 0.0
    if slip == 1.0:
        limit = cos_a * cos_a + aspect * aspect * sin_a * sin_a
        return 0.0, 0.0, limit * (3.0 * math.pi / 16.0) / zero_slip_moment(aspect) - 1.0
    u = _slip_ratio(slip, aspect)
    return exact_ratios(u, direction, aspect)


def _inverse(function: Callable[[float], float], value: float, upper: float) -> float:
    """x in [0, upper] with function(x) = value, for an increasing function."""
    if value <= function(0.0):
        return 0.0
    if value >= function(upper):
        return upper
    return float(optimize.brentq(lambda x: function(x) - value, 0.0, upper, xtol=1e-15, rtol=1e-15))


def _slip_ratio(slip: float, aspect: float) -> float:
    """u at the slip coordinate 0 < s < 1 (the inverse of ``slip_coordinate``)."""
    # s(u) <= (2/π) atan(u/k) and s(u) >= (2/π) atan(u) bracket u
    lower = aspect * math.tan(0.5 * math.pi * slip)
    upper = math.tan(0.5 * math.pi * slip)
    return float(
        optimize.brentq(
            lambda u: slip_coordinate(u, 1.0, aspect) - slip, lower, upper, xtol=1e-300, rtol=1e-15
        )
    )


def _aspect_slice(
    arguments: tuple[np.ndarray, np.ndarray, float],
) -> np.ndarray:
    slips, directions, aspect = arguments
    values = np.empty((3, slips.size, directions.size))
    for i, slip in enumerate(slips):
        for j, beta in enumerate(directions):
            values[:, i, j] = node_ratios(float(slip), float(beta), aspect)
    return values


def generate_table(
    slip_nodes: int = SLIP_NODES,
    direction_nodes: int = DIRECTION_NODES,
    aspect_nodes: int = ASPECT_NODES,
    aspect_min: float = ASPECT_MIN,
    processes: int | None = None,
) -> dict[str, np.ndarray]:
    """The node values: ``ratios`` (d_par, r_perp, d_M), shape (3, n_s, n_β, n_k), and the grid.

    One exact evaluation per interior node (about 1 ms each), spread over
    ``processes`` worker processes (default: the CPU count, at most the number of k).
    """
    slips, directions, aspects = node_coordinates(
        slip_nodes, direction_nodes, aspect_nodes, aspect_min
    )
    jobs = [(slips, directions, float(aspect)) for aspect in aspects]
    workers = min(processes or os.cpu_count() or 1, len(jobs))
    if workers > 1:
        with Pool(workers) as pool:
            slices = pool.map(_aspect_slice, jobs)
    else:
        slices = [_aspect_slice(job) for job in jobs]
    return {
        "ratios": np.stack(slices, axis=-1),
        "slip_coordinates": slips,
        "direction_coordinates": directions,
        "aspects": aspects,
        "aspect_min": np.array(aspect_min),
    }


def write_table(path: Path = TABLE_FILE, **options: int) -> dict[str, np.ndarray]:
    """Generate the table and write it to ``path`` whole or not at all: a temporary name
    beside it, moved into place once written, removed if anything fails (a full disk, a
    Ctrl-C)."""
    table = generate_table(**options)
    handle = tempfile.NamedTemporaryFile(dir=path.parent, suffix=".npz", delete=False)
    temporary = Path(handle.name)
    try:
        with handle:
            np.savez(handle, **table)  # type: ignore[arg-type]
        os.chmod(temporary, 0o644)
        temporary.replace(path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    return table


def main() -> int:
    """Write ``kernels/friction_ellipse_table.npz`` and say how long it took."""
    start = time.perf_counter()
    table = write_table()
    shape = table["ratios"].shape
    print(
        f"{TABLE_FILE}: ratios {shape} in {time.perf_counter() - start:.1f} s",
        file=sys.stderr,
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
