from designer.bench import survey


def test_survey_benchmark_runs_at_a_small_scale():
    rows = survey.run(repeats=1, scale=0.02)
    steps = [r["step"] for r in rows]
    assert steps[:3] == ["flight plan", "terrain bounds (ray caster)", "station GSD + overlaps"]
    assert steps[-1] == "total: plan + analyse_plan"
    # every step works on the same plan, and the total covers the analysis steps
    assert len({r["images"] for r in rows}) == 1 and rows[0]["images"] > 10
    assert all(r["seconds"] > 0 for r in rows)
    table = survey.format_table(rows).splitlines()
    assert table[0].split() == ["step", "images", "seconds"]
    for row, line in zip(rows, table[2:], strict=False):
        assert line.startswith(row["step"]) and line.split()[-1] == f"{row['seconds']:.3f}"
