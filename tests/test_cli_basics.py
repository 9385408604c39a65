import subprocess
import sys

import pytest

from spectex.cli import main


def test_help_lists_commands(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert "noise" in out


def test_unknown_command_is_one_line_exit_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["frobnicate"])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "frobnicate" in err[0]


def test_module_entry_point_runs():
    proc = subprocess.run([sys.executable, "-m", "spectex", "--version"], capture_output=True, text=True)
    assert proc.returncode == 0
    assert proc.stdout.startswith("spectex ")


def test_every_writing_command_takes_dash_o_output():
    from spectex.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    for name in ("demo", "noise", "tile", "spectrum", "render", "export", "synth", "text", "compare", "fit",
                 "bake"):
        flags = {s for a in sub.choices[name]._actions for s in a.option_strings}
        assert {"-o", "--output"} <= flags, name
    # view writes nothing
    assert "--output" not in {s for a in sub.choices["view"]._actions for s in a.option_strings}


def test_options_given_are_noted_and_defaults_are_not():
    from spectex.cli import build_parser

    args = build_parser().parse_args(["noise", "fbm", "--gain", "0.4", "--tileable", "-o", "x.png"])
    assert args.given == {"gain": "--gain", "tileable": "--tileable", "output": "-o"}
    assert args.long_names == {"gain": "--gain", "tileable": "--tileable", "output": "--output"}
    assert args.octaves == 6 and args.lacunarity == 2.0  # defaults still in place


def test_demo_output_in_a_missing_folder_is_refused_before_the_work(tmp_path, capsys):
    missing = str(tmp_path / "nope" / "demo")
    assert main(["demo", "-o", missing]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--output" in err[0] and "does not exist" in err[0]


def test_help_texts_have_no_internal_references():
    from spectex.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    for name, parser in sub.choices.items():
        text = parser.format_help()
        assert "(seed 0" not in text and "issue " not in text, name


class _FakeTerminal:
    def __init__(self, tty):
        import io

        self._buf, self._tty = io.StringIO(), tty

    def isatty(self):
        return self._tty

    def write(self, text):
        return self._buf.write(text)

    def flush(self):
        pass

    def getvalue(self):
        return self._buf.getvalue()


@pytest.mark.parametrize("tty", [True, False])
def test_steps_show_on_a_terminal_only(monkeypatch, tty):
    import time

    from spectex.cli._common import Steps

    fake = _FakeTerminal(tty)
    monkeypatch.setattr(sys, "stderr", fake)

    def shown_soon(text):  # the line is drawn by a timer and a refresh thread: wait for it, not a fixed time
        deadline = time.monotonic() + 10.0
        while text not in fake.getvalue() and time.monotonic() < deadline:
            time.sleep(0.01)

    with Steps(2, delay=0.0) as steps:
        steps.step("computing fbm 16x16")
        if tty:
            shown_soon("computing fbm 16x16")
        steps.step("writing PNG")
        if tty:
            shown_soon("writing PNG")
    shown = fake.getvalue()
    if tty:
        assert "computing fbm 16x16" in shown and "writing PNG" in shown and "1/2" in shown
    else:
        assert shown == ""


@pytest.mark.parametrize("argv, option", [
    (["tile", "--cutoff", "5", "-o", "{tmp}/x.png"], "--cutoff"),
    (["text", "--order", "99", "-o", "{tmp}/x.txt", "{readme}"], "--order"),
])
def test_a_library_refusal_names_the_option_typed(argv, option, tmp_path, capsys):
    """The library's check names its parameter (``cutoff``); the command line says the option
    (``--cutoff``), with the rest of the message and nothing written."""
    from pathlib import Path

    readme = Path(__file__).resolve().parents[1] / "README.md"
    code = main([a.format(tmp=tmp_path, readme=readme) for a in argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert err[0].startswith(f"spectex {argv[0]}: error: {option} must be"), err
    assert list(tmp_path.iterdir()) == []


def test_only_an_option_given_is_renamed():
    from argparse import Namespace

    from spectex.cli import _as_option

    args = Namespace(long_names={"cutoff": "--cutoff", "pixel_size": "--pixel-size", "output": "--output"})
    assert _as_option("pixel_size must be > 0, got -1.0", args) == "--pixel-size must be > 0, got -1.0"
    assert _as_option("output must end in .png", args) == "--output must end in .png"
    assert _as_option("order must be <= 12, got 99", args) == "order must be <= 12, got 99"  # not given: kept
    assert _as_option("cutoff", None) == "cutoff"  # refused before the options were read
