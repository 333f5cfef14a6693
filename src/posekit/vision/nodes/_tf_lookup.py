"""Base of the lecture's periodic TF-lookup nodes (``aruco_marker_listener``,
``kdl_chain_demo``): a tf2 ``Buffer`` filled by a ``TransformListener`` and a timer.

Parameters it declares: ``period`` (1.0 s, > 0) and ``lookup_timeout`` (0.1 s, the course's;
negative means 0). Subclasses declare their own parameters after ``super().__init__`` and
implement :meth:`_timer_callback`; the timer only fires once an executor spins the node.
"""

from __future__ import annotations

from typing import Any

from posekit.runtime.node import Node
from posekit.runtime.parameters import declare_value
from posekit.tf2 import Buffer
from posekit.tf2_ros import TransformListener
from posekit.time import Duration

__all__ = ["PeriodicTfLookupNode"]


class PeriodicTfLookupNode(Node):
    """A node that looks transforms up every ``period`` seconds (see the module docstring)."""

    def __init__(self, node_name: str, **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        period = float(declare_value(self, "period", 1.0))
        timeout = float(declare_value(self, "lookup_timeout", 0.1))
        if not period > 0.0:
            raise ValueError(f"period must be > 0 s, got {period}")
        self._timeout = Duration(seconds=max(timeout, 0.0))
        # The Buffer before the listener: the listener writes into it.
        self._tf_buffer = Buffer()
        self._tf_listener = TransformListener(self._tf_buffer, self)
        self._timer = self.create_timer(period, self._timer_callback)

    @property
    def buffer(self) -> Buffer:
        """The node's tf2 buffer."""
        return self._tf_buffer

    def _timer_callback(self) -> None:
        raise NotImplementedError
