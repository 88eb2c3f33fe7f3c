"""Short teaching notes shown beside the explorer's controls (from the user guide)."""

from __future__ import annotations

__all__ = ["NOTES"]

NOTES: dict[str, str] = {
    "stone": (
        "A rattleback's long axis of curvature is turned against its principal axes of "
        "inertia (the misalignment δ). That skew couples spin to rocking: spun one way, "
        "the rocking it excites pushes the spin down; spun the other way, it does not "
        "(docs: guide/bodies)."
    ),
    "start": (
        "Spun the *wrong way* (the sense whose steady spin is unstable), the stone "
        "starts to rock, the rocking grows, and its energy flows back into spin of the "
        "opposite sense: a reversal. Spun the *right way*, steady spin is stable and "
        "it spins on (docs: guide/reversals)."
    ),
    "contact": (
        "Rolling: the contact point does not slip and energy is conserved. Sliding: "
        "the contact is a disk of radius ε where Coulomb friction (coefficient f) acts "
        "on both sliding and pivoting (Contensou coupling); the Padé law is Zhuravlev's "
        "approximation of the exact integrals. Stick-slip: the contact rolls while "
        "friction can hold it and slides when it cannot (docs: guide/friction, "
        "guide/models)."
    ),
    "plots": (
        "Spin ω·n is the angular velocity about the vertical; a reversal is counted "
        "when its rocking average crosses a band around zero (red dotted lines). Energy "
        "lost to sliding equals the friction work W; E + W stays at E(0) up to the "
        "integrator's error."
    ),
}
