"""``posekit launch`` and ``posekit run`` arguments, in this process on the isolated bus.

Oracles: the parameter values the started nodes report (``get_parameter``), the P
controller's documented node defaults, ``ros2 launch -s``'s output layout (a header line,
then per argument ``'name':``, a description line and ``(default: 'value')``), the lecture's
command lines (``ros2 launch PACKAGE FILE.launch.py`` / ``ros2 run PACKAGE EXECUTABLE``) and
the scenario registry.
"""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import Any

import pytest

from posekit.cli import launch_cmd, run_cmd
from posekit.cli.main import main as posekit_main


@pytest.fixture(autouse=True)
def _isolated(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("POSEKIT_TRANSPORT", "inprocess")


def run_cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = launch_cmd.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def spy_scenario(monkeypatch: pytest.MonkeyPatch) -> dict[str, Any]:
    """Record what run_robot_scenario receives (the real one still runs)."""
    import posekit.robot.scenarios as scenarios

    seen: dict[str, Any] = {}
    real = scenarios.run_robot_scenario

    def spy(name: str, params: Any, **kwargs: Any) -> Any:
        seen.update(name=name, params=dict(params), **kwargs)
        result = real(name, params, **kwargs)
        seen["k_rho"] = result.node("p_controller").get_parameter("k_rho").value
        return result

    monkeypatch.setattr(scenarios, "run_robot_scenario", spy)
    return seen


@pytest.mark.parametrize("argv", [
    ["p_controller", "--until-sim-time", "0.5", "k_rho:=1.0"],
    ["--until-sim-time", "0.5", "p_controller", "k_rho:=1.0"],
    ["p_controller", "k_rho:=1.0", "--until-sim-time", "0.5", "--seed", "3"],
    ["p_controller", "--param", "k_rho:=1.0", "--until-sim-time=0.5"],
])
def test_options_and_assignments_in_any_order(
    argv: list[str], capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    seen = spy_scenario(monkeypatch)
    code, out, err = run_cli(capsys, *argv)
    assert code == 0, err
    assert seen["name"] == "p_controller"
    assert seen["params"] == {"k_rho": 1.0}
    assert seen["until_sim_time"] == 0.5
    assert seen["k_rho"] == 1.0
    assert seen["transport"] == "inprocess"  # POSEKIT_TRANSPORT=inprocess: isolated
    assert out.startswith("p_controller: 0.50 s simulated")


def test_network_is_the_default_and_isolated_switches_it_off(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.delenv("POSEKIT_TRANSPORT")
    parser = launch_cmd._parser()
    assert launch_cmd.network_transport(parser.parse_args(["x"])) == "zenoh"
    assert launch_cmd.network_transport(parser.parse_args(["x", "--isolated"])) is None
    monkeypatch.setenv("POSEKIT_TRANSPORT", "inprocess")
    assert launch_cmd.network_transport(parser.parse_args(["x"])) is None


def test_unknown_transport_is_one_line(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    code, _, err = run_cli(capsys, "p_controller", "--transport", "carrier_pigeon")
    assert code == 2
    assert err.count("\n") == 1
    assert "invalid choice: 'carrier_pigeon'" in err
    monkeypatch.setenv("POSEKIT_TRANSPORT", "carrier_pigeon")
    code, _, err = run_cli(capsys, "p_controller")
    assert code == 2
    assert err.count("\n") == 1
    assert "unknown transport 'carrier_pigeon'" in err


def test_show_args_lists_parameters_with_defaults(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run_cli(capsys, "p_controller", "--show-args")
    assert code == 0
    lines = out.splitlines()
    assert lines[0] == "Arguments (pass arguments as '<name>:=<value>'):"
    block = lines[lines.index("    'k_rho':"):][:3]
    # The node's documented default, not the launch's goal overrides.
    assert block == ["    'k_rho':", "        parameter of p_controller",
                     "        (default: '0.4')"]
    i = lines.index("    'goal_x':")
    assert lines[i + 2] == "        (default: '5.0')"  # p_controller.launch.py's goal


def test_lecture_launch_lines_resolve() -> None:
    import posekit.demos.scenarios  # noqa: F401
    from posekit.demos.lecture import resolve_launch
    from posekit.launch.scenarios import ScenarioError, get_scenario

    lecture = {
        "rosbot_gazebo empty_world.launch.py": "empty_world",
        "rosbot_gazebo husarion_world.launch.py": "husarion_world",
        "rosbot_gazebo aruco_box_world.launch.py": "aruco_box_world",
        "rosbot_gazebo aruco_box_camera_world.launch.py": "aruco_box_camera_world",
        "rosbot_gazebo aruco_markers_world.launch.py": "aruco_markers_world",
        "robot_control_demo p_controller.launch.py": "robot_control_demo/p_controller",
        "frame_demo dynamic_detector_demo.launch.py": "frame_demo/dynamic_detector_demo",
        "frame_demo dynamic_detector_listener.launch.py": "frame_demo/dynamic_detector_listener",
        "frame_demo static_aruco_detector.launch.py": "frame_demo/static_aruco_detector",
        "frame_demo kdl_chain_demo.launch.py": "frame_demo/kdl_chain_demo",
    }
    for line, name in lecture.items():
        assert resolve_launch(line.split()) == name, line
        scenario = get_scenario(name)
        # Worlds own the simulation; the demos follow a running world's clock.
        assert scenario.follows_clock == (not line.startswith("rosbot_gazebo")), line
    assert resolve_launch(["p_controller"]) == "p_controller"  # combined, one process
    assert not get_scenario("p_controller").follows_clock
    assert resolve_launch(["dynamic_detector_demo.launch.py"]) == (
        "frame_demo/dynamic_detector_demo")
    with pytest.raises(ScenarioError, match=r"no launch file 'nope\.launch\.py'"):
        resolve_launch(["rosbot_gazebo", "nope.launch.py"])


def test_world_launch_has_the_robot_and_its_cameras() -> None:
    import posekit.demos.scenarios  # noqa: F401
    from posekit.launch.scenarios import start_scenario

    run = start_scenario("aruco_box_camera_world", {}, 0)
    try:
        names = {n.get_name() for n in run.nodes}
    finally:
        run.shutdown()
    assert names == {"world_simulation", "wheel_odometry", "ekf_node", "oak_camera",
                     "overhead_camera"}
    run = start_scenario("husarion_world", {}, 0)  # its own walls
    try:
        assert {n.get_name() for n in run.nodes} == {
            "world_simulation", "wheel_odometry", "ekf_node", "oak_camera"}
        assert run.node("world_simulation").get_parameter("world").value == "husarion_world"
    finally:
        run.shutdown()


def test_demo_launch_needs_the_network(capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = run_cli(capsys, "robot_control_demo", "p_controller.launch.py")
    assert code == 2
    assert err.count("\n") == 1
    assert "needs the network" in err


def test_run_maps_lecture_executables(capsys: pytest.CaptureFixture[str]) -> None:
    assert run_cmd.main(["robot_control_demo", "no_such_node"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "robot_control_demo random_mover" in err
    # A ROS tool maps onto posekit's: the same exit code and output as posekit tf echo.
    direct = posekit_main(["tf", "echo", "--help"]), capsys.readouterr()
    via_run = posekit_main(["run", "tf2_ros", "tf2_echo", "--help"]), capsys.readouterr()
    assert via_run == direct
    assert "tf2_echo source_frame target_frame" in via_run[1].out


@pytest.mark.parametrize(("args", "error"), [
    # every --ros-args form is accepted: what stops this run is only the isolated bus
    (["--ros-args", "-r", "__ns:=/r", "-r", "a:=b", "-r", "__node:=x", "--log-level", "warn",
      "-p", "publish_rate:=4.0"], "runs against a running world"),
    (["--ros-args", "--bogus"], "--ros-args: Found unknown ROS arguments: ['--bogus']"),
    (["--ros-args", "-p", "rate"], "--ros-args: Couldn't parse parameter override rule: "
                                   "'-p rate'"),
    (["--ros-args", "--params-file", "/nonexistent/p.yaml"],
     "--ros-args: Couldn't parse params file: '--params-file /nonexistent/p.yaml'"),
    (["--no-such-option"], "unrecognized arguments: --no-such-option"),
])
def test_run_errors_are_one_line_naming_posekit_run(
        args: list[str], error: str, capsys: pytest.CaptureFixture[str]) -> None:
    code = run_cmd.main(["robot_control_demo", "random_mover", *args])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1, err
    assert err.startswith("posekit run: "), err
    assert error in err


def test_run_of_a_tool_refuses_ros_args_in_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    code = run_cmd.main(["tf2_ros", "tf2_echo", "odom", "base_link", "--ros-args", "-p",
                         "use_sim_time:=true"])
    err = capsys.readouterr().err
    assert code == 2
    assert err == ("posekit run: tf2_ros tf2_echo is 'posekit tf echo', which takes no "
                   "--ros-args (see its --help for its options)\n")


LAUNCH_FILE = """
from posekit.launch import DeclareLaunchArgument, LaunchConfiguration, LaunchDescription, Node
from sibling_node import make_node  # a module next to the launch file

def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument("rate", default_value=4.0, description="ticks per second"),
        DeclareLaunchArgument("seed", default_value=0, description="random seed"),
        Node(make_node, name="ticker",
             parameters=[{"rate": LaunchConfiguration("rate"),
                          "seed": LaunchConfiguration("seed")}]),
    ])
"""

SIBLING = """
from posekit.runtime.node import Node

TICKS = []

def make_node():
    node = Node("ticker")
    rate = node.declare_parameter("rate", 1.0).value
    seed = node.declare_parameter("seed", 0).value
    node.create_timer(1.0 / rate, lambda: TICKS.append((node.get_clock().now().nanoseconds,
                                                         seed)))
    return node
"""


@pytest.fixture
def launch_file(tmp_path: Path) -> Path:
    (tmp_path / "sibling_node.py").write_text(textwrap.dedent(SIBLING))
    path = tmp_path / "ticker.launch.py"
    path.write_text(textwrap.dedent(LAUNCH_FILE))
    return path


def test_launch_file_folder_is_importable_and_options_apply(
    launch_file: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import sys

    code, _, err = run_cli(capsys, str(launch_file), "--until-sim-time", "2", "rate:=2.0",
                           "--seed", "7")
    assert code == 0, err
    ticks = sys.modules["sibling_node"].TICKS
    assert [t for t, _ in ticks] == [int(k * 0.5e9) for k in range(1, 5)]  # 2 Hz for 2 s
    assert {s for _, s in ticks} == {7}


def test_isolated_launch_file_cannot_follow_a_clock(
    launch_file: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, _, err = run_cli(capsys, str(launch_file), "use_sim_time:=true")
    assert code == 2
    assert err == ("posekit launch: use_sim_time:=true follows a running simulation's /clock, "
                   "which an isolated launch cannot hear (drop --isolated)\n")


def test_a_world_marks_a_launch_as_its_own_clock_source() -> None:
    from posekit.demos.scenarios import include_scenario
    from posekit.launch import CLOCK_SOURCE, LaunchDescription, Node
    from posekit.robot.nodes.world_simulation import WorldSimulation

    assert getattr(WorldSimulation, CLOCK_SOURCE) is True
    assert LaunchDescription([*include_scenario("empty_world")]).has_clock_source()
    assert not LaunchDescription([*include_scenario("robot_control_demo/random_mover"),
                                  Node("posekit.robot.nodes:EkfNode")]).has_clock_source()


def test_launch_file_show_args_and_one_line_errors(
    launch_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, _ = run_cli(capsys, str(launch_file), "-s")
    assert code == 0
    assert "    'rate':\n        ticks per second\n        (default: '4.0')\n" in out
    broken = tmp_path / "broken.launch.py"
    broken.write_text("import does_not_exist_anywhere\n")
    code, _, err = run_cli(capsys, str(broken))
    assert code == 2
    assert err.count("\n") == 1
    assert "ModuleNotFoundError" in err
    no_seed = tmp_path / "plain.py"
    no_seed.write_text("from posekit.launch import LaunchDescription\n"
                       "def generate_launch_description():\n    return LaunchDescription([])\n")
    code, _, err = run_cli(capsys, str(no_seed), "--seed", "1")
    assert code == 2
    assert err.count("\n") == 1
    assert "declares no 'seed' launch argument" in err
    # --plot on a launch file that runs no robot: one line, not a traceback.
    code, _, err = run_cli(capsys, str(no_seed), "--plot", str(tmp_path / "odom.png"),
                           "--until-sim-time", "0.5")
    assert code == 2
    assert err.count("\n") == 1
    assert "--plot: the recording holds no odometry messages" in err


def test_launch_file_plot_and_record(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "robot.launch.py"
    path.write_text("from posekit.demos.scenarios import include_scenario\n"
                    "from posekit.launch import LaunchDescription\n"
                    "def generate_launch_description():\n"
                    "    return LaunchDescription(include_scenario('p_controller'))\n")
    png, bag = tmp_path / "odom.png", tmp_path / "bag"
    code, out, err = run_cli(capsys, str(path), "--until-sim-time", "2", "--plot", str(png),
                             "--record", str(bag))
    assert code == 0, err
    assert f"odometry plot: {png}" in out
    assert png.read_bytes().startswith(b"\x89PNG")
    assert (bag / "metadata.yaml").is_file()
