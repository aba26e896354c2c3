import pytest

import lemke


def pytest_configure(config):
    # Registered only: nothing deselects it by default, so a plain ``pytest`` runs the slow
    # tests too; ``pytest -m "not slow"`` leaves them out.
    config.addinivalue_line("markers", "slow: a test that takes tens of seconds (it still runs by default)")


@pytest.fixture(params=lemke.METHODS)
def method(request):
    """Every test that takes ``method`` runs once per Lemke method."""
    return request.param
