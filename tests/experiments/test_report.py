"""A validation report opens with its result, its question and how it was measured; the
validations share one configuration of how they render."""

from designer.experiments.psf import PSFConfig
from designer.experiments.report import Criterion, Report
from designer.experiments.settings import quality
from designer.experiments.texture import TextureConfig


def _criterion(passed: bool) -> Criterion:
    return Criterion("leak", "light outside the pixel", 0.0, "= 0", passed)


def test_the_opening_says_passed_only_when_every_criterion_passed():
    for criteria, word in (([_criterion(True), _criterion(True)], "PASSED"),
                           ([_criterion(True), _criterion(False)], "FAILED"), ([], "PASSED")):
        r = Report("Validation 9: a check")
        passed = r.opening(criteria, "**Question.** Is it right?")
        assert passed == (word == "PASSED")
        assert r.text().splitlines() == [
            "# Validation 9: a check", "", f"**Result: {word}.**", "",
            "**Question.** Is it right?", "", "## How it was measured"]


def test_the_validations_render_alike_by_default():
    for config in (PSFConfig(), TextureConfig()):
        assert config.settings == quality("metrology")
        assert config.seed == 0 and config.workers is None
    assert PSFConfig(workers=2, seed=3) == TextureConfig(workers=2, seed=3)
