"""Test-wide settings (hypothesis runs derandomised in CI so a run is repeatable) and the
fixtures of the synthetic scenes."""

import os

import numpy as np
import pytest
from hypothesis import settings

from tests import synthetic

settings.register_profile("ci", derandomize=True, database=None, print_blob=True)
settings.register_profile("dev", database=None, print_blob=True)
settings.load_profile("ci" if os.environ.get("CI") else "dev")


@pytest.fixture(autouse=True)
def _own_cache_dir(tmp_path_factory, monkeypatch):
    """Each test its own designer cache folder (the render-speed file,
    designer.render_time.model): no test sees another's, or the user's, calibration;
    the variable reaches the processes a test starts."""
    monkeypatch.setenv("DESIGNER_CACHE_DIR", str(tmp_path_factory.mktemp("designer-cache")))


# ------------------------------------------------------------------ synthetic scenes
# The scenes themselves are defined once in tests/synthetic.py; these fixtures hand them
# to tests (factories where a test chooses the seed or lens).


@pytest.fixture
def origin_world() -> np.ndarray:
    """The UTM-sized world origin of the synthetic scenes (a fresh copy per test)."""
    return synthetic.ORIGIN_WORLD.copy()


@pytest.fixture
def make_survey():
    """``make_survey(seed, lens="opencv")`` → (interior, poses, gcps, observations)."""
    return synthetic.survey


@pytest.fixture
def small_project_file(tmp_path):
    """``small_project_file(**small_survey options)`` → path of a written small project."""
    def write(**options):
        return synthetic.write_project_file(synthetic.small_survey(**options),
                                            tmp_path / "project")
    return write


@pytest.fixture(scope="session")
def sample_site(tmp_path_factory):
    """The sample real site (designer.scene.sample_site) written once per test session:
    {'dem', 'orthophoto', 'dem_wgs84'} → path."""
    from designer.scene.sample_site import write_sample_site

    return write_sample_site(tmp_path_factory.mktemp("sample-site"))
