"""The live explorer: ``celtstone serve`` and :func:`celtstone.explore`.

A page of controls (the stone, the start, the contact) that runs the simulation again
after each change and draws spin, energy and rocking, with a one-line verdict, a pinned
run to compare with, and downloads. Panel and Bokeh (the ``explore`` extra) are imported
only when an explorer is made.
"""

from celtstone.explorer.inputs import Inputs as Inputs
from celtstone.explorer.inputs import command_line as command_line
from celtstone.explorer.inputs import prepare as prepare
from celtstone.explorer.inputs import python_snippet as python_snippet
from celtstone.explorer.launch import EXTRA_HINT as EXTRA_HINT
from celtstone.explorer.launch import explore as explore
from celtstone.explorer.launch import require_panel as require_panel
from celtstone.explorer.runner import FinishedRun as FinishedRun
from celtstone.explorer.runner import Runner as Runner
