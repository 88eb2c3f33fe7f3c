"""celtstone: the Celt stone (rattleback) on a plane, rolling or rolling with sliding.

Models of Zhuravlev-style friction on a Hertz contact after the paper "On the
influence of sliding on the Celt rattleback motion" (see README).

>>> import celtstone as cs
>>> body = cs.load_body("kane_levinson_1982")
>>> run = cs.simulate(cs.RollingModel(), body, cs.InitialState(omega=(0, 0, -5)), t_end=5.0)
>>> run.dataset["spin"]  # doctest: +SKIP
"""

# first of all: the `celtstone` command's Ctrl-C and SIGTERM while it starts (exit 130/143,
# one line); nothing changes for a program that imports the package
from celtstone import _early_signals  # noqa: F401

# isort: split
from typing import TYPE_CHECKING

from celtstone._about import version as version
from celtstone._lazy import lazy_attributes
from celtstone.errors import CeltstoneError as CeltstoneError
from celtstone.errors import CeltstoneWarning as CeltstoneWarning
from celtstone.errors import FrictionBoundWarning as FrictionBoundWarning
from celtstone.errors import FrictionSingularityError as FrictionSingularityError
from celtstone.errors import IdentifiabilityWarning as IdentifiabilityWarning
from celtstone.errors import IntegrationError as IntegrationError
from celtstone.errors import LiftOffError as LiftOffError
from celtstone.errors import ParameterError as ParameterError
from celtstone.errors import PlausibilityWarning as PlausibilityWarning

if TYPE_CHECKING:  # the names below are imported on first use (__getattr__)
    from celtstone.bodies import AddedMass as AddedMass
    from celtstone.bodies import Body as Body
    from celtstone.bodies import Design as Design
    from celtstone.bodies import Ellipsoid as Ellipsoid
    from celtstone.bodies import ImplicitFunction as ImplicitFunction
    from celtstone.bodies import ImplicitPolynomial as ImplicitPolynomial
    from celtstone.bodies import Paraboloid as Paraboloid
    from celtstone.bodies import Superellipsoid as Superellipsoid
    from celtstone.bodies import list_bodies as list_bodies
    from celtstone.bodies import load_body as load_body
    from celtstone.explorer import explore as explore
    from celtstone.fitting import FitResult as FitResult
    from celtstone.fitting import Record as Record
    from celtstone.fitting import fit as fit
    from celtstone.fitting import make_record as make_record
    from celtstone.fitting import read_record as read_record
    from celtstone.precompile import CompileReport as CompileReport
    from celtstone.precompile import compile_solvers as compile_solvers
    from celtstone.simulation.integrate import simulate as simulate
    from celtstone.simulation.integrate import simulate_many as simulate_many
    from celtstone.simulation.models import MODELS as MODELS
    from celtstone.simulation.models import HybridModel as HybridModel
    from celtstone.simulation.models import InitialState as InitialState
    from celtstone.simulation.models import RollingModel as RollingModel
    from celtstone.simulation.models import SlidingModel as SlidingModel
    from celtstone.simulation.models import model_from_name as model_from_name
    from celtstone.simulation.reversals import reversal_times as reversal_times
    from celtstone.simulation.trajectory import Trajectory as Trajectory
    from celtstone.stability import SpinStability as SpinStability
    from celtstone.stability import spin_stability as spin_stability
    from celtstone.sweep import Sweep as Sweep
    from celtstone.sweep import open_sweep as open_sweep

__all__ = [
    "MODELS",
    "AddedMass",
    "Body",
    "CeltstoneError",
    "CeltstoneWarning",
    "CompileReport",
    "Design",
    "Ellipsoid",
    "FitResult",
    "FrictionBoundWarning",
    "FrictionSingularityError",
    "HybridModel",
    "IdentifiabilityWarning",
    "ImplicitFunction",
    "ImplicitPolynomial",
    "InitialState",
    "IntegrationError",
    "LiftOffError",
    "Paraboloid",
    "ParameterError",
    "PlausibilityWarning",
    "Record",
    "RollingModel",
    "SlidingModel",
    "SpinStability",
    "Superellipsoid",
    "Sweep",
    "Trajectory",
    "compile_solvers",
    "explore",
    "fit",
    "list_bodies",
    "load_body",
    "make_record",
    "model_from_name",
    "open_sweep",
    "read_record",
    "reversal_times",
    "simulate",
    "simulate_many",
    "spin_stability",
    "version",
]

# name -> module: imported on first use, so that `import celtstone` stays light (no numba,
# SciPy, xarray, Zarr or Dask until the engine, a dataset or a sweep is asked for)
_LAZY = {
    "SpinStability": "celtstone.stability",
    "reversal_times": "celtstone.simulation.reversals",
    "spin_stability": "celtstone.stability",
    "AddedMass": "celtstone.bodies",
    "Body": "celtstone.bodies",
    "Design": "celtstone.bodies",
    "Ellipsoid": "celtstone.bodies",
    "ImplicitFunction": "celtstone.bodies",
    "ImplicitPolynomial": "celtstone.bodies",
    "Paraboloid": "celtstone.bodies",
    "Superellipsoid": "celtstone.bodies",
    "list_bodies": "celtstone.bodies",
    "explore": "celtstone.explorer",
    "load_body": "celtstone.bodies",
    "simulate": "celtstone.simulation.integrate",
    "simulate_many": "celtstone.simulation.integrate",
    "FitResult": "celtstone.fitting",
    "Record": "celtstone.fitting",
    "fit": "celtstone.fitting",
    "make_record": "celtstone.fitting",
    "read_record": "celtstone.fitting",
    "MODELS": "celtstone.simulation.models",
    "HybridModel": "celtstone.simulation.models",
    "InitialState": "celtstone.simulation.models",
    "RollingModel": "celtstone.simulation.models",
    "SlidingModel": "celtstone.simulation.models",
    "model_from_name": "celtstone.simulation.models",
    "Trajectory": "celtstone.simulation.trajectory",
    "Sweep": "celtstone.sweep",
    "open_sweep": "celtstone.sweep",
    "CompileReport": "celtstone.precompile",
    "compile_solvers": "celtstone.precompile",
}

__getattr__, __dir__ = lazy_attributes(__name__, _LAZY, __all__)
