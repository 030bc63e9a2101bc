"""The accuracy report: summary.json's figures as Markdown and HTML, and a terminal table.

The report holds what a surveyor expects of a DEM/point-cloud check: the inputs, the
classical and robust statistics of the signed distances (Höhle & Höhle 2009; ASPRS
2014), the share within tolerances, the histogram and the error map, then GCP /
check-point errors and camera pose errors when they were computed. Images are linked
by file name (they sit beside the report). Files are written atomically.
"""

from __future__ import annotations

import html
import os
from pathlib import Path

from designer.atomic import write_text_atomic
from designer.evaluate.statistics import format_statistics


def area_words(area: dict) -> str:
    """Which points the statistics cover, in words (the summary's ``area`` record)."""
    if not area.get("extent_m"):
        return area["name"]
    x0, x1, y0, y1 = area["extent_m"]
    return (f"{area['name']}, X {x0:.1f} to {x1:.1f}, Y {y0:.1f} to {y1:.1f} "
            f"({area['points_left_out']:,} points outside it left out)")


def format_summary(summary: dict) -> str:
    """A plain-text table of the distance statistics (and GCP / pose RMSE if present)."""
    rows = format_statistics(summary["distances"])
    if summary.get("area"):
        rows.insert(0, ("statistics over", area_words(summary["area"])))
    surface = summary["inputs"].get("surface")
    if surface:
        rows.insert(0, ("true surface", {"dtm": "DTM (bare earth)",
                                         "dsm": "DSM (surface)"}[surface]))
    gcp = summary.get("gcps")
    if gcp:
        for role in ("check", "control"):
            s = gcp["summary"][role]
            if s["n"]:
                rows.append((f"{role} points RMSE XY / Z", f"{s['rmse_XY']:.4f} / "
                             f"{s['rmse_Z']:.4f} m (n = {s['n']})"))
    poses = summary.get("cameras")
    if poses:
        s = poses["summary"]
        rows.append(("camera RMSE XYZ / rotation", f"{s['rmse_XYZ']:.4f} m / "
                     f"{s['rotation_rmse_deg']:.4f}° (n = {s['n']})"))
    width = max(len(label) for label, _ in rows)
    title = "signed distance, cloud to mesh (+ above the mesh)"
    lines = [title, "-" * max(len(title), width + 20)]
    lines += [f"{label:<{width}}  {value}" for label, value in rows]
    return "\n".join(lines)


_SURFACE_WORDS = {
    "dtm": "DTM, bare earth (terrain and GCP targets; no objects, buildings or vegetation)",
    "dsm": "DSM, the surface with what stands on the ground (objects, buildings, vegetation)",
}


def _markdown(summary: dict, images: dict[str, str]) -> str:
    inp = summary["inputs"]
    lines = ["# Accuracy report", "",
             f"- cloud: `{inp['cloud']}` ({inp['n_points']:,} points)",
             f"- reference mesh: `{inp['mesh']}` ({inp['n_faces']:,} triangles)"]
    if inp.get("surface"):
        lines.append(f"- true surface: {_SURFACE_WORDS[inp['surface']]}")
    if inp.get("offset"):
        lines.append(f"- offset added to the cloud: {inp['offset']} m")
    if inp.get("max_distance") is not None:
        lines.append(f"- maximum distance: {inp['max_distance']} m (farther points left out)")
    area = summary.get("area")
    if area:
        lines.append(f"- statistics over: {area_words(area)}")
    lines += [f"- **warning**: {w}" for w in summary.get("warnings") or []]
    lines += ["- distance: signed, exact point-to-triangle, positive above (outside) the "
              "mesh; sign from the nearest feature's pseudo-normal",
              f"- mesh index {summary['timing']['index_s']:.2f} s, distances "
              f"{summary['timing']['distances_s']:.2f} s", "",
              "## Signed distances", "", "| statistic | value |", "|---|---|"]
    lines += [f"| {label} | {value} |" for label, value in format_statistics(
        summary["distances"])]
    if "histogram" in images:
        lines += ["", f"![Histogram of signed distances]({images['histogram']})"]
    grid = summary.get("error_map")
    if grid and "error_map" in images:
        lines += ["", "## Error map", "",
                  f"Nearest-neighbour grid, {grid['cell_m']:g} m cells, {grid['cols']} x "
                  f"{grid['rows']} ({grid['filled_share'] * 100:.1f} % filled); "
                  f"north-west corner E {grid['x_min']:.3f}, N {grid['y_max']:.3f}.", "",
                  f"![Error map]({images['error_map']})"]
    if summary.get("gcps"):
        from designer.evaluate.gcp import format_gcp_table

        lines += ["", "## Ground control and check points", "",
                  f"Errors = estimated − {summary['gcps']['reference']} position (m).", ""]
        lines += format_gcp_table(summary["gcps"])
    if summary.get("cameras"):
        from designer.evaluate.poses import format_pose_table

        lines += ["", "## Camera poses", ""]
        lines += format_pose_table(summary["cameras"])
    return "\n".join(lines) + "\n"


def _html(markdown: str) -> str:
    """A small Markdown subset (headings, lists, tables, images) as a standalone page."""
    body, table, items = [], False, False
    for line in markdown.splitlines():
        if items and not line.startswith("- "):
            body.append("</ul>")
            items = False
        if line.startswith("|"):
            cells = [html.escape(c.strip()) for c in line.strip("|").split("|")]
            if set("".join(cells)) <= set("-: "):
                continue
            tag = "th" if not table else "td"
            if not table:
                body.append("<table>")
                table = True
            body.append("<tr>" + "".join(f"<{tag}>{c}</{tag}>" for c in cells) + "</tr>")
            continue
        if table:
            body.append("</table>")
            table = False
        if line.startswith("!["):
            alt, src = line[2:].split("](", 1)
            body.append(f'<p><img src="{html.escape(src[:-1])}" alt="{html.escape(alt)}"></p>')
        elif line.startswith("#"):
            level = len(line) - len(line.lstrip("#"))
            body.append(f"<h{level}>{html.escape(line[level:].strip())}</h{level}>")
        elif line.startswith("- "):
            if not items:
                body.append("<ul>")
                items = True
            body.append(f"<li>{html.escape(line[2:]).replace('`', '')}</li>")
        elif line.strip():
            body.append(f"<p>{html.escape(line)}</p>")
    body.append("</table>" if table else "</ul>" if items else "")
    style = ("body{font-family:sans-serif;max-width:60em;margin:2em auto}"
             "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:2px 8px;"
             "text-align:right}td:first-child,th:first-child{text-align:left}img{max-width:100%}")
    return ("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Accuracy report"
            f"</title><style>{style}</style></head><body>\n" + "\n".join(body)
            + "\n</body></html>\n")


def write_report(out_dir: str | os.PathLike, summary: dict,
                 images: dict[str, str] | None = None) -> dict[str, Path]:
    """Write report.md and report.html into ``out_dir``; {"markdown": path, "html": path}.

    ``images`` maps "histogram" / "error_map" to PNG file names relative to ``out_dir``.
    """
    out = Path(out_dir)
    markdown = _markdown(summary, images or {})
    paths = {"markdown": out / "report.md", "html": out / "report.html"}
    write_text_atomic(paths["markdown"], markdown)
    write_text_atomic(paths["html"], _html(markdown))
    return paths
