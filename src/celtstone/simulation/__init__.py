"""The run pipeline: a run's declared inputs (``schema``), the model built from them
(``models``), the checks before a run (``plausibility``), the run (``integrate``, with
``hybrid`` for the stick–slip phases) and its result (``trajectory``, ``reversals``).

This package hands no names on: import each module (``celtstone.simulation.integrate``);
``celtstone`` itself is the public interface."""
