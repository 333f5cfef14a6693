# Shared by every differential script (prepended to it on both sides).
import sys


def show(label, fn):
    """Print ``label: <repr of the result>`` or ``label: raise <Class>: <message>``."""
    try:
        value = fn()
    except Exception as exc:
        text = str(exc).replace("\n", "\\n")
        print(f"{label}: raise {type(exc).__name__}: {text}")
    else:
        print(f"{label}: {value!r}")
    sys.stdout.flush()


def kind(label, fn):
    """Like show, but only the exception class (for messages posekit words differently)."""
    try:
        value = fn()
    except Exception as exc:
        print(f"{label}: raise {type(exc).__name__}")
    else:
        print(f"{label}: {value!r}")
    sys.stdout.flush()


def plain(value):
    """A value with numpy/array.array containers as lists, for printing."""
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    return value
