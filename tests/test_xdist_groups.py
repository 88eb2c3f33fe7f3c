"""``make test``'s ``--dist loadgroup`` keeps each ``xdist_group`` on one worker: a grouped
test's node ID carries its group (the conftest hook, for pytest-xdist issue 1386), else
the expensive fixtures its group shares are computed once in each worker."""

from __future__ import annotations

import pytest


@pytest.mark.xdist_group("probe")
def test_a_grouped_test_carries_its_group(request: pytest.FixtureRequest) -> None:
    if not getattr(request.config.option, "loadgroup", False):
        pytest.skip("only a worker of --dist loadgroup groups tests")
    assert request.node.nodeid.endswith("@probe")
