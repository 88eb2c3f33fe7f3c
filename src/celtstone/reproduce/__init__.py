"""Reproduce the paper's findings: Figures 2 and 3, the friction threshold, a report.

>>> from celtstone.reproduce import reproduce          # doctest: +SKIP
>>> reproduce(["all"], out="results")                  # doctest: +SKIP

Each target (one study's fig2, fig3 or threshold) is written into a staging directory
``out/.reproduce.<pid>.<random>.part`` and its files are moved into ``out`` only when
the target has finished, its numbers (``data/TARGET_KEY.json``, KEY the study's key:
the body, or ``BODY+VARIANT`` for another contact) last. An interrupted
target (Ctrl-C, SIGTERM, an error) leaves nothing of its own and no staging directory;
one left by a killed process is removed by the next reproduction into ``out``. Every
target's numbers carry the identity of the run that made them (``run``: id, time,
celtstone version, targets), which the report shows.
"""

# The atlas (celtstone.atlas) reads the studies, findings and judges through these names
# only: this is the one interface between the two packages (an import-linter contract).
# boundary, case_name, figure2_models, summarise and threshold_numbers are for the atlas,
# not in ``__all__`` (the documented API).
# every module here is light to import (matplotlib, pandas and xarray are imported where a
# figure or table is made), so the names are imported eagerly: a lazy ``figure2`` would be
# replaced by the submodule of that name as soon as the submodule is imported
from celtstone.reproduce.atlas_report import PARAMETER_WORDS as PARAMETER_WORDS
from celtstone.reproduce.cases import case_name as case_name
from celtstone.reproduce.cases import summarise as summarise
from celtstone.reproduce.figure2 import figure2 as figure2
from celtstone.reproduce.figure2 import figure2_models as figure2_models
from celtstone.reproduce.figure3 import figure3 as figure3
from celtstone.reproduce.findings import FINDINGS as FINDINGS
from celtstone.reproduce.findings import JUDGES as JUDGES
from celtstone.reproduce.progress import Progress as Progress
from celtstone.reproduce.report import render_report as render_report
from celtstone.reproduce.report import write_report as write_report
from celtstone.reproduce.study import REALISTIC_STUDIES as REALISTIC_STUDIES
from celtstone.reproduce.study import STUDIES as STUDIES
from celtstone.reproduce.study import TARGETS as TARGETS
from celtstone.reproduce.study import Study as Study
from celtstone.reproduce.study import realistic_study_for as realistic_study_for
from celtstone.reproduce.study import reduced as reduced
from celtstone.reproduce.study import study_for as study_for
from celtstone.reproduce.targets import reproduce as reproduce
from celtstone.reproduce.targets import run_identity as run_identity
from celtstone.reproduce.threshold import boundary as boundary
from celtstone.reproduce.threshold import threshold as threshold
from celtstone.reproduce.threshold import threshold_numbers as threshold_numbers

__all__ = [
    "FINDINGS",
    "JUDGES",
    "PARAMETER_WORDS",
    "REALISTIC_STUDIES",
    "STUDIES",
    "TARGETS",
    "Progress",
    "Study",
    "figure2",
    "figure3",
    "realistic_study_for",
    "reduced",
    "render_report",
    "reproduce",
    "run_identity",
    "study_for",
    "threshold",
    "write_report",
]
