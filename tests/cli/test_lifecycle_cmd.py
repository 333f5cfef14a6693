"""``posekit lifecycle`` against lifecycle nodes served by another thread (in-process).

Oracle: ros2cli's ros2lifecycle (Jazzy) output formats, written out literally here from its
sources' format strings; the states and transitions are rcl_lifecycle's, which
tests/rclpy/differential/lifecycle.py compares with the real rclpy.
"""

from __future__ import annotations

import io
import threading
from collections.abc import Iterator

import pytest

from posekit.cli import lifecycle_cmd
from posekit.cli.main import main as posekit_main
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from posekit.runtime.node import Node


class Camera(LifecycleNode):
    """Refuses to activate while ``broken``."""

    broken = False

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        if self.broken:
            return TransitionCallbackReturn.FAILURE
        return super().on_activate(state)


@pytest.fixture
def camera(ctx) -> Iterator[Camera]:
    node = Camera("camera", namespace="/robot", context=ctx)
    plain = Node("plain", context=ctx)
    ex = SingleThreadedExecutor(context=ctx)
    ex.add_node(node)
    ex.add_node(plain)
    spinner = threading.Thread(target=ex.spin, daemon=True)
    spinner.start()
    try:
        yield node
    finally:
        ex.shutdown()
        spinner.join(timeout=5.0)


def run(verb: str, argv: list[str], ctx) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    code = lifecycle_cmd.run(verb, argv, context=ctx, out=out, err=err)
    return code, out.getvalue(), err.getvalue()


def test_nodes_lists_only_lifecycle_nodes(ctx, camera: Camera) -> None:
    assert run("nodes", [], ctx) == (0, "/robot/camera\n", "")
    assert run("nodes", ["-c"], ctx) == (0, "1\n", "")


def test_get_list_and_set_walk_the_state_machine(ctx, camera: Camera) -> None:
    assert run("get", ["/robot/camera"], ctx) == (0, "unconfigured [1]\n", "")
    assert run("list", ["/robot/camera"], ctx) == (0, (
        "- configure [1]\n\tStart: unconfigured\n\tGoal: configuring\n"
        "- shutdown [5]\n\tStart: unconfigured\n\tGoal: shuttingdown\n"), "")
    assert run("set", ["/robot/camera", "configure"], ctx) == (
        0, "Transitioning successful\n", "")
    assert run("set", ["/robot/camera", "3"], ctx) == (0, "Transitioning successful\n", "")
    assert run("get", [], ctx) == (0, "/robot/camera: active [3]\n", "")
    graph = run("list", ["/robot/camera", "-a"], ctx)[1]
    assert graph.count("- ") == 25
    assert graph.startswith("- configure [1]\n\tStart: unconfigured\n\tGoal: configuring\n"
                            "- transition_success [10]\n\tStart: configuring\n\tGoal: inactive\n")


def test_a_failed_transition_and_bad_requests_are_one_line(ctx, camera: Camera) -> None:
    camera.broken = True
    assert run("set", ["/robot/camera", "configure"], ctx)[0] == 0
    assert run("set", ["/robot/camera", "activate"], ctx) == (0, "", "Transitioning failed\n")
    assert run("get", ["/robot/camera"], ctx)[1] == "inactive [2]\n"
    assert run("set", ["/robot/camera", "fly"], ctx) == (1, "", (
        "Unknown transition requested, available ones are:\n- cleanup [2]\n- activate [3]\n"
        "- shutdown [6]\n"))
    assert run("get", ["/plain"], ctx) == (1, "", "Node not found\n")
    assert run("list", ["/nobody"], ctx) == (1, "", "Node not found\n")


def test_the_dispatcher_routes_the_verbs(capsys: pytest.CaptureFixture[str]) -> None:
    assert posekit_main(["lifecycle"]) == 0
    assert "nodes" in capsys.readouterr().out
