"""Random tf2 trees for property tests: frames f0..fn-1, dynamic and static edges, samples
re-parented between stamps, and query times inside, on and outside the stored stamps."""

from __future__ import annotations

from typing import Any

from hypothesis import strategies as st

from posekit.msgs.geometry_msgs import TransformStamped

__all__ = ["S", "apply", "msg", "scene"]

S = 1_000_000_000


def msg(parent: str, child: str, ns: int, q: tuple[float, ...], v: tuple[float, ...]) -> Any:
    """A TransformStamped parent_T_child stamped ``ns`` nanoseconds."""
    m = TransformStamped()
    m.header.frame_id = parent
    m.child_frame_id = child
    m.header.stamp.sec, m.header.stamp.nanosec = divmod(ns, S)
    r = m.transform.rotation
    r.x, r.y, r.z, r.w = q
    tr = m.transform.translation
    tr.x, tr.y, tr.z = v
    return m


_component = st.sampled_from([0.0, -0.0, 0.5, -0.5, 1.0, 0.3, -0.7, 2.0])
_quat = st.tuples(_component, _component, _component, _component).filter(
    lambda q: sum(c * c for c in q) > 0.0
)
_vec = st.tuples(_component, _component, _component)


@st.composite
def scene(draw: st.DrawFn) -> tuple[list[tuple[Any, bool]], list[int], int]:
    """(inserts as (message, is_static), query times, number of frames)."""
    n = draw(st.integers(3, 6))
    names = [f"f{i}" for i in range(n)]
    inserts: list[tuple[Any, bool]] = []
    for i in range(1, n):
        parent = draw(st.integers(0, i - 1))
        if draw(st.integers(0, 4)) == 0:
            inserts.append((msg(names[parent], names[i], 0, draw(_quat), draw(_vec)), True))
            continue
        for k in range(draw(st.integers(1, 4))):
            stamp = 10 * S + draw(st.sampled_from([0, 1, 2, 3])) * S // 10 + k
            p = parent
            if draw(st.integers(0, 5)) == 0:  # re-parented sample
                p = draw(st.integers(0, n - 1))
                if p == i:
                    p = parent
            inserts.append((msg(names[p], names[i], stamp, draw(_quat), draw(_vec)), False))
    times = [0, 10 * S, 10 * S + S // 20, 10 * S + S // 10, 10 * S + 2 * S // 10 + 1]
    times += [10 * S + S // 7, 10 * S + 4 * S // 10, 9 * S]
    return inserts, times, n


def apply(cores: list[Any], inserts: list[tuple[Any, bool]]) -> None:
    """Insert the scene's messages into every core, in order."""
    for m, static in inserts:
        for core in cores:
            if static:
                core.set_transform_static(m, "test")
            else:
                core.set_transform(m, "test")
