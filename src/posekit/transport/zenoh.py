"""Alias module: the runtime's transport registry names ``posekit.transport.zenoh:ZenohTransport``.

The implementation is :mod:`posekit.transport.zenoh_transport`.
"""

from __future__ import annotations

from posekit.transport.zenoh_transport import ZenohTransport

__all__ = ["ZenohTransport"]
