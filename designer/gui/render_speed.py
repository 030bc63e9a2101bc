"""This machine's measured render speed, kept between sessions (Qt settings).

The estimates start from the reference machine's figures (``designer bench render``,
as ``designer plan`` uses them). After every render the window stores how much longer
(or shorter) the images took here — wall-clock seconds of the run, scene set-up
included, per rendered image, over the reference estimate — and scales every estimate
by that factor from then on.
"""

from __future__ import annotations

import time

KEY_FACTOR = "render/speed_factor"
KEY_IMAGES = "render/speed_images"
KEY_WHEN = "render/speed_measured"


def speed_factor(settings) -> tuple[float, int, str] | None:
    """(factor over the reference estimate, images it was measured on, when) or None."""
    if settings is None:
        return None
    try:
        factor = float(settings.value(KEY_FACTOR, 0.0))
        images = int(settings.value(KEY_IMAGES, 0))
    except (TypeError, ValueError):
        return None
    if not factor > 0 or images <= 0:
        return None
    return factor, images, str(settings.value(KEY_WHEN, ""))


def record(settings, wall_s: float, n_rendered: int, reference_s_per_image: float) -> float:
    """Store this machine's factor from a finished run; returns it."""
    factor = wall_s / (n_rendered * reference_s_per_image)
    settings.setValue(KEY_FACTOR, factor)
    settings.setValue(KEY_IMAGES, int(n_rendered))
    settings.setValue(KEY_WHEN, time.strftime("%Y-%m-%d %H:%M"))
    settings.sync()
    return factor


def describe(settings) -> str:
    """Where the estimate comes from, for the panels."""
    known = speed_factor(settings)
    if known is None:
        return "reference machine; a first render here calibrates it"
    factor, images, when = known
    return (f"this machine, measured over {images} image(s) on {when}: "
            f"{factor:.2f} × the reference")


def calibrated(settings, reference_s: float) -> float:
    known = speed_factor(settings)
    return reference_s * (known[0] if known else 1.0)
