import os
import re
import shutil

import numpy as np
import pytest

from designer.bench import compare


def _cell(line: str, column: int) -> str:
    return line.split()[column]


@pytest.mark.slow
def test_compare_benchmark_table_at_a_small_scale():
    rows = compare.run(repeats=1, scale=0.002)
    table = compare.format_table(rows)
    by_tool: dict[str, list[dict]] = {}
    for r in rows:
        by_tool.setdefault(r["tool"], []).append(r)
    designer = by_tool["designer"]
    assert [r["case"] for r in designer] == [c[0] for c in compare.CASES]
    for r in designer:
        assert r["sign_errors"] == 0 and r["points"] == 2000 and r["triangles"] == 1922
        # the whole process includes the kernels it reports
        assert 0 < r["compute_s"] < r["process_s"]
    have_cc = shutil.which("CloudCompare") is not None
    assert ("CloudCompare" in by_tool) == have_cc
    for r in by_tool.get("CloudCompare", []) + by_tool.get("VTK", []):
        assert r["max_abs_diff"] < 1e-5 and r["max_abs_diff_unsigned"] < 1e-5
    for r in by_tool.get("CloudCompare", []):
        assert 0 < r["compute_s"] < r["process_s"]
    # the table shows each row's figures and the process ratio it states
    for r in designer + by_tool.get("CloudCompare", []):
        line = next(ln for ln in table.splitlines()
                    if ln.startswith(r["case"]) and f" {r['tool']} " in ln)
        fields = line[len(r["case"]):].split()
        assert float(fields[1]) == pytest.approx(r["compute_s"], abs=0.006)
        assert float(fields[3]) == pytest.approx(r["process_s"], abs=0.006)
    if have_cc:
        ratios = re.findall(r"whole process, designer / CloudCompare: ([0-9.]+) \((.+)\)", table)
        assert [case for _, case in ratios] == [c[0] for c in compare.CASES]
        cc = {r["case"]: r for r in by_tool["CloudCompare"]}
        for (ratio, case), r in zip(ratios, designer, strict=True):
            assert float(ratio) == pytest.approx(r["process_s"] / cc[case]["process_s"],
                                                 abs=0.006)
    (install,) = by_tool["install"]
    assert install["warmup_s"] > 0 and install["first_run_s"] > 0
    assert install["warm_run_s"] == designer[0]["process_s"]
    found = re.search(r"installation \(designer warmup --no-probe, empty matplotlib cache\): "
                      r"([0-9.]+) s; "
                      r"first designer compare after it ([0-9.]+) s, warm ([0-9.]+) s: first / "
                      r"warm = ([0-9.]+)", table)
    assert found is not None
    assert float(found[2]) == pytest.approx(install["first_run_s"], abs=0.006)
    assert float(found[4]) == pytest.approx(install["first_run_s"] / install["warm_run_s"],
                                            abs=0.006)


def test_compare_benchmark_without_cloudcompare_says_why(monkeypatch):
    cc = shutil.which("CloudCompare")
    if cc is not None:  # hide it: keep every other folder of PATH
        folder = os.path.dirname(cc)
        monkeypatch.setenv("PATH", os.pathsep.join(
            p for p in os.environ["PATH"].split(os.pathsep) if os.path.realpath(p) !=
            os.path.realpath(folder)))
    assert shutil.which("CloudCompare") is None
    reason = compare.cloudcompare_skip_reason()
    assert "not on PATH" in reason and "cloudcompare" in reason
    rows = compare.run(repeats=1, scale=0.0005, first_run=False)
    assert not any(r["tool"] == "CloudCompare" and "skipped" not in r for r in rows)
    assert not any(r["tool"] == "install" for r in rows)
    table = compare.format_table(rows)
    assert f"CloudCompare skipped: {reason}" in table
    assert "whole process, designer / CloudCompare" not in table
    assert "÷ CC" in table and "installation" not in table


def test_benchmark_cloud_is_float32_exact_after_the_shift():
    hf, _ = compare._terrain(16)
    xyz = compare._cloud(hf, 100, 0.03, 0.1, seed=0)
    local = xyz - compare.SHIFT
    assert np.array_equal(local.astype(np.float32).astype(np.float64), local)
