"""Stiffness switching between DOP853 and Radau IIA: the method ``auto`` (``METHOD_AUTO``).

A sliding run is stiff only in stretches. The friction law's Jacobian grows as
f N / (|V1| + b ε |ω·n| + δ): where the stone slides fast or spins, the equations are at
most mildly stiff, and DOP853 (order 8) takes a tenth of Radau's (order 5) steps at
equal tolerance (a 10 s run at f = 0.081, rtol 1e-8: 5 336 against 47 541 steps); near
stick, λ reaches 1e6–1e10 1/s and an explicit method crawls. ``auto`` takes each step
with whichever of the two should be cheaper, as LSODA switches between Adams and BDF
(Petzold, SIAM J. Sci. Stat. Comput. 4 (1983) 136), judged by ρ, the spectral radius
of the Jacobian (power iteration, ``spectral_radius``):

- DOP853 is stable for h ρ up to about 6 (its stability domain reaches −6.39 on the
  real axis and 5.96 on the imaginary one, computed from its tableau). Where stability
  holds its steps, they average h ρ ≈ ``HELD_STEP``, rejections included; a Radau
  step costs about ``COST_RATIO`` DOP853 steps (5.2 against 2.4 µs for the sliding
  model on the 2-core machine; docs/decisions.md). Radau's steps h_R and DOP853's therefore
  cost the same where h_R ρ = ``BREAK_EVEN``; each switch waits until the other method
  is ``HYSTERESIS`` times cheaper, so that the two do not take turns at every check.
- **Radau → DOP853**: ρ whenever Radau evaluates its Jacobian (and a Jacobian for ρ
  alone after ``REFRESH_STEPS`` steps without one); ``CALM_STEPS`` accepted steps in a
  row with h_R ρ ≤ ``BREAK_EVEN`` / ``HYSTERESIS`` (h_R Radau's next step), each no
  more than ``SETTLED_GROWTH`` times the one before, switch: Radau's first steps after
  a start or a switch are short of what accuracy allows and would judge DOP853 cheap.
- **DOP853 → Radau**: ρ from a forward-difference Jacobian every ``CHECK_STEPS``
  accepted DOP853 steps, at a run's (or a phase's) start against its first step and
  again after that step, and early when Hairer's cheap test (the code DOP853's
  h ‖f(y_new) − f(y₁₂)‖ / ‖y_new − y₁₂‖, y₁₂ the 12th stage's argument) exceeds
  ``STABILITY_LIMIT``. DOP853 gives way when stability holds its steps (its next
  h ρ ≥ ``HELD_LIMIT``) and either h_R ρ > ``BREAK_EVEN`` ``HYSTERESIS`` for Radau's
  last step size h_R (before any Radau step: always) or ``HELD_CHECKS`` checks in a
  row found it held (h_R may be stale: a run once spent 10⁶ DOP853 steps on one).

The constants were set on eight sliding points of the sweep benchmark's grid
(docs/decisions.md §34). A switch happens between accepted steps: the driver asks
``_methods.active`` which method takes the next step and labels the step with it, so
samples and events read the interpolant of the method that took the step. With error
control off (fixed steps) the run stays with DOP853. ``RECORD`` is the whole state.
"""

from __future__ import annotations

import math

import numpy as np

from celtstone.kernels._jit import kernel
from celtstone.solvers import _dop853 as dop853
from celtstone.solvers import _radau as radau5
from celtstone.solvers._compile import inlined
from celtstone.solvers.codes import (
    METHOD_DOP853,
    METHOD_RADAU5,
    STAT_NJEV,
    STAT_SWITCHES,
)

ORDER = dop853.ORDER  # a non-stiff run, and every fixed-step run, is DOP853's
ERROR_ORDER = dop853.ERROR_ORDER  # the first step is DOP853's
DENSE_EVERY_STEP = True  # while Radau steps (the driver asks the active method)

STABILITY_LIMIT = 5.0  # Hairer's h λ above which ρ is checked early [1]
COST_RATIO = 2.5  # cost of a Radau step over a DOP853 step [1]
HELD_LIMIT = 3.0  # DOP853's next h ρ from which stability holds its steps [1]
HELD_STEP = 2.4  # h ρ of DOP853's accepted steps, on average, where stability holds them
BREAK_EVEN = HELD_STEP * COST_RATIO  # h_R ρ at which both cost the same [1]
TRIGGER_SPACING = 6  # DOP853 steps at least between two checks that Hairer's test asks for
HYSTERESIS = 2.0  # each switch waits until the other method is this much cheaper [1]
CALM_STEPS = 5  # Radau steps in a row that could have been DOP853's, to switch
SETTLED_GROWTH = 1.2  # a calm Radau step is at most this much longer than the last one
HELD_CHECKS = 4  # checks in a row that find DOP853 held switch whatever h_R was
CHECK_STEPS = 24  # accepted DOP853 steps between Jacobians for ρ
REFRESH_STEPS = 50  # Radau steps after which a Jacobian is evaluated for ρ alone
POWER_ITERATIONS = 8  # of the spectral radius estimate

RECORD = np.dtype(
    (
        np.record,
        np.dtype(
            [
                ("active", "i8"),  # method code of the next step
                ("calm_count", "i8"),  # Radau steps in a row that could have been DOP853's
                ("steps_since_check", "i8"),  # accepted steps since ρ was estimated
                ("jacobians_seen", "i8"),  # the run's Jacobian count when ρ was estimated
                ("spectral_radius", "f8"),  # ρ of the last estimate [1/s]
                ("radau_step", "f8"),  # Radau's last step size [s]; inf before any
                ("held_checks", "i8"),  # DOP853 checks in a row that found it held
                ("stiffness", "f8"),  # Hairer's h λ of the last DOP853 step [1]
            ],
            align=True,
        ),
    )
)


@inlined
def workspace():
    """The switching record of one run (its ``memory``), before the first step."""
    return np.zeros(1, dtype=RECORD)


@kernel
def reset(record):
    """The record of a run (or a phase of one) that begins with DOP853, ρ not yet checked."""
    state = record[0]
    state.active = METHOD_DOP853
    state.calm_count = 0
    state.steps_since_check = CHECK_STEPS
    state.jacobians_seen = -1
    state.spectral_radius = 0.0
    state.radau_step = math.inf
    state.held_checks = 0
    state.stiffness = 0.0


@kernel
def start(record, model, params, t, y, f, h, controls, work, stats):
    """A run (or a phase of one) begins (contract item 5): DOP853's start, then ρ checked
    against the first step h [s], so that a stiff start starts with Radau; if DOP853 takes
    that step, ρ is checked again after it (Hairer's first step may be short of stiff).

    The check is :func:`after_step`'s for DOP853, due from the reset on; called alone,
    so that this function does not compile (and link) what Radau's steps need."""
    reset(record)
    dop853.start(model, params, t, y, f, controls, work.dop853, stats)
    if controls.adaptive:
        check_explicit(record, model, params, t, y, f, h, controls, work.radau5, stats)
    if record[0].active == METHOD_DOP853:
        record[0].steps_since_check = CHECK_STEPS


@inlined
def note_explicit_step(record, work, y_new, h):
    """After an accepted DOP853 step of size h [s] (``work``: its workspace, read before
    its interpolant overwrites the 12th stage's argument): Hairer's h λ."""
    stages = work.stages
    argument = work.scratch  # y₁₂, left by the trial step
    numerator = 0.0
    denominator = 0.0
    for j in range(y_new.shape[0]):
        numerator += (stages[dop853.N_STAGES, j] - stages[dop853.N_STAGES - 1, j]) ** 2
        denominator += (y_new[j] - argument[j]) ** 2
    stiffness = 0.0
    if denominator > 0.0:
        stiffness = h * math.sqrt(numerator / denominator)
    record[0].stiffness = stiffness


@kernel
def spectral_radius(matrix, size, vector, image):
    """An estimate of the spectral radius of the leading ``size`` × ``size`` block of
    ``matrix`` [its unit] by power iteration from the ones vector: the geometric mean of
    the last two iterations' growth, which a dominant complex pair does not upset as one
    step's growth would. ``vector`` and ``image`` are scratch of length >= size."""
    vector[:size] = 1.0 / math.sqrt(float(size))
    growth_before = 0.0
    growth = 0.0
    for _ in range(POWER_ITERATIONS):
        total = 0.0
        for i in range(size):
            value = 0.0
            for j in range(size):
                value += matrix[i, j] * vector[j]
            image[i] = value
            total += value * value
        growth_before = growth
        growth = math.sqrt(total)  # ‖A v‖ for the unit vector v
        if growth == 0.0 or not math.isfinite(growth):
            return growth
        for i in range(size):
            vector[i] = image[i] / growth
    return math.sqrt(growth_before * growth)


@inlined
def jacobian_radius(radau):
    """ρ of Radau's Jacobian in ``radau`` (its workspace): of the dynamics' block when
    the Jacobian is block lower triangular (the driven block's eigenvalues are the
    quaternion's ±i|ω|/2 and zeros), else of the whole."""
    size = radau.jacobian.shape[0]
    split = radau.memory[0].split
    if split > 0:
        size = split
    return spectral_radius(radau.jacobian, size, radau.scratch, radau.column)


@inlined
def after_step(record, model, params, t, y, f, h_next, controls, work, stats):
    """Between accepted steps, at (t, y) with f = f(t, y) and the proposed next step
    h_next [s]: switch the method that takes it if the tests above say so; ``work`` holds
    both methods' workspaces (``_methods.Workspaces``). What needs a Jacobian, a few
    steps in a hundred, is compiled apart (:func:`check_explicit`, :func:`refresh_radius`)."""
    if not controls.adaptive:
        return
    state = record[0]
    state.steps_since_check += 1
    if state.active == METHOD_DOP853:
        if state.steps_since_check < CHECK_STEPS and (
            state.stiffness <= STABILITY_LIMIT or state.steps_since_check < TRIGGER_SPACING
        ):
            return
        check_explicit(record, model, params, t, y, f, h_next, controls, work.radau5, stats)
        return
    if state.jacobians_seen != stats[STAT_NJEV] or state.steps_since_check >= REFRESH_STEPS:
        refresh_radius(record, model, params, t, y, f, work.radau5, stats)
    # calm: DOP853 cheaper at this step, and Radau's step no longer growing (its first
    # steps after a start or a switch are short of what accuracy allows)
    settled = h_next <= SETTLED_GROWTH * state.radau_step
    state.radau_step = h_next
    if settled and h_next * state.spectral_radius * HYSTERESIS <= BREAK_EVEN:
        state.calm_count += 1
    else:
        state.calm_count = 0
    if state.calm_count >= CALM_STEPS:
        state.active = METHOD_DOP853
        state.calm_count = 0
        state.steps_since_check = 0
        stats[STAT_SWITCHES] += 1


@kernel
def check_explicit(record, model, params, t, y, f, h_next, controls, radau, stats):
    """While DOP853 steps, when ρ is due (``after_step``): ρ from a Jacobian into
    Radau's workspace ``radau``, and the switch to Radau if stability holds DOP853."""
    state = record[0]
    radau5.evaluate_jacobian(model, params, t, y, f, radau, stats)
    rho = jacobian_radius(radau)
    state.spectral_radius = rho
    state.steps_since_check = 0
    held = h_next * rho >= HELD_LIMIT
    state.held_checks = state.held_checks + 1 if held else 0
    if held and (
        state.radau_step * rho > BREAK_EVEN * HYSTERESIS or state.held_checks >= HELD_CHECKS
    ):
        radau5.resume(controls, radau)  # with the Jacobian just evaluated
        state.active = METHOD_RADAU5
        state.calm_count = 0
        state.held_checks = 0
        state.radau_step = 0.0  # no Radau step of this stretch yet
        state.jacobians_seen = stats[STAT_NJEV]
        stats[STAT_SWITCHES] += 1


@kernel
def refresh_radius(record, model, params, t, y, f, radau, stats):
    """While Radau steps, after it evaluated a Jacobian or ``REFRESH_STEPS`` steps without
    one (then evaluated here): ρ of Radau's Jacobian in ``radau``."""
    state = record[0]
    if state.jacobians_seen == stats[STAT_NJEV]:  # no Jacobian for REFRESH_STEPS steps
        radau5.evaluate_jacobian(model, params, t, y, f, radau, stats)
        radau.memory[0].lu_valid = False
    state.spectral_radius = jacobian_radius(radau)
    state.jacobians_seen = stats[STAT_NJEV]
    state.steps_since_check = 0
