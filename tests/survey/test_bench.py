from designer.bench import survey


def test_survey_benchmark_runs_at_a_small_scale():
    rows = survey.run(repeats=1, scale=0.02)
    assert rows[0]["step"] == "flight plan"
    assert all(r["seconds"] >= 0 and r["images"] > 10 for r in rows)
    table = survey.format_table(rows)
    assert "seconds" in table and "total" in table
