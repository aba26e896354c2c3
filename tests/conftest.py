from pathlib import Path

import pytest

import lemke

HERE = Path(__file__).resolve().parent


@pytest.fixture(params=lemke.METHODS)
def method(request):
    """Every test that takes ``method`` runs once per Lemke method."""
    return request.param
