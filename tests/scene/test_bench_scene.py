from designer.bench import scene


def test_scene_benchmark_runs_small_and_prints_a_table():
    rows = scene.run(repeats=1, scale=0.001)
    assert [r["step"] for r in rows] == ["procedural terrain", "mesh height field",
                                         "write binary PLY", "procedural texture"]
    assert all(r["seconds"] > 0 for r in rows)
    table = scene.format_table(rows)
    assert "procedural texture" in table and "seconds" in table
