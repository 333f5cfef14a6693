"""One-line errors for the command line: what a user did wrong never shows a traceback.

Tools raise :class:`CliError` (or let a named posekit exception, an ``OSError`` on a path or a
port, or an argument error propagate); :func:`report` turns it into the single line
``posekit <verb>: error: <reason>`` on stderr and an exit code, as argparse does for usage
errors. ``posekit.cli.main`` applies it around every command, so tools need not catch these
themselves.

Anything else (a bug in posekit, or an exception from the user's own code run by
``posekit launch FILE.py``) is reported on one line too, with the exception's name, and a
second line saying that ``POSEKIT_TRACEBACK=1`` prints the full traceback.
"""

from __future__ import annotations

import errno
import os
import re
import sys
import traceback
from typing import TextIO

__all__ = ["ENV_TRACEBACK", "CliError", "describe", "is_user_error", "report"]

#: Set to 1 to get the full traceback of an unexpected error.
ENV_TRACEBACK = "POSEKIT_TRACEBACK"


class CliError(Exception):
    """A user mistake or an unusable environment, reported on one line.

    ``code`` is the exit status (1 by default; 2 for usage errors, as argparse uses).
    """

    def __init__(self, message: str, code: int = 1) -> None:
        super().__init__(message)
        self.code = code


def _user_error_types() -> tuple[type[BaseException], ...]:
    """Exceptions that describe bad input, each defined by the layer that detects it."""
    from posekit.geometry.errors import GeometryError
    from posekit.msgs.errors import MessageError
    from posekit.runtime.arguments import RCLError
    from posekit.runtime.names import NameValidationError
    from posekit.runtime.parameters import ParameterException
    from posekit.runtime.sim_executor import ClockConflictError
    from posekit.runtime.transport import (
        ServicesNotSupportedError,
        TopicTypeMismatchError,
        UnknownTransportError,
    )

    types: list[type[BaseException]] = [
        CliError, OSError, UnicodeError, MessageError, NameValidationError, ParameterException,
        UnknownTransportError, TopicTypeMismatchError, GeometryError, ServicesNotSupportedError,
        ClockConflictError, RCLError,
        re.error,  # a --filter/--regex pattern given by the user
    ]
    for module, name in (
        ("posekit.bag.errors", "BagError"),
        ("posekit.launch.scenarios", "ScenarioError"),
        ("posekit.launch.description", "LaunchDescriptionError"),
        ("posekit.worlds", "WorldError"),
        ("posekit.robot.plot", "PlotError"),
        ("posekit.viewer.errors", "ViewerError"),
        ("posekit.vision.errors", "VisionError"),
        ("posekit.cli.static_args", "StaticArgsError"),
        ("posekit.cli.tf_echo", "RateError"),
        ("yaml", "YAMLError"),  # a broken YAML file given by the user
    ):
        loaded = sys.modules.get(module)  # only types a command actually used can be raised
        error_type = getattr(loaded, name, None) if loaded is not None else None
        if isinstance(error_type, type) and issubclass(error_type, BaseException):
            types.append(error_type)
    return tuple(types)


def is_user_error(exc: BaseException) -> bool:
    """True when ``exc`` describes bad input or environment rather than a posekit bug."""
    if isinstance(exc, _user_error_types()):
        return True
    # zenoh reports a bad endpoint or an unreachable router as a ZError
    return type(exc).__name__ == "ZError"


def describe(exc: BaseException) -> str:
    """The reason of ``exc`` on one line, with the path or port of an ``OSError``."""
    if isinstance(exc, OSError) and not isinstance(exc, CliError):
        reason = exc.strerror or str(exc) or type(exc).__name__
        if exc.errno == errno.EADDRINUSE:
            reason = "address already in use (is another instance running on that port?)"
        target = exc.filename if exc.filename is not None else None
        text = f"{reason}: '{target}'" if target is not None else reason
    else:
        text = str(exc) or type(exc).__name__
        if not is_user_error(exc):
            text = f"{type(exc).__name__}: {text}"
    return " ".join(text.split()) if "\n" in text else text


def report(exc: BaseException, prog: str, err: TextIO | None = None) -> int:
    """Print ``prog: error: <reason>`` for ``exc`` and return the exit code to use."""
    err = err or sys.stderr
    user = is_user_error(exc)
    if not user and os.environ.get(ENV_TRACEBACK, "") not in ("", "0"):
        traceback.print_exception(exc, file=err)
    err.write(f"{prog}: error: {describe(exc)}\n")
    if not user and os.environ.get(ENV_TRACEBACK, "") in ("", "0"):
        err.write(f"{prog}: ({ENV_TRACEBACK}=1 prints the traceback)\n")
    err.flush()
    return exc.code if isinstance(exc, CliError) else 1
