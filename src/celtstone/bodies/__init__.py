"""Bodies: validated parameter sets, loaded from TOML data files.

``list_bodies()`` names the shipped sets; ``load_body(name_or_path)`` reads one. What
a file may hold (tables, keys, forms, units) is declared in ``bodies.file_schema``.
"""

from celtstone.bodies.body import Body as Body
from celtstone.bodies.catalogue import body_from_dict as body_from_dict
from celtstone.bodies.catalogue import list_bodies as list_bodies
from celtstone.bodies.catalogue import load_body as load_body
from celtstone.bodies.catalogue import load_design as load_design
from celtstone.bodies.catalogue import shape_from_table as shape_from_table
from celtstone.bodies.design import AddedMass as AddedMass
from celtstone.bodies.design import Design as Design
from celtstone.bodies.file_schema import BodyFileError as BodyFileError
from celtstone.bodies.shapes import SHAPES as SHAPES
from celtstone.bodies.shapes import STORED_SHAPES as STORED_SHAPES
from celtstone.bodies.shapes import Ellipsoid as Ellipsoid
from celtstone.bodies.shapes import ImplicitFunction as ImplicitFunction
from celtstone.bodies.shapes import ImplicitPolynomial as ImplicitPolynomial
from celtstone.bodies.shapes import ImplicitSurface as ImplicitSurface
from celtstone.bodies.shapes import Paraboloid as Paraboloid
from celtstone.bodies.shapes import Shape as Shape
from celtstone.bodies.shapes import Superellipsoid as Superellipsoid
