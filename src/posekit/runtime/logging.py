"""rclpy-style loggers: ``get_logger(name).info(...)`` printing ROS 2's console line.

Line format (rcutils' default): ``[INFO] [1700000000.123456789] [talker]: message``, written
to stderr (as rcutils does). rcutils' environment is honoured, read at the first line:
``RCUTILS_CONSOLE_OUTPUT_FORMAT`` (tokens ``{severity}``, ``{name}``, ``{message}``,
``{function_name}``, ``{file_name}`` (the caller's absolute path), ``{line_number}``,
``{time}``, ``{time_as_nanoseconds}``, ``{date_time_with_ms}`` (local time)),
``RCUTILS_COLORIZED_OUTPUT`` (1: rcutils' colours per severity, 0: none, unset: when the
stream is a terminal) and ``RCUTILS_LOGGING_USE_STDOUT=1`` (stdout instead of stderr).
Severities: debug, info, warn/warning, error, fatal. Each call accepts rclpy's keywords:

* ``throttle_duration_sec=s``: from one call site, print at most once per ``s`` seconds;
* ``once=True``: print only the first time that call site runs;
* ``skip_first=True``: skip the first time (with throttling: the first window).

A call site is identified by the caller's code location, as rclpy does.

posekit deviation: a node's logger stamps lines and measures throttle windows with the
*node's clock*, so in simulated time logs carry sim time and a stepped run prints identical
output every time (rclpy always uses the wall clock). Standalone loggers use the wall clock.

Output goes to the registered sinks (default: one that writes to ``sys.stderr``); tests and
tools can add their own with :func:`add_sink` (each receives a :class:`LogRecord`).

``/rosout``: a node (``enable_rosout=True``, the default) registers a rosout handler under its
logger's name (:func:`register_rosout`); every emitted record of a logger with that name, of
``get_logger(<that name>)``, and of loggers made from them with ``get_child`` is also handed
to the handler with the caller's file, function and line, as rcl's rosout output handler
does. A record logged while a rosout handler of the same thread runs (the transport logging
while publishing a log) is printed but not published again.
"""

from __future__ import annotations

import enum
import os
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from types import FrameType

__all__ = [
    "DEFAULT_CONSOLE_FORMAT",
    "ConsoleSettings",
    "LogRecord",
    "LoggingSeverity",
    "RcutilsLogger",
    "add_sink",
    "compile_console_format",
    "configure_console",
    "console_line",
    "format_line",
    "get_logger",
    "get_logger_effective_level",
    "get_logger_level",
    "get_logging_severity_from_string",
    "register_rosout",
    "remove_sink",
    "set_logger_level",
    "unregister_rosout",
]


class LoggingSeverity(enum.IntEnum):
    """rcutils log severities."""

    UNSET = 0
    DEBUG = 10
    INFO = 20
    WARN = 30
    ERROR = 40
    FATAL = 50


_LABEL = {
    LoggingSeverity.DEBUG: "DEBUG",
    LoggingSeverity.INFO: "INFO",
    LoggingSeverity.WARN: "WARN",
    LoggingSeverity.ERROR: "ERROR",
    LoggingSeverity.FATAL: "FATAL",
}


@dataclass(frozen=True, slots=True)
class LogRecord:
    """One emitted log line: severity, logger name, stamp (ns), message and where it came from.

    ``file_name`` is the caller's absolute path (as rclpy passes it to rcutils),
    ``function_name`` its function (``<module>`` at module level), ``line_number`` its line.
    """

    severity: LoggingSeverity
    name: str
    stamp_ns: int
    message: str
    file_name: str = ""
    function_name: str = ""
    line_number: int = 0

    @property
    def line(self) -> str:
        """The console line in rcutils' default format (see :func:`console_line`)."""
        return format_line(self.severity, self.stamp_ns, self.name, self.message)


def format_line(severity: LoggingSeverity, stamp_ns: int, name: str, message: str) -> str:
    """``[SEVERITY] [sec.nanosec] [name]: message`` (nanoseconds zero-padded to 9 digits)."""
    sec, nsec = divmod(stamp_ns, 1_000_000_000)
    return f"[{_LABEL.get(severity, severity.name)}] [{sec}.{nsec:09d}] [{name}]: {message}"


# -- the console output, configured as rcutils is (environment read once, at the first line) --
#: rcutils' default ``RCUTILS_CONSOLE_OUTPUT_FORMAT``.
DEFAULT_CONSOLE_FORMAT = "[{severity}] [{time}] [{name}]: {message}"


def _date_time_with_ms(r: LogRecord) -> str:
    sec, nsec = divmod(r.stamp_ns, 1_000_000_000)
    return time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(sec)) + f".{nsec // 1_000_000:03d}"


#: rcutils' tokens (Jazzy): what each ``{token}`` of the format becomes.
_TOKENS: dict[str, Callable[[LogRecord], str]] = {
    "severity": lambda r: _LABEL.get(r.severity, r.severity.name),
    "name": lambda r: r.name,
    "message": lambda r: r.message,
    "function_name": lambda r: r.function_name,
    "file_name": lambda r: r.file_name,
    "line_number": lambda r: str(r.line_number),
    "time": lambda r: "{}.{:09d}".format(*divmod(r.stamp_ns, 1_000_000_000)),
    "time_as_nanoseconds": lambda r: str(r.stamp_ns),
    "date_time_with_ms": _date_time_with_ms,
}

#: rcutils' colours per severity (``RCUTILS_COLORIZED_OUTPUT``), and the reset after a line.
_COLORS = {
    LoggingSeverity.DEBUG: "\x1b[32m",
    LoggingSeverity.INFO: "\x1b[0m",
    LoggingSeverity.WARN: "\x1b[33m",
    LoggingSeverity.ERROR: "\x1b[31m",
    LoggingSeverity.FATAL: "\x1b[31m",
}
_RESET = "\x1b[0m"


def compile_console_format(fmt: str) -> list[str | Callable[[LogRecord], str]]:
    """``fmt`` as literal text and token functions, parsed as rcutils parses it.

    ``{token}`` of a known token is replaced; anything else is kept as written (an unknown
    ``{x}``, a ``{`` without ``}``; ``{{name}}`` is ``{`` + name + ``}``). An empty format
    is the default one.
    """
    fmt = fmt or DEFAULT_CONSOLE_FORMAT
    parts: list[str | Callable[[LogRecord], str]] = []
    text: list[str] = []
    i = 0
    while i < len(fmt):
        if fmt[i] == "{":
            end = fmt.find("}", i)
            token = _TOKENS.get(fmt[i + 1:end]) if end != -1 else None
            if token is not None:
                if text:
                    parts.append("".join(text))
                    text = []
                parts.append(token)
                i = end + 1
                continue
        text.append(fmt[i])
        i += 1
    if text:
        parts.append("".join(text))
    return parts


@dataclass(frozen=True, slots=True)
class ConsoleSettings:
    """rcutils' console environment: the format, colours and the stream."""

    #: ``RCUTILS_CONSOLE_OUTPUT_FORMAT`` compiled (:func:`compile_console_format`).
    parts: tuple[str | Callable[[LogRecord], str], ...]
    #: ``RCUTILS_COLORIZED_OUTPUT``: True ("1"), False ("0"), None (colour when a terminal).
    colorized: bool | None
    #: ``RCUTILS_LOGGING_USE_STDOUT=1``: lines go to stdout instead of stderr.
    use_stdout: bool

    @classmethod
    def from_environment(cls) -> ConsoleSettings:
        """Read the three variables now."""
        env = os.environ
        color = env.get("RCUTILS_COLORIZED_OUTPUT", "")
        return cls(
            tuple(compile_console_format(env.get("RCUTILS_CONSOLE_OUTPUT_FORMAT", ""))),
            True if color == "1" else False if color == "0" else None,
            env.get("RCUTILS_LOGGING_USE_STDOUT", "") == "1",
        )


_console: ConsoleSettings | None = None


def configure_console(settings: ConsoleSettings | None = None) -> ConsoleSettings:
    """Use ``settings`` for console lines (None: read the environment again); returns them."""
    global _console
    _console = settings if settings is not None else ConsoleSettings.from_environment()
    return _console


def console_line(record: LogRecord, settings: ConsoleSettings | None = None) -> str:
    """``record`` as the console prints it: the configured format, without colour."""
    parts = (settings or _console or configure_console()).parts
    return "".join(p if isinstance(p, str) else p(record) for p in parts)


def _stderr_sink(record: LogRecord) -> None:
    settings = _console or configure_console()
    stream = sys.stdout if settings.use_stdout else sys.stderr
    line = console_line(record, settings)
    colorized = settings.colorized
    if colorized is None:
        isatty = getattr(stream, "isatty", None)
        colorized = bool(isatty and isatty())
    if colorized:
        line = _COLORS.get(record.severity, _RESET) + line + _RESET
    stream.write(line + "\n")
    stream.flush()


#: A rosout handler: ``handler(record, file, function, line)``.
RosoutHandler = Callable[[LogRecord, str, str, int], None]

_sinks: list[Callable[[LogRecord], None]] = [_stderr_sink]
# Logger name -> rosout handlers (first registered wins; later ones wait as fallbacks).
_rosout: dict[str, list[RosoutHandler]] = {}
_rosout_busy = threading.local()
_abspaths: dict[str, str] = {}  # code file name -> absolute path (rclpy's CallerId path)
_levels: dict[str, LoggingSeverity] = {}
_default_level = LoggingSeverity.INFO
_lock = threading.Lock()


def add_sink(sink: Callable[[LogRecord], None]) -> None:
    """Also send every emitted record to ``sink``."""
    with _lock:
        _sinks.append(sink)


def remove_sink(sink: Callable[[LogRecord], None]) -> None:
    """Stop sending records to ``sink`` (the default stderr sink can be removed too)."""
    with _lock:
        if sink in _sinks:
            _sinks.remove(sink)


def register_rosout(name: str, handler: RosoutHandler) -> None:
    """Hand records of the logger ``name`` (and its ``get_child`` loggers) to ``handler``.

    With several handlers for one name (two nodes of the same name) the first one publishes,
    as rcl keeps the first node's publisher.
    """
    with _lock:
        _rosout.setdefault(name, []).append(handler)


def unregister_rosout(handler: RosoutHandler) -> None:
    """Remove ``handler`` under every name it was registered for."""
    with _lock:
        for name in list(_rosout):
            handlers = [h for h in _rosout[name] if h is not handler]
            if handlers:
                _rosout[name] = handlers
            else:
                del _rosout[name]


def _publish_rosout(handler: RosoutHandler, record: LogRecord) -> None:
    if getattr(_rosout_busy, "active", False):
        return  # logged by the rosout publish itself: print only, never recurse
    _rosout_busy.active = True
    try:
        handler(record, record.file_name, record.function_name, record.line_number)
    finally:
        _rosout_busy.active = False


def set_logger_level(name: str, level: LoggingSeverity | int) -> None:
    """Set the threshold of the logger ``name`` (and of its children without their own)."""
    with _lock:
        _levels[name] = LoggingSeverity(level)


def get_logger_level(name: str) -> LoggingSeverity:
    """The threshold set for ``name`` itself (UNSET if none; the root's is the default)."""
    with _lock:
        if not name:
            return _levels.get("", _default_level)
        return _levels.get(name, LoggingSeverity.UNSET)


def get_logging_severity_from_string(log_severity: str) -> LoggingSeverity:
    """A severity by rcutils' name (``info``, ``WARN``...); RuntimeError otherwise, as rclpy.

    The names: ``unset``, ``debug``, ``info``, ``warn``, ``error``, ``fatal``, in any case.
    """
    key = log_severity.upper()
    if key not in LoggingSeverity.__members__:
        raise RuntimeError("Failed to get severity name")
    return LoggingSeverity[key]


def get_logger_effective_level(name: str) -> LoggingSeverity:
    """The effective threshold of ``name``: its own, its nearest ancestor's, else INFO."""
    parts = name.split(".") if name else []
    while parts:
        level = _levels.get(".".join(parts))
        if level is not None and level != LoggingSeverity.UNSET:
            return level
        parts.pop()
    return _levels.get("", _default_level)


class RcutilsLogger:
    """A named logger (rclpy's ``RcutilsLogger`` API)."""

    def __init__(self, name: str = "", clock_ns: Callable[[], int] | None = None) -> None:
        self.name = name
        self._clock_ns = clock_ns if clock_ns is not None else time.time_ns
        # Per call site: (times called, last emitted stamp or None).
        self._sites: dict[tuple[object, int], list[int | None]] = {}

    def get_child(self, name: str) -> RcutilsLogger:
        """Logger ``<self>.<name>`` sharing this logger's clock."""
        if not name:
            raise ValueError("child logger name must not be empty")
        full = f"{self.name}.{name}" if self.name else name
        with _lock:
            handlers = _rosout.get(self.name)
            if handlers and self.name:  # rcl's rosout sublogger
                for handler in handlers:
                    if handler not in _rosout.setdefault(full, []):
                        _rosout[full].append(handler)
        return RcutilsLogger(full, self._clock_ns)

    def set_level(self, level: LoggingSeverity | int) -> None:
        """Set this logger's threshold."""
        set_logger_level(self.name, level)

    def get_effective_level(self) -> LoggingSeverity:
        """The threshold in force for this logger."""
        return get_logger_effective_level(self.name)

    def is_enabled_for(self, severity: LoggingSeverity | int) -> bool:
        """Whether a message of ``severity`` would be printed."""
        return severity >= self.get_effective_level()

    def _emit(
        self,
        message: object,
        severity: LoggingSeverity,
        frame: FrameType | None,
        throttle_duration_sec: float | None = None,
        throttle_time_source_type: object = None,
        skip_first: bool = False,
        once: bool = False,
    ) -> bool:
        del throttle_time_source_type  # the logger's own clock is used (module docstring)
        if severity < self.get_effective_level():
            return False
        if type(message) is not str:  # rclpy hands the message to C: a str or None only
            if message is not None and not isinstance(message, str):
                raise TypeError(
                    f"the log message must be a str, got {type(message).__name__} "
                    f"(rclpy raises TypeError too)")
            message = "(null)" if message is None else str(message)
        filtered = once or skip_first or throttle_duration_sec is not None
        now = self._clock_ns()
        if filtered:
            key = (frame.f_code, frame.f_lineno) if frame is not None else (None, 0)
            site = self._sites.setdefault(key, [0, None])
            calls = int(site[0] or 0)
            site[0] = calls + 1
            if once and calls > 0:
                return False
            if throttle_duration_sec is not None:
                last = site[1]
                if last is not None and now - last < round(throttle_duration_sec * 1e9):
                    return False
                site[1] = now
                if skip_first and last is None:
                    return False
            elif skip_first and calls == 0:
                return False
        if frame is not None:
            code = frame.f_code
            path = _abspaths.get(code.co_filename)
            if path is None:  # rclpy's CallerId path: absolute
                path = _abspaths[code.co_filename] = os.path.abspath(code.co_filename)
            record = LogRecord(severity, self.name, now, message, path, code.co_name,
                               frame.f_lineno)
        else:
            record = LogRecord(severity, self.name, now, message)
        with _lock:
            sinks = list(_sinks)
        for sink in sinks:
            sink(record)
        handlers = _rosout.get(self.name)
        if handlers:
            _publish_rosout(handlers[0], record)
        return True

    def log(self, message: object, severity: LoggingSeverity | int, **kwargs: object) -> bool:
        """Log at ``severity``; returns whether the line was emitted."""
        return self._emit(message, LoggingSeverity(severity), sys._getframe(1), **kwargs)  # type: ignore[arg-type]

    def debug(self, message: object, **kwargs: object) -> bool:
        """Log at DEBUG."""
        return self._emit(message, LoggingSeverity.DEBUG, sys._getframe(1), **kwargs)  # type: ignore[arg-type]

    def info(self, message: object, **kwargs: object) -> bool:
        """Log at INFO."""
        return self._emit(message, LoggingSeverity.INFO, sys._getframe(1), **kwargs)  # type: ignore[arg-type]

    def warning(self, message: object, **kwargs: object) -> bool:
        """Log at WARN."""
        return self._emit(message, LoggingSeverity.WARN, sys._getframe(1), **kwargs)  # type: ignore[arg-type]

    warn = warning

    def error(self, message: object, **kwargs: object) -> bool:
        """Log at ERROR."""
        return self._emit(message, LoggingSeverity.ERROR, sys._getframe(1), **kwargs)  # type: ignore[arg-type]

    def fatal(self, message: object, **kwargs: object) -> bool:
        """Log at FATAL."""
        return self._emit(message, LoggingSeverity.FATAL, sys._getframe(1), **kwargs)  # type: ignore[arg-type]


def get_logger(name: str = "") -> RcutilsLogger:
    """A wall-clock logger called ``name`` (rclpy.logging.get_logger)."""
    return RcutilsLogger(name)
