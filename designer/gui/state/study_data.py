"""What the Study panel shows, without Qt: levels typed by the user, the cost of a
planned study (variants, runs, distinct renders and reconstructions, an estimate of the
time) and the contents of a study output folder (``designer study run -o DIR``).

Time estimate (seconds on one worker):

* render: per distinct image set, the render-time model with this machine's measured
  coefficients (:mod:`designer.render_time.model`: the set-up, every image's size,
  samples and share on the terrain, the run's workers);
* reconstruction + comparison: per distinct processing, its images ×
  :func:`reconstruct_seconds_per_image` (grows with the image size, measured); a
  processing whose SfM model an earlier run of the study found (same images, matching,
  calibration mode and SfM settings: the runs differ only in what follows the mapper —
  GCP roles, marking or survey error, GCP mode) pays only :data:`AFTER_SFM_SHARE` of it
  (georeferencing and the comparison); one whose features and matches an earlier run
  computed (same images, camera start values and matching settings) pays
  1 − :data:`FEATURE_SHARE`;
* each run: :data:`RUN_OVERHEAD_S` of planning (its project, prepared job and ground
  truth) and of writing its results.
"""

from __future__ import annotations

import csv
import json
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

#: reconstruction + comparison seconds per image (sparse SfM, on its own): A + B ×
#: megapixels of the rendered image, fitted to two measured studies on the 2-core
#: machine — the tiny study (``designer study new --template tiny``): 1.39 s wall
#: (1.93 s CPU) for 18 images of 0.019 MP (0.077 s per image; reconstruct 0.77 s +
#: compare 0.63 s, 2026-12-06), and the gcp-count example: 21 CPU seconds for 12 images
#: of 0.31 MP (1.75 s per image; docs/studies.md); the line through both has a
#: negative A, so A is 0 and B lies between the two images' 4.0 and 5.6 s per MP (the
#: tiny study's estimate then sits midway between its measured CPU and wall seconds,
#: the gcp-count example's 11 % low) —
RECONSTRUCT_S_A = 0.0
RECONSTRUCT_S_B_PER_MP = 5.0
#: — up to at most this (the feature count is capped, so larger images cost little more:
#: ``designer demo`` reconstructed the example's 60 images of 1.25 MP in 418 s, dense
#: cloud included; docs/benchmarks.md)
RECONSTRUCT_S_MAX = 7.0
#: a dense cloud (``<dense mode="cpu"/>``) costs this much more: 46–54 s per nadir run of
#: 12 images in the flight-geometry example against 21–54 s without (docs/studies.md)
DENSE_FACTOR = 1.3


#: the share of a reconstruction's time spent on feature extraction and matching, which
#: runs of the same images share through the feature cache: ``designer demo`` on the
#: example survey spent 129.8 s on features and 102.8 s on matching of 418.6 s, 56 %
#: (dense cloud included; docs/benchmarks.md)
FEATURE_SHARE = 0.55
#: the share of a reconstruction + comparison a run pays when it reuses the SfM model
#: of an earlier run: the tiny study's runs that reused it took 0.27 s against 1.39 s
#: (0.19, 2026-12-06), the gcp-count example's 3.2 s against 21 s (0.15)
AFTER_SFM_SHARE = 0.2
#: seconds of each run outside its render and reconstruction (the study's planning of
#: the run: project, prepared render job, ground truth; its results and figures): the
#: tiny study's 3 runs took 10.0 s wall of which the stages took 4.5 s (1.8 s per run,
#: an idle machine, 2026-12-06); on a busy one earlier, 4.3 to 6.8 s per run
RUN_OVERHEAD_S = 3.0


def _sfm_key(features_key: str, project) -> str:
    """What a run's SfM model depends on besides its features and matches: the
    calibration mode and the mapper's settings (as the study's SfM group)."""
    processing = project.processing
    if processing is None:
        return features_key
    return features_key + repr((processing.calibration.mode, processing.sfm))


def _features_key(render_key: str, project) -> str:
    """What a run's features and matches depend on besides the images: the camera's start
    values (calibration settings) and the matching settings."""
    processing = project.processing
    if processing is None:
        return render_key
    return render_key + repr((processing.calibration, processing.matching))


def reconstruct_seconds_per_image(project, interior) -> float:
    """Estimated reconstruction + comparison seconds per image of ``project``."""
    from designer.gui.state.derived import rendered_size_px

    w_px, h_px = rendered_size_px(interior, project.render.resolution_scale)
    seconds = min(RECONSTRUCT_S_A + RECONSTRUCT_S_B_PER_MP * w_px * h_px / 1e6,
                  RECONSTRUCT_S_MAX)
    dense = project.processing is not None and project.processing.dense != "none"
    return seconds * (DENSE_FACTOR if dense else 1.0)


def parse_levels(text: str) -> tuple[str, ...]:
    """The levels in ``text``: values separated by spaces or commas, or a range
    ``START:STOP:STEP`` (inclusive, as ``<range>`` in a study file). ValueError says why
    the text is not usable."""
    text = text.strip()
    if not text:
        raise ValueError("no levels; type values separated by spaces, or START:STOP:STEP")
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise ValueError(f"'{text}': a range is START:STOP:STEP, e.g. 20:40:5")
        try:
            start, stop, step = (float(p) for p in parts)
        except ValueError:
            raise ValueError(f"'{text}': a range needs three numbers, e.g. 20:40:5") from None
        from designer.study.spec import range_levels

        return range_levels(start, stop, step)
    return tuple(v for v in re.split(r"[\s,;]+", text) if v)


def parse_range(text: str) -> tuple[float, float, float] | None:
    """(start, stop, step) when ``text`` is a range START:STOP:STEP, else None (values, or
    not usable: :func:`parse_levels` says why)."""
    parts = text.strip().split(":")
    if len(parts) != 3:
        return None
    try:
        return tuple(float(p) for p in parts)
    except ValueError:
        return None


def range_text(spec: tuple[float, float, float]) -> str:
    """A range as the Study panel shows it: START:STOP:STEP."""
    return ":".join(f"{v:.15g}" for v in spec)


# ------------------------------------------------------------------ cost of a plan
@dataclass(frozen=True)
class PlanCost:
    variants: int
    runs: int
    renders: int          # distinct image sets
    reconstructions: int  # distinct processings
    images_rendered: int
    render_s: float
    reconstruct_s: float
    #: each run's planning and results (:data:`RUN_OVERHEAD_S`)
    overhead_s: float = 0.0
    #: runs that would fail, told before the study runs (:func:`plan_warnings`)
    warnings: tuple[str, ...] = ()
    #: the render coefficients the estimate's text names: those of the first render's
    #: kind of image (``render_time.model.RenderSpeed``; None without a render)
    basis_speed: object = None

    @property
    def total_s(self) -> float:
        return self.render_s + self.reconstruct_s + self.overhead_s


def _render_key(project) -> str:
    """What the images depend on: the project without its processing settings and the
    GCP survey error (ground truth only)."""
    scene = project.scene
    if scene.targets is not None:
        scene = replace(scene, targets=replace(scene.targets, survey_accuracy=None))
    return repr(replace(project, name="", description=None, processing=None, scene=scene))


def plan_cost(plan, heightfield, speed=None) -> PlanCost:
    """Counts and estimated seconds (one worker) of a planned study
    (:func:`designer.study.design.plan_study`); ``heightfield``: the base terrain's;
    ``speed``: the render coefficients of every image (default: this machine's for each
    kind of image, its own records, :func:`designer.render_time.model.load_speed`)."""
    from designer.project.interiors import interior_from_camera
    from designer.render_time.model import (
        estimate_render_s,
        load_speed,
        project_image_costs,
        render_workers,
    )
    from designer.survey.project_poses import project_images, project_stations
    from designer.survey.surroundings import rendered_terrain

    basis = speed
    renders: dict[str, tuple[int, float]] = {}
    render_s = 0.0
    processings: dict[str, int] = {}
    features_done: set[str] = set()
    sfm_done: set[str] = set()
    reconstruct_s = 0.0
    for run in plan.runs:
        project = run.project
        key = _render_key(project)
        if key not in renders:
            stations, camera_id = project_stations(project, heightfield)
            interior = interior_from_camera(project.camera(camera_id))
            renders[key] = (len(stations), reconstruct_seconds_per_image(project, interior))
            images = project_images(project, heightfield)
            # over the terrain as rendered, with its surroundings
            costs = project_image_costs(project, images, rendered_terrain(
                project, heightfield, images).heightfield)
            render_s += estimate_render_s(costs, render_workers(project, len(costs)),
                                          speed=speed)
            if basis is None and costs:
                basis = load_speed(costs[0])
        proc_key = repr(replace(project, name="", description=None))
        if proc_key not in processings:
            n_images, per_image_s = renders[key]
            processings[proc_key] = n_images
            features_key = _features_key(key, project)
            sfm_key = _sfm_key(features_key, project)
            if sfm_key in sfm_done:
                share = AFTER_SFM_SHARE
            elif features_key in features_done:
                share = 1.0 - FEATURE_SHARE
            else:
                share = 1.0
            features_done.add(features_key)
            sfm_done.add(sfm_key)
            reconstruct_s += n_images * per_image_s * share
    return PlanCost(plan.n_variants, len(plan.runs), len(renders), len(processings),
                    sum(n for n, _ in renders.values()), render_s, reconstruct_s,
                    overhead_s=len(plan.runs) * RUN_OVERHEAD_S, basis_speed=basis)


#: control GCPs a georeferencing on GCPs needs (designer.sfm.process_free)
MIN_CONTROL_GCPS = 3


def _gcp_shortfall(project) -> str | None:
    """Why every reconstruction of ``project`` would fail for want of control GCPs
    (its GCP mode georeferences on them and it has fewer than 3), or None."""
    from designer.project import model as m

    p = project.processing or m.Processing()
    mode = p.gcps.mode
    if mode == "none" or (mode == "bundle" and p.position_prior.mode != "none"):
        return None
    from designer.project.processing import control_count

    targets = project.targets
    n = control_count(p.gcps.control, targets)
    if n >= MIN_CONTROL_GCPS:
        return None
    has = (f"the project has {len(targets)} GCP targets" if n == len(targets) else
           f"the project has {n} control GCPs of {len(targets)} GCP targets")
    other = " or give camera-position priors" if mode == "bundle" else ""
    return (f"GCP mode {mode} needs at least {MIN_CONTROL_GCPS} control GCPs and {has}; "
            f"add GCP targets, or set the GCP mode to none{other} (Processing panel)")


def plan_warnings(plan) -> list[str]:
    """What can be told before a study runs about runs that would fail: runs whose
    processing georeferences on GCPs the project lacks. One line per reason."""
    by_reason: dict[str, list[str]] = {}
    for run in plan.runs:
        reason = _gcp_shortfall(run.project)
        if reason is not None:
            by_reason.setdefault(reason, []).append(run.run_id)
    total = len(plan.runs)
    out = []
    for reason, ids in by_reason.items():
        if len(ids) == total:
            who = f"every run ({total} of {total})"
        else:
            who = (f"{len(ids)} of {total} runs (" + ", ".join(ids[:4])
                   + (", …" if len(ids) > 4 else "") + ")")
        out.append(f"{who} would fail: {reason}")
    return out


def duration_text(seconds: float) -> str:
    """The window's one way of writing a time (:func:`designer.gui.state.wording.duration`)."""
    from designer.gui.state.wording import duration

    return duration(seconds)


# ------------------------------------------------------------------ output folders
@dataclass
class StudyFolder:
    """A study output folder as the panel shows it."""

    path: Path
    name: str = ""
    state: str = "empty"  # empty (no study yet), partial (runs missing), complete
    runs_total: int = 0
    runs_done: int = 0
    rows: list[dict] = field(default_factory=list)
    metrics: tuple[str, ...] = ()
    summary: dict | None = None
    figures: list[Path] = field(default_factory=list)

    @property
    def columns(self) -> list[str]:
        """Table columns: the run, each factor's level, the metrics, the study's cost,
        seconds, status."""
        factors = sorted({k for r in self.rows for k in r if k.startswith("factor:")})
        cost = ((self.summary or {}).get("cost") or {}).get("column")
        extra = [cost] if cost and cost != "total_s" and cost not in self.metrics else []
        metrics = [m for m in self.metrics if m != "total_s"]
        return ["run", *factors, *metrics, *extra, "total_s", "status"]

    @property
    def failed_rows(self) -> list[dict]:
        """The finished runs that failed (status other than ok)."""
        return [r for r in self.rows if str(r.get("status", "")) != "ok"]

    def failure_reason(self, row: dict) -> str:
        """A failed run's reason without the "failed:" and its run folder."""
        reason = str(row.get("status", "")).removeprefix("failed:").strip()
        return re.sub(r"^\S*/runs/[^/\s:]+(/\S*)?: ", "", reason)

    def outcome(self) -> str:
        """``N of M runs succeeded, K failed: first reason`` (finished runs only)."""
        failed = self.failed_rows
        text = (f"{len(self.rows) - len(failed)} of {self.runs_total} runs succeeded"
                if failed else f"{self.runs_done} of {self.runs_total} runs")
        if failed:
            text += f", {len(failed)} failed: {self.failure_reason(failed[0])}"
        return text

    def describe(self) -> str:
        if self.state == "empty":
            return f"{self.path}: no study yet"
        text = f"study '{self.name}': {self.runs_done} of {self.runs_total} runs finished"
        if self.summary is not None:
            s = self.summary
            text += (f"; {s.get('renders')} renders, {s.get('reconstructions')} "
                     f"reconstructions, {s.get('cache_hits')} cache hits, "
                     f"{s.get('failed')} failed")
        failed = self.failed_rows
        if failed:
            if self.summary is None:
                text += f"; {len(failed)} failed"
            text += f" (first: {self.failure_reason(failed[0])})"
        return text + ("" if self.state == "complete" else "; not finished (Resume continues)")


def read_folder(path: str | Path, contents: bool = True) -> StudyFolder:
    """The study in ``path``: its state, its rows (results.csv, or the finished runs'
    result.json while it is not complete), summary.json and the report's figures
    (``contents=False``: the state and counts only)."""
    from designer.errors import DesignerError
    from designer.study.spec import DEFAULT_METRICS

    folder = StudyFolder(Path(path))
    marker = folder.path / "study.json"
    if not marker.is_file():
        return folder
    try:
        study = json.loads(marker.read_text())
    except (OSError, json.JSONDecodeError) as error:
        raise DesignerError(f"{marker}: not a study record ({error}); open the folder "
                            "'designer study run -o DIR' wrote") from None
    folder.name = str(study.get("name", ""))
    run_ids = list(study.get("runs", []))
    folder.runs_total = len(run_ids)
    done = [r for r in run_ids if (folder.path / "runs" / r / "result.json").is_file()]
    folder.runs_done = len(done)
    results = folder.path / "results.csv"
    summary = folder.path / "summary.json"
    complete = folder.runs_done == folder.runs_total and results.is_file() and \
        summary.is_file()
    folder.state = "complete" if complete else "partial"
    if not contents:
        return folder
    if complete:
        with results.open(newline="") as table:
            folder.rows = list(csv.DictReader(table))
        folder.summary = json.loads(summary.read_text())
        folder.summary.pop("rows", None)
        folder.metrics = tuple(folder.summary.get("metrics") or DEFAULT_METRICS)
    else:
        folder.rows = [json.loads((folder.path / "runs" / r / "result.json").read_text())
                       for r in done]
        folder.metrics = DEFAULT_METRICS
    folder.figures = _figures(folder.path)
    return folder


@dataclass(frozen=True)
class LevelChart:
    """One metric of a study against one factor's levels, as the report draws it
    (:func:`designer.study.report.draw_level_chart`)."""

    factor: str
    metric: str
    title: str
    levels: list[str]
    stats: list[dict]           # per level: mean, low, high (95 % interval) or None
    points: list[list[float]]   # per level: each finished run's value
    is_cost: bool = False

    @property
    def name(self) -> str:
        """The selector's words: the metric against the factor (no identifier)."""
        return f"{column_words(self.metric)} against {column_words('factor:' + self.factor)}"

    @property
    def identifiers(self) -> str:
        """What results.csv and the study file call the two (the selector's tooltip)."""
        return f"{self.metric} against the levels of {self.factor}"


def _number(value) -> float | None:
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if number == number else None


def level_charts(folder: StudyFolder) -> list[LevelChart]:
    """The charts of a finished study, one per factor and metric (the study's metrics,
    then its cost), from summary.json and results.csv."""
    from designer.study.levels import rows_at_level

    summary = folder.summary or {}
    design = summary.get("design", "one-at-a-time")
    cost = (summary.get("cost") or {}).get("column")
    metrics = [*folder.metrics, *([cost] if cost and cost not in folder.metrics else [])]
    # results.csv holds text: the variant as a number, as the study wrote it (the base
    # variant, 0, gives the other factors' base levels)
    table = [{**r, "variant": int(v) if (v := _number(r.get("variant"))) is not None
              else r.get("variant")} for r in folder.rows]
    charts = []
    for factor, info in (summary.get("factors") or {}).items():
        levels = [str(lv["level"]) for lv in info.get("levels", [])]
        for metric in metrics:
            stats = [lv["metrics"].get(metric) or {"mean": None}
                     for lv in info.get("levels", [])]
            points = []
            for level in levels:
                rows = rows_at_level(design, table, factor, level)
                values = [_number(r.get(metric)) for r in rows
                          if str(r.get("status", "")) == "ok"]
                points.append([v for v in values if v is not None])
            charts.append(LevelChart(factor, metric, column_words(metric), levels, stats,
                                     points, is_cost=metric == cost))
    return charts


def column_words(column: str) -> str:
    """A column of the Study results table (:attr:`StudyFolder.columns`) in words: a
    factor's (``factor:altitude-m``), a metric's or cost's, the run and its status."""
    from designer.study.report import label
    from designer.study.words import factor_words, metric_words

    if column.startswith("factor:"):
        return factor_words(column.removeprefix("factor:"))
    if column in ("run", "status"):
        return column
    try:
        return metric_words(column)
    except KeyError:
        return label(column)


def figure_words(stem: str) -> str:
    """A figure of the study's report (``figures/STEM.png``) in words: the accuracy
    against cost, the error maps of a factor's levels, a factor's charts."""
    from designer.study.words import factor_words

    if stem == "pareto":
        return "accuracy against cost (the report's figure)"
    for prefix, what in (("maps-", "error maps over the levels of"),
                         ("factor-", "every metric against")):
        if stem.startswith(prefix):
            try:
                return f"{what} {factor_words(stem.removeprefix(prefix))}"
            except KeyError:
                break
    return stem.replace("-", " ").replace("_", " ")


def _figures(path: Path) -> list[Path]:
    """The report's figures in the report's order (report.md), then any others."""
    found = sorted((path / "figures").glob("*.png"))
    order = []
    report = path / "report.md"
    if report.is_file():
        for name in re.findall(r"\]\(figures/([^)]+\.png)\)", report.read_text()):
            p = path / "figures" / name
            if p in found and p not in order:
                order.append(p)
    return order + [p for p in found if p not in order]


def cell_text(value) -> str:
    """A results value for the table: numbers to 4 significant digits."""
    if value is None or value == "":
        return ""
    try:
        number = float(value)
    except (TypeError, ValueError):
        return str(value)
    if isinstance(value, str) and not re.fullmatch(r"[-+0-9.eE]+", value):
        return value
    return f"{number:.4g}"
