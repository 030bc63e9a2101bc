"""The timings of one render, each named for what it counts.

One definition serves the command's last line, the manifest (``times_last_run``) and the
``finished`` progress event the desktop designer reads, so no two places time the same
render differently:

* ``command_wall_s`` — wall seconds of the whole render, from reading the project to
  the last file written (the Python start-up before it is not counted: ~1 s);
* ``prepare_s`` — of it, preparing the scene (terrain, texture and light bakes, the job);
* ``ground_truth_s`` — of it, writing the ground truth;
* ``images_wall_s`` — of it, the images: worker start-up, scene build, every frame;
* ``cycles_s_per_image`` — the mean wall seconds of Cycles' path tracing per image
  rendered (the worker's ``cycles_s`` stage), without start-up, bakes or effects.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass


@dataclass(frozen=True)
class RenderTimes:
    """Seconds of one render run (see the module docstring)."""

    images: int
    command_wall_s: float
    prepare_s: float
    ground_truth_s: float
    images_wall_s: float
    cycles_s_per_image: float | None

    @classmethod
    def measured(cls, report, command_wall_s: float, prepare_s: float,
                 ground_truth_s: float) -> RenderTimes:
        """From a run's :class:`~designer.render.runner.RenderReport` and the pipeline's
        clocks; figures rounded to milliseconds (what the manifest keeps)."""
        cycles = [s["cycles_s"] for i, s in report.stages.items()
                  if i in report.rendered and "cycles_s" in s]
        per_image = round(sum(cycles) / len(cycles), 3) if cycles else None
        return cls(len(report.rendered), round(command_wall_s, 3), round(prepare_s, 3),
                   round(ground_truth_s, 3), round(report.wall_seconds, 3), per_image)

    def text(self) -> str:
        """'in 18.0 s wall for the whole command (preparing the scene 7.9 s, ground truth
        0.3 s, images 9.8 s); Cycles 0.40 s per image'."""
        line = (f"in {self.command_wall_s:.1f} s wall for the whole command (preparing the "
                f"scene {self.prepare_s:.1f} s, ground truth {self.ground_truth_s:.1f} s, "
                f"images {self.images_wall_s:.1f} s)")
        if self.cycles_s_per_image is not None:
            line += f"; Cycles {self.cycles_s_per_image:.2f} s per image"
        return line

    def to_json(self) -> dict:
        return asdict(self)
