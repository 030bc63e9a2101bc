"""The Render and Flight panels' render figures in words: each quality's cost with the
set-up (paid once per render) apart from the seconds each image adds, and the rendered
images' count in the right number."""

from __future__ import annotations

from designer.gui.state.wording import count, duration


def preset_cost_lines(estimates: dict[str, tuple[int, object]]) -> list[str]:
    """One line per quality preset from ``{preset: (samples, RenderEstimate)}``, the
    seconds each image adds apart from the set-up, which follows on a line of its own
    ('draft: 4 samples, 0.4 s per image, 22 s for 1 image' … 'each total includes 21 s
    of set-up …'): a set-up that dominates a render of few images would otherwise make
    every quality look as expensive per image. A set-up that differs between presets is
    given on each line."""
    setups = {duration(e.setup_s) for _spp, e in estimates.values()}
    lines = []
    for preset, (samples, e) in estimates.items():
        own = f" (with {duration(e.setup_s)} of set-up)" if len(setups) > 1 else ""
        lines.append(f"{preset}: {samples} samples, {duration(e.per_image_s)} per image, "
                     f"{duration(e.total_s)} for {count(e.n_images, 'image')}{own}")
    if len(setups) == 1:
        lines.append(f"each total includes {setups.pop()} of set-up (scene, texture, "
                     "Blender's start), once per render")
    return lines


def flight_estimate_line(estimate, samples: int, basis: str) -> str:
    """The Flight panel's line: '≈ 68 s to render (1.0 s per image at 16 samples + 9.7 s
    set-up; BASIS)'."""
    return (f"≈ {duration(estimate.total_s)} to render ({duration(estimate.per_image_s)} "
            f"per image at {samples} samples + {duration(estimate.setup_s)} set-up; "
            f"{basis})")


def up_to_date_line(n_images: int) -> str:
    """'the 60 rendered images are up to date with the project'; one image: 'the
    rendered image is …'."""
    if n_images == 1:
        return "the rendered image is up to date with the project"
    return f"the {n_images} rendered images are up to date with the project"
