import numpy as np

from designer.bench import compare


def test_compare_benchmark_runs_at_a_small_scale():
    rows = compare.run(repeats=1, scale=0.002)
    designer = [r for r in rows if r["tool"] == "designer"]
    assert len(designer) == len(compare.CASES)
    assert all(r["sign_errors"] == 0 and r["points"] == 2000 for r in designer)
    for r in rows:
        if r["tool"] != "designer":  # CloudCompare and VTK, when installed
            assert r["max_abs_diff"] < 1e-5 and r["max_abs_diff_unsigned"] < 1e-5
    table = compare.format_table(rows)
    assert "designer" in table and "M pts/s" in table


def test_benchmark_cloud_is_float32_exact_after_the_shift():
    hf, _ = compare._terrain(16)
    xyz = compare._cloud(hf, 100, 0.03, 0.1, seed=0)
    local = xyz - compare.SHIFT
    assert np.array_equal(local.astype(np.float32).astype(np.float64), local)
