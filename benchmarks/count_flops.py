"""Floating-point operations and time of one right-hand-side evaluation (issue 17, item 2).

For the shipped Kane & Levinson ellipsoid at a generic state (tilt 0.5/0.5 deg,
ω = (0.1, 0.2, -5) rad/s; in sliding a slip V1 of 1 mm/s tangent to the plane) this
script

1. counts every floating-point operation that one ``kernels.system.rhs`` evaluation
   executes, for (a) the rolling model and (b) the sliding model (Padé law, Hertz
   pressure, static friction load N = m g, f = 0.35, fixed contact radius 1 mm). The
   kernels run as plain Python (``NUMBA_DISABLE_JIT=1``) on a ``float`` subclass that
   tallies each arithmetic operation, comparison, ``abs``/``min``/``max`` and ``math``
   call by kind and by the kernel function that executes it; the counted dy is checked
   against the compiled kernel's (so the whole path ran);
2. times one evaluation of the compiled ``rhs`` inside a numba-compiled loop of
   ``--evaluations`` calls (one state component perturbed by 1e-12 each iteration, so
   nothing can be hoisted out of the loop), best of ``--repeats``, in a subprocess with
   the JIT on; for comparison also with ω1 perturbed instead of n3 (a check that nothing
   was hoisted) and calling ``system.evaluate`` directly instead of ``rhs`` (the
   wrapper costs two more NRT_incref/NRT_decref pairs on y and dy per call);
3. prints a table: operations, flops, ns per evaluation, cycles at the nominal clock of
   /proc/cpuinfo and flops per cycle (``--json`` for a JSON record, ``--by-site``
   for the counts by source line).

Flops are additions/subtractions + multiplications + divisions + square roots + other
``math`` calls and powers (a division and a square root count 1 each although they cost
10-20 cycles of latency). Negations, comparisons, ``abs``/``min``/``max`` and the
multiplications by a literal ±1.0 (LLVM folds ``x * -1.0`` to a negation) are listed
separately and are not flops. Integer index arithmetic is not counted.

Run ``python benchmarks/count_flops.py`` (about 15 s).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
from collections import Counter
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from datetime import UTC, datetime
from pathlib import Path
from types import ModuleType, SimpleNamespace
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

BODY = "kane_levinson_1982"
OMEGA = (0.1, 0.2, -5.0)  # initial angular velocity [rad/s]
TILT = (0.5, 0.5)  # Euler tilts alpha, beta [deg]
FRICTION_COEFFICIENT = 0.35
CONTACT_RADIUS = 1e-3  # [m]
SLIP_SPEED = 1e-3  # |V1| of the sliding state [m/s]
SLIP_DIRECTION = (1.0, 0.5, 0.0)  # projected onto the plane (V1 · n = 0) and normalised
PERTURBATION = 1e-12  # added to one state component each timed iteration
MODELS = ("rolling", "sliding")

# the kinds of operation the counter tells apart
FLOP_KINDS = ("add", "mul", "div", "sqrt")
OTHER_KINDS = ("neg", "mul_unit", "compare", "abs", "min", "max")
# math functions that classify (no arithmetic): tallied as comparisons
CLASSIFIERS = ("isfinite", "isnan", "isinf")
MATH_FUNCTIONS = (
    "sqrt",
    "cbrt",
    "exp",
    "expm1",
    "log",
    "log1p",
    "sin",
    "cos",
    "tan",
    "asin",
    "acos",
    "atan",
    "atan2",
    "sinh",
    "cosh",
    "tanh",
    "hypot",
    "copysign",
    "fabs",
    "pow",
    "fmod",
    "floor",
    "ceil",
    "trunc",
    *CLASSIFIERS,
)

# ---------------------------------------------------------------------------------------
# counting


class Tally:
    """Operation counts of one evaluation: by kind, and by call site and kind.

    The call site of an operation is the first line outside ``kernels/vector.py`` on the
    stack, so the operations of ``cross``, ``dot`` ... are charged to the line that
    calls them (with the helper's name).
    """

    def __init__(self) -> None:
        self.kinds: Counter[str] = Counter()
        self.sites: Counter[tuple[str, int, str, str, str]] = Counter()
        self.active = False

    def record(self, kind: str) -> None:
        if not self.active:
            return
        # frame 0: record, 1: the operator or wrapper, 2: the kernel that executes it
        frame = sys._getframe(2)
        helper = ""
        site = frame
        while site is not None and Path(site.f_code.co_filename).name == "vector.py":
            helper = site.f_code.co_name
            site = site.f_back
        if site is None:
            site, helper = frame, ""
        self.kinds[kind] += 1
        key = (
            Path(site.f_code.co_filename).name,
            site.f_lineno,
            site.f_code.co_name,
            helper,
            kind,
        )
        self.sites[key] += 1


TALLY = Tally()


class SlippedScalarError(TypeError):
    """A NumPy scalar met a counting float: an operation could escape the count."""


def _operand(other: Any) -> float | None:
    """``other`` as a float for an arithmetic operation, None if it is no real number."""
    if isinstance(other, bool):
        return float(other)
    if isinstance(other, CountingFloat):
        return float(other)
    if type(other) in (float, int):
        return float(other)
    if type(other).__module__ == "numpy":
        raise SlippedScalarError(f"a NumPy scalar {other!r} reached the counted evaluation")
    return None


def _is_unit_literal(other: Any) -> bool:
    return type(other) in (float, int) and other in (1.0, -1.0)


class CountingFloat(float):
    """A float whose arithmetic, comparisons and ``abs`` are tallied in ``TALLY``.

    Every result of an operation with a CountingFloat is a CountingFloat, on either side
    of the operator (Python tries the reflected method of a float subclass first).
    """

    __slots__ = ()

    def __add__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("add")
        return CountingFloat(float(self) + value)

    def __radd__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("add")
        return CountingFloat(value + float(self))

    def __sub__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("add")
        return CountingFloat(float(self) - value)

    def __rsub__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("add")
        return CountingFloat(value - float(self))

    def __mul__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("mul_unit" if _is_unit_literal(other) else "mul")
        return CountingFloat(float(self) * value)

    def __rmul__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("mul_unit" if _is_unit_literal(other) else "mul")
        return CountingFloat(value * float(self))

    def __truediv__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("div")
        return CountingFloat(float(self) / value)

    def __rtruediv__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("div")
        return CountingFloat(value / float(self))

    def __pow__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("math.pow")
        return CountingFloat(float(self) ** value)

    def __rpow__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("math.pow")
        return CountingFloat(value ** float(self))

    def __mod__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("math.fmod")
        return CountingFloat(float(self) % value)

    def __floordiv__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("math.floordiv")
        return CountingFloat(float(self) // value)

    def __neg__(self) -> CountingFloat:
        TALLY.record("neg")
        return CountingFloat(-float(self))

    def __pos__(self) -> CountingFloat:
        return self

    def __abs__(self) -> CountingFloat:
        TALLY.record("abs")
        return CountingFloat(abs(float(self)))

    def __lt__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("compare")
        return float(self) < value

    def __le__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("compare")
        return float(self) <= value

    def __gt__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("compare")
        return float(self) > value

    def __ge__(self, other: Any) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("compare")
        return float(self) >= value

    def __eq__(self, other: object) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("compare")
        return float(self) == value

    def __ne__(self, other: object) -> Any:
        value = _operand(other)
        if value is None:
            return NotImplemented
        TALLY.record("compare")
        return float(self) != value

    def __hash__(self) -> int:
        return float.__hash__(self)


def _math_wrapper(name: str, function: Callable[..., Any]) -> Callable[..., Any]:
    kind = "compare" if name in CLASSIFIERS else ("sqrt" if name == "sqrt" else f"math.{name}")

    def counted(*args: Any) -> Any:
        for argument in args:
            _operand(argument)  # refuses a NumPy scalar
        TALLY.record(kind)
        result = function(*(float(argument) for argument in args))
        return CountingFloat(result) if type(result) is float else result

    counted.__name__ = f"counted_{name}"
    return counted


def _extremum(kind: str, pick: Callable[[float, float], bool]) -> Callable[..., Any]:
    def counted(*args: Any) -> Any:
        values = args[0] if len(args) == 1 else args
        best = None
        for value in values:
            _operand(value)
            if best is None or pick(float(value), float(best)):
                best = value
        for _ in range(len(values) - 1):
            TALLY.record(kind)
        return CountingFloat(best) if type(best) is float else best

    counted.__name__ = f"counted_{kind}"
    return counted


@contextmanager
def counting(kernel_modules: list[ModuleType]) -> Iterator[None]:
    """Route ``math.*``, ``min`` and ``max`` of the kernels through counting wrappers."""
    saved = {name: getattr(math, name) for name in MATH_FUNCTIONS if hasattr(math, name)}
    injected: list[tuple[ModuleType, str]] = []
    try:
        for name, function in saved.items():
            setattr(math, name, _math_wrapper(name, function))
        for module in kernel_modules:
            for name, wrapper in (
                ("min", _extremum("min", lambda a, b: a < b)),
                ("max", _extremum("max", lambda a, b: a > b)),
            ):
                if name in vars(module):
                    raise RuntimeError(f"{module.__name__} defines {name}; cannot count it")
                setattr(module, name, wrapper)
                injected.append((module, name))
        TALLY.active = True
        yield
    finally:
        TALLY.active = False
        for name, function in saved.items():
            setattr(math, name, function)
        for module, name in injected:
            delattr(module, name)


class CountingArray:
    """A read-only stand-in for a NumPy array of a parameter record: ``[i]``, ``[i, j]``,
    ``shape``, ``len``, iteration; float elements are CountingFloats, int elements ints."""

    def __init__(self, array: Any) -> None:
        self.shape = tuple(array.shape)
        self.ndim = len(self.shape)
        self._items = [_counting_scalar(value) for value in array.ravel().tolist()]

    def _flat(self, index: Any) -> int:
        indices = index if isinstance(index, tuple) else (index,)
        if len(indices) != self.ndim:
            raise IndexError(f"{index!r} on shape {self.shape}")
        flat = 0
        for i, size in zip(indices, self.shape, strict=True):
            i = int(i)
            if i < 0:
                i += size
            if not 0 <= i < size:
                raise IndexError(f"{index!r} on shape {self.shape}")
            flat = flat * size + i
        return flat

    def __getitem__(self, index: Any) -> Any:
        if self.ndim > 1 and not isinstance(index, tuple):
            raise TypeError("row indexing of a parameter matrix is not supported")
        return self._items[self._flat(index)]

    def __len__(self) -> int:
        return self.shape[0]

    def __iter__(self) -> Iterator[Any]:
        if self.ndim != 1:
            raise TypeError("iteration over a parameter matrix is not supported")
        return iter(self._items)


def _counting_scalar(value: Any) -> Any:
    if isinstance(value, bool):
        return value
    if isinstance(value, int):
        return int(value)
    return CountingFloat(float(value))


class CountingState(list):  # type: ignore[type-arg]
    """The state or rate array as a list of CountingFloats, with ``shape`` and ``copy``."""

    @property
    def shape(self) -> tuple[int]:
        return (len(self),)

    def copy(self) -> CountingState:
        return CountingState(self)


def counting_parameters(record: Any) -> SimpleNamespace:
    """The parameter record with every field converted (floats to CountingFloat)."""
    import numpy as np

    fields: dict[str, Any] = {}
    for name in record.dtype.names:
        value = record[name]
        if isinstance(value, np.ndarray):
            fields[name] = CountingArray(value)
        else:
            fields[name] = _counting_scalar(value.item())
    return SimpleNamespace(**fields)


# ---------------------------------------------------------------------------------------
# the cases


def model_object(name: str) -> Any:
    import celtstone as cs

    if name == "rolling":
        return cs.RollingModel()
    return cs.SlidingModel(
        friction_coefficient=FRICTION_COEFFICIENT,
        contact_radius=CONTACT_RADIUS,
        friction_load="static",
        friction_law="pade",
        contact_pressure="hertz",
    )


def case(name: str) -> tuple[int, Any, list[float]]:
    """(model code, parameter record, state vector) of one model's generic state."""
    import numpy as np

    import celtstone as cs
    from celtstone.kernels.layout import Y_N, Y_SLIP
    from celtstone.simulation.models import initial_vector, kernel_parameters

    model = model_object(name)
    params = kernel_parameters(model, cs.load_body(BODY))
    y = initial_vector(cs.InitialState(OMEGA, TILT))
    if name == "sliding":
        n = y[Y_N : Y_N + 3]
        direction = np.array(SLIP_DIRECTION)
        direction -= direction.dot(n) / n.dot(n) * n
        y[Y_SLIP : Y_SLIP + 3] = SLIP_SPEED * direction / np.linalg.norm(direction)
    return int(model.code), params, [float(value) for value in y]


def count_case(name: str) -> dict[str, Any]:
    """Operation counts and dy of one counted evaluation of ``rhs``."""
    from celtstone.kernels import (
        dynamics,
        friction,
        friction_exact,
        geometry,
        hertz,
        implicit,
        stick,
        system,
        vector,
    )

    if not getattr(system.rhs, "__module__", "").startswith("celtstone") or hasattr(
        system.rhs, "py_func"
    ):
        raise RuntimeError("the kernels are compiled: set NUMBA_DISABLE_JIT=1 before importing")
    modules = [dynamics, friction, friction_exact, geometry, hertz, implicit, stick, system]
    modules.append(vector)
    code, record, state = case(name)
    params = counting_parameters(record)
    y = CountingState(CountingFloat(value) for value in state)
    dy = CountingState(CountingFloat(0.0) for _ in state)
    TALLY.kinds.clear()
    TALLY.sites.clear()
    with counting(modules):
        status, _ = system.rhs(code, CountingFloat(0.0), y, params, dy)
    plain = [value for value in dy if type(value) is not CountingFloat and value != 0.0]
    if plain:
        raise RuntimeError(f"{name}: a rate left the counted path: {plain}")
    kinds = dict(TALLY.kinds)
    by_site: dict[str, dict[str, int]] = {}
    for (file, line, function, helper, kind), count in sorted(TALLY.sites.items()):
        label = f"{file}:{line} {function}" + (f" [{helper}]" if helper else "")
        by_site.setdefault(label, {})[kind] = count
    return {
        "status": int(status),
        "dy": [float(value) for value in dy],
        "kinds": kinds,
        "by_site": by_site,
    }


def summarise(kinds: dict[str, int]) -> dict[str, Any]:
    other = {kind[5:]: count for kind, count in sorted(kinds.items()) if kind.startswith("math.")}
    flops = sum(kinds.get(kind, 0) for kind in FLOP_KINDS) + sum(other.values())
    summary = {kind: kinds.get(kind, 0) for kind in (*FLOP_KINDS, *OTHER_KINDS)}
    summary.update(other_math=other, other_math_calls=sum(other.values()), flops=flops)
    return summary


# ---------------------------------------------------------------------------------------
# timing (a subprocess with the JIT on)


def timing_worker(evaluations: int, repeats: int) -> dict[str, Any]:
    """dy of the compiled rhs at each model's state, and ns per evaluation in a loop."""
    import time

    import numba
    import numpy as np

    from celtstone.kernels.layout import Y_N, Y_OMEGA
    from celtstone.kernels.system import evaluate, rhs

    @numba.njit(error_model="numpy")
    def loop_rhs(model, y, params, dy, count, index):
        base = y[index]
        total = 0.0
        for i in range(count):
            y[index] = base + (i & 1) * PERTURBATION  # a new state each iteration
            rhs(model, 0.0, y, params, dy)
            total += dy[Y_OMEGA]
        y[index] = base
        return total

    @numba.njit(error_model="numpy")
    def loop_evaluate(model, y, params, dy, count, index):
        base = y[index]
        total = 0.0
        for i in range(count):
            y[index] = base + (i & 1) * PERTURBATION
            status, normal_force, power, force = evaluate(model, y, params, dy)
            total += dy[Y_OMEGA] + normal_force + power + force + status
        y[index] = base
        return total

    variants = (
        ("ns", loop_rhs, Y_N + 2),  # the reported time: rhs, n3 perturbed
        ("ns_perturb_omega1", loop_rhs, Y_OMEGA),  # hoisting check
        ("ns_evaluate", loop_evaluate, Y_N + 2),  # without the rhs -> evaluate wrapper
    )
    results: dict[str, Any] = {}
    for name in MODELS:
        code, params, state = case(name)
        y = np.array(state)
        dy = np.zeros_like(y)
        status, _ = rhs(code, 0.0, y, params, dy)
        entry: dict[str, Any] = {"status": int(status), "dy": [value.hex() for value in dy]}
        for label, loop, index in variants:
            loop(code, y, params, dy, 10, index)  # compile
            entry[label] = math.inf
        for _ in range(repeats):  # the variants interleaved, so a busy spell hits all alike
            for label, loop, index in variants:
                start = time.perf_counter_ns()
                loop(code, y, params, dy, evaluations, index)
                entry[label] = min(entry[label], (time.perf_counter_ns() - start) / evaluations)
        results[name] = entry
    return results


def run_timing(evaluations: int, repeats: int) -> dict[str, Any]:
    environment = {key: value for key, value in os.environ.items() if key != "NUMBA_DISABLE_JIT"}
    command = [
        sys.executable,
        str(Path(__file__).resolve()),
        "--timing-worker",
        "--evaluations",
        str(evaluations),
        "--repeats",
        str(repeats),
    ]
    completed = subprocess.run(
        command, env=environment, capture_output=True, text=True, check=False, cwd=ROOT
    )
    if completed.returncode != 0:
        raise RuntimeError(f"timing subprocess failed:\n{completed.stderr}")
    result: dict[str, Any] = json.loads(completed.stdout.strip().splitlines()[-1])
    return result


def cpu() -> dict[str, Any]:
    """CPU model and nominal clock from /proc/cpuinfo (its first processor).

    The "cpu MHz" of a virtual machine is the host's nominal clock; a boost clock, if
    any, is not visible there, so cycles computed from it may be too few.
    """
    model, mhz = "", math.nan
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        text = ""
    for line in text.splitlines():
        key, _, value = line.partition(":")
        key = key.strip()
        if key == "model name" and not model:
            model = value.strip()
        elif key == "cpu MHz" and math.isnan(mhz):
            mhz = float(value)
    return {
        "model": model or platform.processor() or "unknown",
        "mhz": mhz,
        "logical_cpus": os.cpu_count(),
        "machine": platform.machine(),
    }


# ---------------------------------------------------------------------------------------
# report


def relative_difference(counted: list[float], compiled: list[float]) -> float:
    scale = max(abs(value) for value in compiled)
    return max(abs(a - b) for a, b in zip(counted, compiled, strict=True)) / scale


def print_table(record: dict[str, Any], by_site: bool) -> None:
    machine = record["cpu"]
    ghz = machine["mhz"] / 1000.0
    print(f"celtstone rhs: operations and time of one evaluation ({record['date']})")
    print(
        f"body {BODY}, tilt {TILT} deg, omega {OMEGA} rad/s; sliding: Padé law, Hertz "
        f"pressure, static load, f = {FRICTION_COEFFICIENT}, eps = {CONTACT_RADIUS} m, "
        f"|V1| = {SLIP_SPEED} m/s"
    )
    print(
        f"CPU {machine['model']}, {machine['mhz']:.0f} MHz nominal (/proc/cpuinfo), "
        f"{machine['logical_cpus']} logical CPUs (others may be busy); "
        f"{record['evaluations']:.0e} evaluations per loop, best of {record['repeats']}"
    )
    columns = (
        ("model", 8),
        ("add/sub", 8),
        ("mul", 5),
        ("div", 4),
        ("sqrt", 5),
        ("other", 6),
        ("flops", 6),
        ("cmp", 4),
        ("abs/min/max", 12),
        ("neg", 4),
        ("x±1", 4),
        ("ns/eval", 8),
        ("cycles", 7),
        ("flop/cyc", 8),
    )
    print("  ".join(f"{title:>{width}}" for title, width in columns))
    for name in MODELS:
        row = record["models"][name]
        ops = row["counts"]
        extremes = ops["abs"] + ops["min"] + ops["max"]
        values = (
            name,
            ops["add"],
            ops["mul"],
            ops["div"],
            ops["sqrt"],
            ops["other_math_calls"],
            ops["flops"],
            ops["compare"],
            extremes,
            ops["neg"],
            ops["mul_unit"],
            f"{row['ns']:.1f}",
            f"{row['ns'] * ghz:.0f}",
            f"{ops['flops'] / (row['ns'] * ghz):.2f}",
        )
        print(
            "  ".join(
                f"{value!s:>{width}}" for value, (_, width) in zip(values, columns, strict=True)
            )
        )
    for name in MODELS:
        row = record["models"][name]
        other = ", ".join(f"{k} {v}" for k, v in row["counts"]["other_math"].items()) or "none"
        print(
            f"{name}: other math calls: {other}; counted dy vs compiled dy: "
            f"{row['dy_relative_difference']:.1e} (max-norm relative); status {row['status']}; "
            f"ns with omega1 perturbed instead of n3: {row['ns_perturb_omega1']:.1f}; "
            f"ns calling evaluate directly (no rhs wrapper): {row['ns_evaluate']:.1f}"
        )
    if by_site:
        for name in MODELS:
            print(f"\n{name}: operations by call site (file:line function [vector helper])")
            for site, kinds in record["models"][name]["by_site"].items():
                parts = ", ".join(f"{kind} {count}" for kind, count in sorted(kinds.items()))
                print(f"  {site:<58} {parts}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--evaluations", type=int, default=2_000_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--json", action="store_true", help="print one JSON record")
    parser.add_argument("--by-site", action="store_true", help="counts by source line")
    parser.add_argument("--timing-worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()

    if args.timing_worker:
        print(json.dumps(timing_worker(args.evaluations, args.repeats)))
        return

    # plain-Python kernels: must be set before celtstone (and numba) is imported
    os.environ["NUMBA_DISABLE_JIT"] = "1"
    if "numba" in sys.modules or "celtstone" in sys.modules:
        raise RuntimeError("numba or celtstone imported before NUMBA_DISABLE_JIT was set")
    timing = run_timing(args.evaluations, args.repeats)
    record: dict[str, Any] = {
        "date": datetime.now(UTC).isoformat(timespec="seconds"),
        "cpu": cpu(),
        "evaluations": args.evaluations,
        "repeats": args.repeats,
        "models": {},
    }
    ghz = record["cpu"]["mhz"] / 1000.0
    for name in MODELS:
        counted = count_case(name)
        compiled = [float.fromhex(value) for value in timing[name]["dy"]]
        difference = relative_difference(counted["dy"], compiled)
        if counted["status"] != timing[name]["status"] or not difference < 1e-13:
            raise RuntimeError(f"{name}: counted evaluation differs from the compiled one")
        counts = summarise(counted["kinds"])
        ns = timing[name]["ns"]
        record["models"][name] = {
            "counts": counts,
            "status": counted["status"],
            "dy_relative_difference": difference,
            "ns": ns,
            "ns_perturb_omega1": timing[name]["ns_perturb_omega1"],
            "ns_evaluate": timing[name]["ns_evaluate"],
            "cycles": ns * ghz,
            "flops_per_cycle": counts["flops"] / (ns * ghz),
            "by_site": counted["by_site"],
        }
    if args.json:
        print(json.dumps(record, indent=2))
    else:
        print_table(record, args.by_site)


if __name__ == "__main__":
    main()
