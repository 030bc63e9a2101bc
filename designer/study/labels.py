"""Names of variants as a reader says them: their factor levels with units
("altitude 35 m", "control-count 5, gcp-mode bundle"), for figures and tables."""

from __future__ import annotations

#: factor-name endings that are units, longest first, and how a level writes them
_UNITS = (("-per-m2", " /m²"), ("-m-s", " m/s"), ("-percent", " %"), ("-deg", "°"),
          ("-px", " px"), ("-dn", " DN"), ("-ev", " EV"), ("-m", " m"), ("-s", " s"),
          ("-k", " K"))


def _split(factor: str) -> tuple[str, str]:
    """(name without its unit ending, the unit as written after a level)."""
    for ending, unit in _UNITS:
        if factor.endswith(ending) and len(factor) > len(ending):
            return factor[:-len(ending)], unit
    return factor, ""


def level_label(factor: str, level) -> str:
    """``altitude-m``, ``35`` → ``altitude 35 m``; a factor without a unit keeps its
    name (``gcp-mode bundle``)."""
    name, unit = _split(factor)
    return f"{name} {level}{unit}"


def short_labels(rows: list[dict], factors: list[str]) -> tuple[dict[int, str], str]:
    """Labels of the variants by their levels alone (``40 m · bundle``) for a figure of
    many, and the key that names the factors in that order."""
    levels: dict[int, dict[str, str]] = {}
    for r in rows:
        levels.setdefault(int(r["variant"]), {f: str(r.get(f"factor:{f}")) for f in factors})
    varied = [f for f in factors if len({lv[f] for lv in levels.values()}) > 1] or factors
    return ({v: " · ".join(f"{lv[f]}{_split(f)[1]}" for f in varied)
             for v, lv in levels.items()}, " · ".join(_split(f)[0] for f in varied))


def variant_labels(rows: list[dict], factors: list[str], design: str) -> dict[int, str]:
    """A label for each variant of the rows (by variant number).

    One factor at a time: the level that sets the variant apart from the base (variant
    0), and ``base`` for the base (with its levels when there are one or two factors).
    Full factorial: the level of every factor that has more than one.
    """
    levels: dict[int, dict[str, str]] = {}
    for r in rows:
        levels.setdefault(int(r["variant"]), {f: str(r.get(f"factor:{f}")) for f in factors})
    out = {}
    if design == "one-at-a-time":
        base = levels.get(0, {})
        for v, lv in levels.items():
            changed = [f for f in factors if lv[f] != base.get(f)]
            if changed:
                out[v] = ", ".join(level_label(f, lv[f]) for f in changed)
            elif len(factors) <= 2:
                out[v] = "base: " + ", ".join(level_label(f, lv[f]) for f in factors)
            else:
                out[v] = "base"
        return out
    varied = [f for f in factors if len({lv[f] for lv in levels.values()}) > 1] or factors
    return {v: ", ".join(level_label(f, lv[f]) for f in varied) for v, lv in levels.items()}
