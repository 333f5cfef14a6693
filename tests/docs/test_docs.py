"""The documentation runs as written: every Python block of README.md, and every shell block
of README.md and docs/*.md marked runnable, in a fresh directory, against the real CLI. A
shell block that cannot run here (it installs, spans two terminals, reaches another
machine, benchmarks for minutes) says so with ``<!-- not runnable: REASON -->`` above it,
naming the test that runs its commands where one does; no block goes unmarked.

A shell block is marked by an HTML comment right above it::

    <!-- runnable -->                        run to completion; exit status 0
    <!-- runnable expect="REGEX" -->         ... and its output must match REGEX
    <!-- runnable until="REGEX" -->          a command that runs until stopped: wait for
                                             REGEX in its output, then Ctrl-C it
    <!-- runnable background expect="RE" --> "terminal 1": start it, wait for RE, leave it
                                             running for the blocks below; stopped (as a
                                             reader leaves terminal 1 behind) by the next
                                             background block, at the next heading of the
                                             document, or at the end

Blocks run with bash (``set -e``) in a temporary directory that links ``examples`` and
``docs`` of the repository, with the test's virtual environment first on PATH, and with
every Zenoh session pointed at a fresh loopback port, so documentation runs never meet each
other, other tests or a user's system. Every wait is bounded. Oracle: the documents'
own claims (exit status, printed text) and, for the README's Python, closed-form values.
"""

from __future__ import annotations

import os
import re
import shlex
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from _support.ports import free_port
from _support.procs import Proc

REPO = Path(__file__).resolve().parents[2]
README = REPO / "README.md"
DOCS = sorted([README, *(REPO / "docs").glob("*.md")])
_BLOCK = re.compile(
    r"<!-- runnable(?P<opts>(?:[^-]|-(?!->))*?)-->\s*\n```(?:sh|bash|console)\n(?P<body>.*?)```",
    re.S)
_OPT = re.compile(r'(\w+)(?:="((?:[^"\\]|\\.)*)")?')


@dataclass
class Block:
    doc: Path
    line: int
    body: str
    background: bool = False
    expect: str | None = None
    until: str | None = None
    section: int = 0  # how many headings come before the block


    def __str__(self) -> str:
        return f"{self.doc.name}:{self.line}"


def runnable_blocks(doc: Path, text: str | None = None) -> list[Block]:
    if text is None:
        text = doc.read_text(encoding="utf-8")
    blocks = []
    # Heading lines outside fenced code (a "# comment" inside a code block is no heading).
    headings, fenced, offset = [], False, 0
    for line in text.splitlines(keepends=True):
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and re.match(r"#{1,6} ", line):
            headings.append(offset)
        offset += len(line)
    for match in _BLOCK.finditer(text):
        block = Block(doc, text.count("\n", 0, match.start()) + 1, match["body"],
                      section=sum(1 for h in headings if h < match.start()))
        for key, value in _OPT.findall(match["opts"]):
            if key == "background":
                block.background = True
            elif key in ("expect", "until"):
                setattr(block, key, value.replace('\\"', '"'))
            else:
                raise AssertionError(f"{doc.name}: unknown runnable option {key!r}")
        blocks.append(block)
    return blocks


def _python_blocks(doc: Path = README) -> list[str]:
    return re.findall(r"```python\n(.*?)```", doc.read_text(encoding="utf-8"), re.S)


def test_readme_python_examples_run() -> None:
    namespace: dict[str, Any] = {}
    blocks = _python_blocks()
    assert len(blocks) >= 3
    for block in blocks:
        exec(compile(block, str(README), "exec"), namespace)
    q = namespace["q"]
    np.testing.assert_allclose(q.as_quat(scalar_first=True),
                               [np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0], atol=1e-15)
    T_odom_cam = namespace["T_odom_cam"]
    # T_odom_base (yaw 1.57 about z, at (1, 2, 0)) applied to the camera offset (0.1, 0, 0.3)
    expected = [1.0 + 0.1 * np.cos(1.57), 2.0 + 0.1 * np.sin(1.57), 0.3]
    np.testing.assert_allclose(T_odom_cam.translation, expected, atol=1e-12)
    translations = namespace["translations"]
    assert np.shape(translations) == (1000, 3)


def test_tutorial_python_examples_run() -> None:
    namespace: dict[str, Any] = {}
    tutorial = REPO / "docs" / "tutorial.md"
    blocks = _python_blocks(tutorial)
    assert len(blocks) >= 3
    for block in blocks:
        exec(compile(block, str(tutorial), "exec"), namespace)
    # The lecture's exercise and table (closed form: cos/sin of half the angle).
    h = np.sqrt(0.5)
    np.testing.assert_allclose([namespace[k] for k in "wxyz"], [h, h, 0, 0], atol=1e-12)
    np.testing.assert_allclose(namespace["yaw_left"], [h, 0, 0, h], atol=1e-12)
    np.testing.assert_allclose(np.abs(namespace["half_turn"]), [0, 0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(namespace["pitch_up"], [np.cos(np.pi / 8), 0, np.sin(np.pi / 8), 0],
                               atol=1e-12)
    # World-frame vs body-frame composition differ (matrix products, by hand).
    Rz = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])
    Rx = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0.0]])
    np.testing.assert_allclose(namespace["about_world_x"].as_matrix(), Rx @ Rz, atol=1e-12)
    np.testing.assert_allclose(namespace["about_body_x"].as_matrix(), Rz @ Rx, atol=1e-12)
    assert namespace["definition"].startswith("std_msgs/Header header\nstring child_frame_id")
    # tf2's lookup equals the hand-made chain T1 * T2 * T3.
    p = namespace["p"]
    np.testing.assert_allclose([p.x, p.y, p.z], namespace["by_hand"].translation, atol=1e-12)


def test_the_tour_and_the_tutorial_are_runnable() -> None:
    assert len(runnable_blocks(README)) >= 4
    assert len(runnable_blocks(REPO / "docs" / "tutorial.md")) >= 10


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("ZENOH_", "ROS_DOMAIN", "POSEKIT_", "PYTHON"))}
    env.update(PATH=f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}",
               POSEKIT_ZENOH_ROUTER=f"tcp/127.0.0.1:{free_port()}", PYTHONUNBUFFERED="1")
    return env


def _output(proc: Proc) -> str:
    return "".join(proc.out) + "".join(proc.err)


def _wait_for(proc: Proc, pattern: str, timeout: float, block: Block) -> None:
    deadline = time.monotonic() + timeout
    while not re.search(pattern, _output(proc), re.M):
        if proc.popen.poll() is not None:
            time.sleep(0.2)  # let the readers drain
            if re.search(pattern, _output(proc), re.M):
                return
            raise AssertionError(f"{block}: exited ({proc.popen.returncode}) without "
                                 f"/{pattern}/\n{proc.describe()}")
        if time.monotonic() > deadline:
            raise AssertionError(f"{block}: no /{pattern}/ after {timeout} s\n"
                                 f"{proc.describe()}")
        time.sleep(0.1)


def _start(script: str, env: dict[str, str], cwd: Path) -> Proc:
    return Proc(["bash", "-c", script], env, cwd=cwd, new_session=True)


@pytest.mark.slow
@pytest.mark.parametrize("doc", [d for d in DOCS if runnable_blocks(d)], ids=lambda d: d.name)
def test_runnable_shell_blocks(doc: Path, tmp_path: Path) -> None:
    for name in ("examples", "docs"):
        (tmp_path / name).symlink_to(REPO / name)
    env = _env()
    background: list[Proc] = []
    try:
        section = 0
        for block in runnable_blocks(doc):
            script = "set -e\n" + block.body
            if block.background or block.section != section:
                # a new "terminal 1", or a new section: the reader stops the old terminal 1
                for proc in background:
                    proc.interrupt_group()
                background.clear()
            section = block.section
            if block.background:
                proc = _start(script, env, tmp_path)
                background.append(proc)
                _wait_for(proc, block.expect or ".", 60.0, block)
                continue
            proc = _start(script, env, tmp_path)
            try:
                if block.until is not None:
                    _wait_for(proc, block.until, 60.0, block)
                    continue
                try:
                    proc.popen.wait(300)
                except Exception:
                    raise AssertionError(f"{block}: still running after 300 s\n"
                                         f"{proc.describe()}") from None
                time.sleep(0.1)  # let the readers drain
                assert proc.popen.returncode == 0, (
                    f"{block}: exit status {proc.popen.returncode}\n{proc.describe()}")
                if block.expect is not None:
                    assert re.search(block.expect, _output(proc), re.M), (
                        f"{block}: no /{block.expect}/ in the output\n{proc.describe()}")
            finally:
                proc.interrupt_group()
    finally:
        for proc in reversed(background):
            proc.interrupt_group()


def test_runnable_marker_parsing() -> None:
    text = ('<!-- runnable background expect="a -> \\"b\\"" -->\n```sh\nposekit a\n```\n'
            'not runnable\n```sh\nposekit x\n```\n'
            '<!-- runnable until="b: \\d" -->\n```console\nposekit b\n```\n')
    first, second = runnable_blocks(Path("x.md"), text)
    assert (first.background, first.expect, first.body, first.line) == (
        True, 'a -> "b"', "posekit a\n", 1)
    assert (second.background, second.until, shlex.split(second.body)) == (
        False, "b: \\d", ["posekit", "b"])


_ANY_BLOCK = re.compile(r"^(?P<indent>[ \t]*)```(?:sh|bash|console)\n", re.M)
_NOT_RUNNABLE = re.compile(r"<!-- not runnable: (?P<reason>[^>]+?) -->$")


def test_every_shell_block_is_run_or_says_why_not() -> None:
    # Every shell block of the README and docs/ is either run above (marked runnable) or
    # marked "not runnable" with its reason; a test a reason names must exist.
    unmarked: list[str] = []
    for doc in DOCS:
        text = doc.read_text(encoding="utf-8")
        for match in _ANY_BLOCK.finditer(text):
            before = text[: match.start()].rstrip().splitlines()
            above = before[-1].strip() if before else ""
            where = f"{doc.name}:{text.count(chr(10), 0, match.start()) + 1}"
            if above.startswith("<!-- runnable"):
                continue
            reason = _NOT_RUNNABLE.match(above)
            if reason is None:
                unmarked.append(where)
                continue
            for path in re.findall(r"tests/[\w/]+(?:\.py)?", reason["reason"]):
                assert (REPO / path).exists(), (where, path)
    assert unmarked == [], f"shell blocks neither runnable nor explained: {unmarked}"
