import pytest

import lemke


@pytest.fixture(params=lemke.METHODS)
def method(request):
    """Every test that takes ``method`` runs once per Lemke method."""
    return request.param
