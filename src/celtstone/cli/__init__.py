"""Command-line interface: one module per subcommand, each with ``add_args`` and ``handle``
(``_methods``: the integrator options that ``run`` and ``sweep`` share)."""
