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
from celtstone.atlas.fields import ATLAS_STUDY as ATLAS_STUDY
from celtstone.atlas.fields import atlas_dataset as atlas_dataset
from celtstone.atlas.fields import atlas_numbers as atlas_numbers
from celtstone.atlas.fields import compute_atlas as compute_atlas
from celtstone.atlas.fields import hertz_study as hertz_study
from celtstone.atlas.fields import judge_design as judge_design
from celtstone.atlas.fields import write_atlas as write_atlas

__all__ = [
    "ATLAS_STUDY",
    "MATERIALS",
    "Material",
    "MaterialPair",
    "StoneDesign",
    "atlas_dataset",
    "atlas_numbers",
    "compute_atlas",
    "half_ellipsoid_inertia",
    "hertz_study",
    "judge_design",
    "write_atlas",
]
