"""celtstone: the Celt stone (rattleback) on a plane, rolling or rolling with sliding.

Models of Zhuravlev-style friction on a Hertz contact after the paper "On the
influence of sliding on the Celt rattleback motion" (see README).

>>> import celtstone as cs
>>> body = cs.load_body("kane_levinson_1982")
>>> run = cs.simulate(cs.RollingModel(), body, cs.InitialState(omega=(0, 0, -5)), t_end=5.0)
>>> run.dataset["spin"]  # doctest: +SKIP
"""

from typing import Any

from celtstone.analysis import SpinStability as SpinStability
from celtstone.analysis import reversal_times as reversal_times
from celtstone.analysis import spin_stability as spin_stability
from celtstone.bodies import Body as Body
from celtstone.bodies import Ellipsoid as Ellipsoid
from celtstone.bodies import ImplicitFunction as ImplicitFunction
from celtstone.bodies import ImplicitPolynomial as ImplicitPolynomial
from celtstone.bodies import Paraboloid as Paraboloid
from celtstone.bodies import Superellipsoid as Superellipsoid
from celtstone.bodies import list_bodies as list_bodies
from celtstone.bodies import load_body as load_body
from celtstone.errors import CeltstoneError as CeltstoneError
from celtstone.errors import CeltstoneWarning as CeltstoneWarning
from celtstone.errors import FrictionBoundWarning as FrictionBoundWarning
from celtstone.errors import FrictionSingularityError as FrictionSingularityError
from celtstone.errors import IntegrationError as IntegrationError
from celtstone.errors import LiftOffError as LiftOffError
from celtstone.errors import ParameterError as ParameterError
from celtstone.errors import PlausibilityWarning as PlausibilityWarning
from celtstone.integrate import simulate as simulate
from celtstone.integrate import version as version
from celtstone.models import MODELS as MODELS
from celtstone.models import HybridModel as HybridModel
from celtstone.models import InitialState as InitialState
from celtstone.models import RollingModel as RollingModel
from celtstone.models import SlidingModel as SlidingModel
from celtstone.models import model_from_name as model_from_name
from celtstone.trajectory import Trajectory as Trajectory

__all__ = [
    "MODELS",
    "Body",
    "CeltstoneError",
    "CeltstoneWarning",
    "Ellipsoid",
    "FrictionBoundWarning",
    "FrictionSingularityError",
    "HybridModel",
    "ImplicitFunction",
    "ImplicitPolynomial",
    "InitialState",
    "IntegrationError",
    "LiftOffError",
    "Paraboloid",
    "ParameterError",
    "PlausibilityWarning",
    "RollingModel",
    "SlidingModel",
    "SpinStability",
    "Superellipsoid",
    "Sweep",
    "Trajectory",
    "list_bodies",
    "load_body",
    "model_from_name",
    "open_sweep",
    "reversal_times",
    "simulate",
    "spin_stability",
    "version",
]


def __getattr__(name: str) -> Any:
    """``Sweep`` and ``open_sweep`` on first use, so ``import celtstone`` stays light
    (no Zarr or Dask until a sweep is asked for)."""
    if name in ("Sweep", "open_sweep"):
        from celtstone import sweep

        return getattr(sweep, name)
    raise AttributeError(f"module 'celtstone' has no attribute {name!r}")
