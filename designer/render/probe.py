"""A short probe render that measures this machine's render speed (``designer warmup``).

It renders six frames of the example survey (``designer new --template survey``) as
``designer demo`` renders them — at the edges of the flight and over the middle, so
both the terrain's and the background's cost are seen — and stores the fitted
coefficients (:mod:`designer.render_time.model`, source "probe"). About 30 s on 2
cores. Every later ``designer render`` adds a record of its own kind.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

#: frames of the example's 60 rendered by the probe: the first frame of each worker
#: builds Cycles' scene and goes into the fixed part (render_time.record); the others span the
#: share of the image on the terrain (0.2 to 1)
PROBE_FRAMES = (0, 10, 20, 29, 39, 59)


def probe_render_speed(progress=None):
    """Render the probe frames in a temporary folder; returns the stored RenderSpeed."""
    from designer.project import template, write_project
    from designer.render.job import prepare_job
    from designer.render.runner import render_frames
    from designer.render_time.record import record_render_speed

    with tempfile.TemporaryDirectory(prefix="designer-probe-") as tmp:
        tmp = Path(tmp)
        project = template("survey").project
        write_project(project, tmp / "survey.xml")
        t0 = time.perf_counter()
        prepared = prepare_job(project, tmp, tmp / "out")
        prepare_s = time.perf_counter() - t0
        frames = [i for i in PROBE_FRAMES if i < len(prepared.job.frames)]
        report = render_frames(prepared.job_path, frames, workers=project.render.workers,
                               progress=progress)
        if report.failed:
            from designer.errors import DesignerError

            raise DesignerError(f"the probe render failed (frames {report.failed}); see "
                                "'designer render' of 'designer new --template survey'")
        speed = record_render_speed(prepared, report, prepare_s, source="probe",
                                    project=project)
        if speed is None:
            from designer.errors import DesignerError

            raise DesignerError("the probe render reported no frame stages")
        return speed
