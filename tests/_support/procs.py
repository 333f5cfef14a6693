"""A child process whose output is collected line by line, with bounded waits.

Every wait has a timeout and fails with the process's collected stdout and stderr, so a test
never blocks forever on a process that went quiet.
"""

from __future__ import annotations

import os
import queue
import signal
import subprocess
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any


class Proc:
    """A child process whose stdout and stderr lines are collected by reader threads."""

    def __init__(self, args: list[str], env: dict[str, str], cwd: Path | None = None, *,
                 new_session: bool = False, stdin: int | None = None) -> None:
        """``new_session``: the child leads its own process group, so a signal sent to the
        group (:meth:`interrupt_group`) reaches a shell and the command it runs. ``stdin``: a
        file descriptor for the child's stdin (a pty, say); default none."""
        self.args = args
        self.popen = subprocess.Popen(
            args, env=env, cwd=cwd, stdin=subprocess.DEVNULL if stdin is None else stdin,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE, text=True, bufsize=1, start_new_session=new_session,
        )
        self.lines: queue.Queue[str] = queue.Queue()
        self.out: list[str] = []
        self.err: list[str] = []
        for stream, sink in ((self.popen.stdout, self.out), (self.popen.stderr, self.err)):
            threading.Thread(target=self._read, args=(stream, sink), daemon=True).start()

    def _read(self, stream: Any, sink: list[str]) -> None:
        for line in stream:
            sink.append(line)
            if sink is self.out:
                self.lines.put(line)

    def describe(self) -> str:
        return (f"$ {' '.join(self.args[2:])}\n--- stdout:\n{''.join(self.out)}"
                f"--- stderr:\n{''.join(self.err)[-3000:]}")

    def wait_line(self, pred: Callable[[str], bool], timeout: float, what: str) -> str:
        deadline = time.monotonic() + timeout
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise AssertionError(f"timed out after {timeout} s waiting for {what}\n"
                                     f"{self.describe()}")
            try:
                line = self.lines.get(timeout=min(remaining, 0.2))
            except queue.Empty:
                if self.popen.poll() is not None and self.lines.empty():
                    time.sleep(0.1)  # let the reader threads drain
                    if self.lines.empty():
                        raise AssertionError(f"process exited ({self.popen.returncode}) before "
                                             f"{what}\n{self.describe()}") from None
                continue
            if pred(line):
                return line

    def finish(self, timeout: float, what: str) -> str:
        try:
            self.popen.wait(timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            raise AssertionError(
                f"{what} did not finish in {timeout} s\n{self.describe()}"
            ) from None
        time.sleep(0.05)
        return "".join(self.out)

    def wait_stderr(self, text: str, timeout: float, what: str) -> None:
        deadline = time.monotonic() + timeout
        while not any(text in line for line in self.err):
            if time.monotonic() > deadline or self.popen.poll() is not None:
                raise AssertionError(f"no {what} after {timeout} s\n{self.describe()}")
            time.sleep(0.05)

    def kill(self, sig: int = signal.SIGKILL) -> None:
        if self.popen.poll() is None:
            self.popen.send_signal(sig)
            try:
                self.popen.wait(5)
            except subprocess.TimeoutExpired:
                self.popen.kill()
                self.popen.wait(5)

    def interrupt_group(self, timeout: float = 10.0) -> None:
        """Ctrl-C the process group (needs ``new_session``), then SIGKILL it if it lingers."""
        if self.popen.poll() is not None:
            return
        os.killpg(self.popen.pid, signal.SIGINT)
        try:
            self.popen.wait(timeout)
        except subprocess.TimeoutExpired:
            os.killpg(self.popen.pid, signal.SIGKILL)
            self.popen.wait(5)


def stop_all(procs: list[Proc]) -> None:
    """Kill ``procs`` newest first (each one this test started) and close their pipes."""
    for proc in reversed(procs):
        proc.kill()
    for proc in procs:
        for stream in (proc.popen.stdout, proc.popen.stderr):
            if stream is not None:
                stream.close()
