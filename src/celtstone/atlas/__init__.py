"""The atlas (issue 15): a family of buildable stones and the paper's findings as fields.

>>> from celtstone.atlas import StoneDesign, compute_atlas     # doctest: +SKIP
>>> designs = [StoneDesign(length=0.1, width_ratio=0.2, height_ratio=0.2, misalignment=2.0)]
>>> atlas = compute_atlas(designs, out="atlas")               # doctest: +SKIP

``family``: :class:`StoneDesign`, a half-ellipsoid plus two point masses, and
:class:`MaterialPair` for the Hertz contact radius; ``fields``: the numbers each finding's
judge reads, computed by the sweep engine, and the verdicts (docs/decisions.md §32).
"""

from celtstone.atlas.family import MATERIALS as MATERIALS
from celtstone.atlas.family import Material as Material
from celtstone.atlas.family import MaterialPair as MaterialPair
from celtstone.atlas.family import StoneDesign as StoneDesign
from celtstone.atlas.family import half_ellipsoid_inertia as half_ellipsoid_inertia

__all__ = [
    "MATERIALS",
    "Material",
    "MaterialPair",
    "StoneDesign",
    "half_ellipsoid_inertia",
]
