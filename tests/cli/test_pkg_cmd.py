"""``posekit pkg list|executables``.

Oracle: ros2pkg's output format (Jazzy: names sorted, ``package executable`` lines, ``Package
'x' not found``), and ``posekit run`` itself: every executable listed is one it resolves.
"""

from __future__ import annotations

import io

from posekit.cli import pkg_cmd
from posekit.cli.main import main as posekit_main
from posekit.demos.lecture import resolve_run


def test_list_and_executables_as_ros2_pkg() -> None:
    out = io.StringIO()
    assert pkg_cmd.main_list([], out=out) == 0
    packages = out.getvalue().splitlines()
    assert packages == sorted(packages)
    assert {"robot_control_demo", "frame_demo", "tf2_ros"} <= set(packages)
    out = io.StringIO()
    assert pkg_cmd.main_executables([], out=out) == 0
    lines = out.getvalue().splitlines()
    assert lines == sorted(lines)
    assert "robot_control_demo p_controller" in lines
    for line in lines:
        package, executable = line.split(" ")
        assert package in packages
        assert resolve_run(package, executable)  # posekit run starts each of them


def test_one_package_and_an_unknown_one() -> None:
    out, err = io.StringIO(), io.StringIO()
    assert pkg_cmd.main_executables(["tf2_ros"], out=out, err=err) == 0
    assert out.getvalue() == "tf2_ros static_transform_publisher\ntf2_ros tf2_echo\n"
    assert pkg_cmd.main_executables(["nope"], out=io.StringIO(), err=err) == 1
    assert err.getvalue() == "Package 'nope' not found\n"


def test_the_dispatcher_routes_pkg(capsys) -> None:
    assert posekit_main(["pkg", "list"]) == 0
    assert "frame_demo\n" in capsys.readouterr().out
