"""Render settings that trade time for geometric accuracy, and the quality presets.

A :class:`RenderSettings` is what the accuracy sweep varies (``designer bench accuracy``)
and what the validations render with. The presets were picked from the measured Pareto
front of render time against corner-error spread (docs/validation.md, "What accuracy
costs in time"); ``PLAIN_64`` is the old 'metrology' setting they are measured against.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, replace

from designer.render.job_spec import PIXEL_FILTER_NAMES, AdaptiveSampling, RenderSpec

PIXEL_FILTERS = PIXEL_FILTER_NAMES
INTERPOLATIONS = ("Closest", "Linear")


@dataclass(frozen=True)
class RenderSettings:
    """Cycles settings for an emission-only scene, in Blender's terms.

    Attributes:
        samples: samples per pixel (the maximum when adaptive sampling is on).
        pixel_filter: 'BOX', 'GAUSSIAN' or 'BLACKMAN_HARRIS'.
        filter_width_px: pixel filter width (px); a 1 px box is exact area sampling.
        adaptive_threshold: Cycles' adaptive-sampling noise threshold, ``None`` = off.
        adaptive_min_samples: samples every pixel takes before adaptive sampling may
            stop it (0: Cycles chooses).
        oversample: render ``oversample``× larger and average blocks in linear light.
        interpolation: texture interpolation, 'Closest' or 'Linear'.
    """

    samples: int = 16
    pixel_filter: str = "BOX"
    filter_width_px: float = 1.0
    adaptive_threshold: float | None = None
    adaptive_min_samples: int = 0
    oversample: int = 1
    interpolation: str = "Closest"

    def __post_init__(self) -> None:
        if self.samples < 1:
            raise ValueError(f"samples = {self.samples} must be >= 1")
        if self.pixel_filter not in PIXEL_FILTERS:
            raise ValueError(f"pixel_filter {self.pixel_filter!r} not in {PIXEL_FILTERS}")
        if self.interpolation not in INTERPOLATIONS:
            raise ValueError(f"interpolation {self.interpolation!r} not in {INTERPOLATIONS}")
        if self.oversample < 1:
            raise ValueError(f"oversample = {self.oversample} must be >= 1")

    def job_render(self, seed: int = 0) -> RenderSpec:
        """The Cycles settings of a worker job (oversampling is done by the caller)."""
        adaptive = (None if self.adaptive_threshold is None else
                    AdaptiveSampling(self.adaptive_threshold, self.adaptive_min_samples))
        return RenderSpec(samples=self.samples, seed=seed, pixel_filter=self.pixel_filter,
                          filter_width_px=float(self.filter_width_px), format="png",
                          bit_depth=8, adaptive_sampling=adaptive)

    def label(self) -> str:
        """Short human-readable description, e.g. '16 spp, adaptive 0.01, box 1 px'."""
        parts = [f"{self.samples} spp"]
        if self.adaptive_threshold is not None:
            parts.append(f"adaptive {self.adaptive_threshold:g}/min {self.adaptive_min_samples}")
        parts.append(f"{self.pixel_filter.lower().replace('_', '-')} {self.filter_width_px:g} px")
        if self.oversample > 1:
            parts.append(f"oversample {self.oversample}x")
        if self.interpolation != "Closest":
            parts.append(self.interpolation.lower())
        return ", ".join(parts)

    def to_dict(self) -> dict:
        return asdict(self)

    def with_(self, **changes) -> RenderSettings:
        return replace(self, **changes)


#: the three presets, chosen from ``designer bench accuracy`` (docs/validation.md): the
#: cheapest measured settings as accurate as plain 4, 16 and 64 spp. Adaptive sampling
#: cannot help below 16 spp (Cycles renders 16 samples in every pixel before its first
#: convergence check), so draft and survey stay plain; metrology gets plain 64 spp's
#: corner accuracy in a third of its time.
QUALITY_PRESETS: dict[str, RenderSettings] = {
    "draft": RenderSettings(samples=4),
    "survey": RenderSettings(samples=16),
    "metrology": RenderSettings(samples=64, adaptive_threshold=0.01, adaptive_min_samples=4),
}
#: the reference every preset's cost is compared with: plain Cycles at 64 spp
PLAIN_64 = RenderSettings(samples=64)


def quality(name: str) -> RenderSettings:
    """The preset called ``name`` (draft, survey, metrology)."""
    try:
        return QUALITY_PRESETS[name]
    except KeyError:
        raise ValueError(f"unknown quality {name!r}; use one of "
                         f"{', '.join(QUALITY_PRESETS)}") from None


@dataclass(frozen=True)
class ValidationConfig:
    """How a render validation (PSF, texture) renders: its Cycles settings (the
    'metrology' preset by default), the noise seed, and the number of render workers
    (``None``: as many as the machine suits)."""

    settings: RenderSettings = field(default_factory=lambda: quality("metrology"))
    seed: int = 0
    workers: int | None = None
