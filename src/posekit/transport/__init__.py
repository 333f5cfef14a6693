"""Transports that carry posekit messages between processes.

:mod:`posekit.transport.zenoh_wire` is rmw_zenoh's wire format (pure Python, no zenoh
import); :mod:`posekit.transport.zenoh_session` opens Zenoh sessions and moves messages;
:mod:`posekit.transport.zenoh_transport` plugs that into the runtime's Transport interface.
Importing this package imports nothing heavy.
"""

from __future__ import annotations

__all__: list[str] = []
