import pytest

from designer.cli.main import main


@pytest.mark.blender
@pytest.mark.slow
def test_demo_runs_its_stages_and_writes_a_report(tmp_path, capsys):
    out = tmp_path / "demo"
    assert main(["demo", "-o", str(out), "--quality", "draft", "--frames", "0-1"]) == 0
    report = (out / "report.md").read_text()
    for section in ("## Plan", "## A rendered image", "## GCPs", "## Timings"):
        assert section in report
    assert (out / "plan-coverage.png").stat().st_size > 10_000
    images = sorted((out / "survey" / "images").iterdir())
    assert [p.name.startswith("DJI_") and p.suffix == ".png" for p in images] == [True, True]
    assert (out / "survey" / "ground-truth" / "colmap" / "images.txt").is_file()
    # a second run resumes: nothing is rendered again
    assert main(["demo", "-o", str(out), "--quality", "draft", "--frames", "0-1"]) == 0
    assert "0 images rendered, 2 already complete" in capsys.readouterr().out
