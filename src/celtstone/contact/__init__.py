"""The contact of the body with the plane: the friction laws' registry, their reference
quadrature, Hertz.

A layer between ``models`` and ``kernels``; it may use SciPy (``quadrature``).
"""

from celtstone.contact.hertz import effective_modulus as effective_modulus
from celtstone.contact.hertz import hertz_contact_radius as hertz_contact_radius
from celtstone.contact.laws import CONTACT_PRESSURES as CONTACT_PRESSURES
from celtstone.contact.laws import CONTACT_SHAPES as CONTACT_SHAPES
from celtstone.contact.laws import FRICTION_LAWS as FRICTION_LAWS
from celtstone.contact.laws import LAW_WORDS as LAW_WORDS
from celtstone.contact.laws import LAWS as LAWS
from celtstone.contact.laws import PRESSURE_WORDS as PRESSURE_WORDS
from celtstone.contact.laws import SHAPE_WORDS as SHAPE_WORDS
from celtstone.contact.laws import FrictionLawEntry as FrictionLawEntry
from celtstone.contact.laws import choice_words as choice_words
from celtstone.contact.laws import friction_functions as friction_functions
from celtstone.contact.laws import law_code as law_code
from celtstone.contact.quadrature import friction_integrals as friction_integrals

# the public names; LAW_WORDS, PRESSURE_WORDS, SHAPE_WORDS and choice_words, the help
# texts of the options, and law_code are importable from here for the CLI but are not
# the user's API
__all__ = [
    "CONTACT_PRESSURES",
    "CONTACT_SHAPES",
    "FRICTION_LAWS",
    "LAWS",
    "FrictionLawEntry",
    "effective_modulus",
    "friction_functions",
    "friction_integrals",
    "hertz_contact_radius",
]
