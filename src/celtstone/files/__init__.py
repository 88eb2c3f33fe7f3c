"""Files celtstone writes: which outputs are its own (``ownership``), writing runs
(``export``), checking names given for paths (``path_names``).

This package hands no names on: import each module."""
