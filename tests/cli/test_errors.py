"""One-line errors for user mistakes, from ``posekit.cli.main`` down, and complete ``--help``.

Oracle: argparse's own ``prog: error: message`` convention (the form every ros2 verb uses),
checked as text: exactly one line on stderr, a non-zero exit, no ``Traceback``.
"""

from __future__ import annotations

import errno
import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from posekit.cli.errors import CliError, describe, report
from posekit.cli.main import _COMMANDS, main


def one_line_error(capsys: pytest.CaptureFixture[str], prog: str) -> str:
    err = capsys.readouterr().err
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"{prog}: error: "), err
    return lines[0].removeprefix(f"{prog}: error: ")


def test_report_formats() -> None:
    err = io.StringIO()
    assert report(CliError("bad value", 2), "posekit x", err) == 2
    assert err.getvalue() == "posekit x: error: bad value\n"
    missing = FileNotFoundError(errno.ENOENT, "No such file or directory", "/nope/out.png")
    assert describe(missing) == "No such file or directory: '/nope/out.png'"
    busy = OSError(errno.EADDRINUSE, "Address already in use")
    assert describe(busy).startswith("address already in use")
    err = io.StringIO()
    assert report(KeyError("boom"), "posekit y", err) == 1
    lines = err.getvalue().splitlines()
    assert lines[0] == "posekit y: error: KeyError: 'boom'"
    assert lines[1] == "posekit y: (POSEKIT_TRACEBACK=1 prints the traceback)"
    import yaml

    broken = yaml.YAMLError("while parsing\nexpected ','")
    err = io.StringIO()
    assert report(broken, "posekit launch", err) == 1
    assert err.getvalue() == "posekit launch: error: while parsing expected ','\n"


def test_user_mistakes_end_in_one_line(capsys: pytest.CaptureFixture[str], tmp_path: Path,
                                       monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("POSEKIT_TRANSPORT", "nosuch")
    assert main(["topic", "list"]) == 1
    assert "unknown transport 'nosuch'" in one_line_error(capsys, "posekit topic list")
    monkeypatch.setenv("POSEKIT_TRANSPORT", "inprocess")
    with pytest.raises(SystemExit) as exit_info:  # argparse: usage line + one error line
        main(["topic", "list", "--transport", "nosuch"])
    assert exit_info.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1].startswith(
        "posekit topic list: error: argument --transport: invalid choice: 'nosuch'")
    for verb in (["info", "bad!name"], ["echo", "bad!name", "std_msgs/msg/String"],
                 ["pub", "bad!name", "std_msgs/msg/String", "{}"]):
        assert main(["topic", *verb]) == 1
        assert one_line_error(capsys, f"posekit topic {verb[0]}").startswith(
            "Invalid topic name 'bad!name'")
    assert main(["tf", "echo", "a", "b", "--count", "abc"]) == 2
    assert one_line_error(capsys, "posekit tf echo") == (
        "--count needs a positive integer, got 'abc'")


def test_unwritable_output_paths(capsys: pytest.CaptureFixture[str],
                                 monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv("POSEKIT_TRANSPORT", "inprocess")
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    assert main(["bag", "record", "-o", str(blocker / "bag"), "--all", "--duration", "0"]) == 1
    assert one_line_error(capsys, "posekit bag record") == (
        f"Not a directory: '{blocker / 'bag'}'")
    unwritable = tmp_path / "ro"
    unwritable.mkdir(mode=0o500)
    if not os.access(unwritable, os.W_OK):  # root may write anywhere
        assert main(["bag", "record", "-o", str(unwritable / "bag"), "--all", "--duration",
                     "0"]) == 1
        assert "Permission denied" in one_line_error(capsys, "posekit bag record")
    assert main(["plot", "odometry", str(tmp_path / "none.npz")]) == 1
    assert "cannot read recording" in one_line_error(capsys, "posekit plot odometry")


def test_the_command_list_keeps_names_and_texts_apart(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--help"]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if line.startswith("  ")]
    names = sorted(g if c is None else f"{g} {c}" for g, c in _COMMANDS)
    assert sorted(line[2:].split("  ")[0] for line in lines) == names  # two spaces at least
    assert len({len(line) - len(line[2:].split("  ", 1)[1].lstrip()) for line in lines}) == 1


def test_groups_list_their_verbs(capsys: pytest.CaptureFixture[str]) -> None:
    for group in ("topic", "node", "tf", "bag", "plot", "param", "service", "action"):
        assert main([group]) == 0
        out = capsys.readouterr().out
        verbs = sorted(c for g, c in _COMMANDS if g == group and c is not None)
        assert [line.split()[0] for line in out.splitlines() if line.startswith("  ")] == verbs
    # interface parses its own verbs (ros2 interface prints its help and succeeds)
    assert main(["interface"]) == 0
    out = capsys.readouterr().out
    for verb in ("list", "package", "packages", "show", "proto"):
        assert f"    {verb} " in out, out


@pytest.mark.parametrize("command", sorted(
    (g, c) for g, c in _COMMANDS if (g, c) != ("demo", None)), ids=str)
def test_every_help_exits_zero(command: tuple[str, str | None],
                               capsys: pytest.CaptureFixture[str]) -> None:
    argv = [p for p in command if p] + ["--help"]
    try:
        code = main(argv)
    except SystemExit as exc:
        code = int(exc.code or 0)
    out = capsys.readouterr().out
    assert code == 0
    assert "usage" in out.lower()
    # every option a parser knows is listed (argparse does this; tf echo's own text too)
    if command == ("tf", "echo"):
        for option in ("--count", "--transport", "--zenoh", "--help"):
            assert option in out


def test_topic_echo_help_lists_ros2s_options(capsys: pytest.CaptureFixture[str]) -> None:
    """The option names of Jazzy's ``ros2 topic echo`` (ros2topic/verb/echo.py, qos args)."""
    with pytest.raises(SystemExit) as exit_info:
        main(["topic", "echo", "--help"])
    assert exit_info.value.code == 0
    out = capsys.readouterr().out
    for option in ("--qos-profile", "--qos-depth", "--qos-history", "--qos-reliability",
                   "--qos-durability", "--qos-liveliness",
                   "--qos-liveliness-lease-duration-seconds", "--csv", "--field",
                   "--full-length", "--truncate-length", "--no-arr", "--no-str",
                   "--flow-style", "--no-lost-messages", "--raw", "--filter", "--once",
                   "--timeout"):
        assert option in out, option


def test_entry_point_prints_no_traceback(tmp_path: Path) -> None:
    env = dict(os.environ, POSEKIT_TRANSPORT="inprocess")
    done = subprocess.run(
        [sys.executable, "-m", "posekit.cli.main", "topic", "info", "bad name"],
        env=env, capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 1
    assert done.stderr.count("\n") == 1
    assert done.stderr.startswith("posekit topic info: error: Invalid topic name 'bad name'")


@pytest.mark.slow
def test_empty_graph_hints(monkeypatch: pytest.MonkeyPatch) -> None:
    """Alone on a fresh Zenoh domain, every graph tool says what to check."""
    from _support.ports import free_port
    from posekit.cli import node_cmd, tf_echo, topic_cmd
    from posekit.runtime.context import Context

    for var in ("ZENOH_SESSION_CONFIG_URI", "ZENOH_CONFIG_OVERRIDE", "ROS_DOMAIN_ID"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.setenv("POSEKIT_ZENOH_ROUTER", f"tcp/127.0.0.1:{free_port()}")
    context = Context()
    context.init(transport="zenoh")
    try:
        for function, argv in ((topic_cmd.main_list, []), (node_cmd.main_list, []),
                               (topic_cmd.main_info, ["/x"]), (tf_echo.main, ["a", "b"])):
            out, err = io.StringIO(), io.StringIO()
            kwargs = {"timeout_s": 1.5} if function is tf_echo.main else {}
            function(argv, context=context, out=out, err=err, **kwargs)
            hint = err.getvalue()
            assert "hint: no other node is visible on zenoh domain" in hint
            assert "ROS_DOMAIN_ID" in hint
        with pytest.raises(CliError, match="Unable to find node '/x'"):
            node_cmd.main_info(["/x"], context=context, out=io.StringIO(), err=io.StringIO())
    finally:
        context.try_shutdown()


LAUNCH_FILE = """
from posekit.launch import LaunchDescription, Node
from posekit.runtime.node import Node as RNode


class Mine(RNode):
    def __init__(self, **kw):
        super().__init__("mine", **kw)


def generate_launch_description():
    return LaunchDescription([Node(Mine, name={name!r}, parameters={parameters!r})])
"""


@pytest.mark.parametrize(("name", "parameters", "expected"), [
    ("bad name!", [], "Invalid node name 'bad name!'"),
    ("ok", ["{missing}"], "Error opening YAML file '{missing}': No such file or directory"),
    ("ok", ["{broken}"], "{broken} is not YAML: while parsing a flow sequence"),
])
def test_bad_launch_files_end_in_one_line(name: str, parameters: list[str], expected: str,
                                          tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str],
                                          monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("POSEKIT_TRANSPORT", raising=False)
    paths = {"missing": str(tmp_path / "nope.yaml"), "broken": str(tmp_path / "broken.yaml")}
    (tmp_path / "broken.yaml").write_text("ok: {ros__parameters: [1, 2\n")
    launch_file = tmp_path / "bad_launch.py"
    launch_file.write_text(LAUNCH_FILE.format(
        name=name, parameters=[p.format(**paths) for p in parameters]))
    assert main(["launch", str(launch_file), "--until-sim-time", "0.1"]) == 1
    assert one_line_error(capsys, "posekit launch").startswith(expected.format(**paths))
