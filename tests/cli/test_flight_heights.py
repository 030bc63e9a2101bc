"""export-flight and import-flight name their heights alike: ``--altitude
relative|absolute``, with ``--height`` and ``amsl`` kept as the former spellings."""

import json

import pytest

from designer.cli.main import build_parser, main
from tests.flight.helpers import EXAMPLE

COMMANDS = {"export-flight": [str(EXAMPLE), "--format", "qgc", "-o", "f.plan"],
            "import-flight": ["images", "--base", str(EXAMPLE), "-o", "new.xml"]}


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize("words, altitude", [
    (["--altitude", "relative"], "relative"), (["--altitude", "absolute"], "absolute"),
    (["--height", "relative"], "relative"), (["--height", "absolute"], "absolute"),
    (["--altitude", "amsl"], "absolute"), (["--height", "amsl"], "absolute")])
def test_both_commands_read_every_spelling_alike(command, words, altitude):
    args = build_parser().parse_args([command, *COMMANDS[command], *words])
    assert args.altitude == altitude


@pytest.mark.parametrize("command, default", [("export-flight", "relative"),
                                              ("import-flight", "absolute")])
def test_each_command_keeps_its_default(command, default):
    assert build_parser().parse_args([command, *COMMANDS[command]]).altitude == default


@pytest.mark.parametrize("command", COMMANDS)
def test_an_unknown_word_is_refused(command, capsys):
    with pytest.raises(SystemExit) as exc:
        build_parser().parse_args([command, *COMMANDS[command], "--altitude", "agl"])
    assert exc.value.code == 2
    assert "relative" in capsys.readouterr().err


def test_the_help_names_the_former_spellings(capsys):
    for command in COMMANDS:
        with pytest.raises(SystemExit):
            main([command, "--help"])
        text = " ".join(capsys.readouterr().out.split())
        assert "--altitude {relative,absolute}, --height {relative,absolute}" in text
        assert "former" in text and "amsl" in text


def test_absolute_and_amsl_write_the_same_absolute_plan(tmp_path):
    """QGroundControl's AltitudeMode 2 is Absolute (1 Relative); the alias writes the
    same file byte for byte."""
    plans = {}
    for words in (["--altitude", "absolute"], ["--altitude", "amsl"], ["--height", "absolute"],
                  ["--altitude", "relative"]):
        out = tmp_path / f"{'-'.join(words)}.plan"
        assert main(["export-flight", str(EXAMPLE), "--format", "qgc", "-o", str(out),
                     *words]) == 0
        plans[words[1] + words[0]] = out.read_text()
    modes = {key: json.loads(text)["mission"]["globalPlanAltitudeMode"]
             for key, text in plans.items()}
    assert modes == {"absolute--altitude": 2, "amsl--altitude": 2, "absolute--height": 2,
                     "relative--altitude": 1}
    assert plans["absolute--altitude"] == plans["amsl--altitude"] == plans["absolute--height"]
