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


def test_the_tests_started_first_exist() -> None:
    """Each entry of ``STARTED_FIRST`` names a test function of a test file: a renamed
    test would silently go back to its place in the collection."""
    import re
    from pathlib import Path

    from tests.conftest import STARTED_FIRST

    root = Path(__file__).resolve().parents[1]
    for entry in STARTED_FIRST:
        path, _, name = entry.partition("::")
        source = (root / path).read_text(encoding="utf-8")
        assert re.search(rf"^def {re.escape(name)}\w*\(", source, flags=re.MULTILINE), entry


def test_the_tests_started_first_come_first_in_a_worker(request: pytest.FixtureRequest) -> None:
    if not getattr(request.config.option, "loadgroup", False):
        pytest.skip("only a worker of --dist loadgroup reorders the tests")
    from tests.conftest import STARTED_FIRST, _started_first_rank

    ranks = [_started_first_rank(item.nodeid) for item in request.session.items]
    assert ranks == sorted(ranks)
    assert ranks[-1] == len(STARTED_FIRST)
