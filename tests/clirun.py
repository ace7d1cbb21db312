"""Running the command line in-process for tests: its exit code, output and one-line error."""

from __future__ import annotations

from morphkit.cli import main


def run(capture, *argv: object) -> tuple[int, str, str]:
    """``main(argv)``'s exit code (argparse's ``SystemExit`` included) and the captured
    ``(out, err)`` of ``capture`` (pytest's ``capsys`` or ``capfd``)."""
    try:
        rc = main([str(a) for a in argv])
    except SystemExit as exc:  # argparse
        rc = int(exc.code)
    out, err = capture.readouterr()
    return rc, out, err


def one_line(err: str, prefix: str = "morphkit: error: ") -> str:
    """The single line of ``err``, which starts with ``prefix`` and holds no traceback."""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith(prefix), lines[0]
    return lines[0]
