import subprocess
import sys

import pytest

from designer import __version__
from designer.cli.main import COMMAND_MODULES, main


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "designer", *args],
                          capture_output=True, text=True, timeout=120)


def test_help_lists_every_command():
    out = run_cli("--help")
    assert out.returncode == 0
    for module in COMMAND_MODULES:
        assert module.rsplit(".", 1)[1].replace("_", "-") in out.stdout


def test_version():
    out = run_cli("--version")
    assert out.returncode == 0
    assert out.stdout.strip() == f"designer {__version__}"


def test_unknown_command_is_a_usage_error():
    with pytest.raises(SystemExit) as exc:
        main(["no-such-command"])
    assert exc.value.code == 2


def test_core_benchmark_prints_its_table(capsys):
    assert main(["bench", "core", "--repeats", "1", "--scale", "0.001"]) == 0
    out = capsys.readouterr().out
    assert "10 M points x 1 camera" in out and "pinhole + Brown" in out
    assert "M points/s" in out
