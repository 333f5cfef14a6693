"""Parameters: declare/get/set, overrides (constructor, --ros-args), types, callbacks."""

from __future__ import annotations

import pytest

from posekit.runtime.context import Context
from posekit.runtime.node import Node
from posekit.runtime.parameters import (
    InvalidParameterTypeException,
    Parameter,
    ParameterAlreadyDeclaredException,
    ParameterDescriptor,
    ParameterNotDeclaredException,
    SetParametersResult,
    declare_value,
    parse_parameter_value,
)


def test_declare_default_and_override(ctx) -> None:
    node = Node("ctl", context=ctx, parameter_overrides=[Parameter("k_rho", value=1.0)])
    assert node.declare_parameter("k_rho", 0.5).value == 1.0
    assert node.declare_parameter("k_alpha", 2.0).value == 2.0
    assert node.get_parameter("k_rho").value == 1.0
    assert node.get_parameter("k_rho").type_ == Parameter.Type.DOUBLE
    assert node.declare_parameter("ignored", 3, ignore_override=True).value == 3
    with pytest.raises(ParameterAlreadyDeclaredException):
        node.declare_parameter("k_rho", 0.1)
    with pytest.raises(ParameterNotDeclaredException):
        node.get_parameter("nope")


def test_declare_value_declares_and_returns_the_winning_value(ctx) -> None:
    node = Node("ctl", context=ctx, parameter_overrides={"k_rho": 1.0})
    assert declare_value(node, "k_rho", 0.5) == 1.0  # the override wins
    assert declare_value(node, "k_alpha", 2.0) == 2.0
    assert node.get_parameter("k_alpha").type_ == Parameter.Type.DOUBLE  # really declared
    with pytest.raises(ParameterAlreadyDeclaredException):
        declare_value(node, "k_alpha", 3.0)


def test_dict_overrides_and_an_int_is_no_double(ctx) -> None:
    # rclpy's rule and text (tests/rclpy/differential/parameters.py runs it on both)
    node = Node("ctl", context=ctx, parameter_overrides={"k_rho": 1, "name": "bot",
                                                         "k_alpha": 1.0})
    with pytest.raises(InvalidParameterTypeException) as raised:
        node.declare_parameter("k_rho", 0.5)
    assert str(raised.value) == ("Trying to set parameter 'k_rho' to '1' of type 'INTEGER', "
                                 "expecting type 'DOUBLE': k_rho")
    assert not node.has_parameter("k_rho")
    p = node.declare_parameter("k_alpha", 0.5)
    assert p.value == 1.0
    assert isinstance(p.value, float)
    assert node.declare_parameter("name", "default").value == "bot"


def test_override_of_wrong_type_is_refused(ctx) -> None:
    node = Node("ctl", context=ctx, parameter_overrides={"k_rho": "fast"})
    with pytest.raises(InvalidParameterTypeException, match="expecting type 'DOUBLE'"):
        node.declare_parameter("k_rho", 0.5)


def test_global_ros_args() -> None:
    context = Context()
    context.init(args=["prog", "--ros-args", "-p", "rate:=20", "-p", "flag:=true",
                       "-r", "chatter:=/other"])
    try:
        node = Node("n", context=context)
        assert node.declare_parameter("rate", 10).value == 20
        assert node.declare_parameter("flag", False).value is True
        assert node.resolve_topic_name("chatter") == "/other"
    finally:
        context.shutdown()


def test_set_parameters_type_checks_and_callbacks(ctx) -> None:
    node = Node("ctl", context=ctx)
    node.declare_parameter("gain", 0.5)
    node.declare_parameter("locked", 1, ParameterDescriptor(read_only=True))
    results = node.set_parameters([Parameter("gain", value=0.7), Parameter("gain", value="x"),
                                   Parameter("locked", value=2)])
    assert [r.successful for r in results] == [True, False, False]
    assert results[1].reason == "Wrong parameter type, expected 'Type.DOUBLE' got 'Type.STRING'"
    assert results[2].reason == "Trying to set a read-only parameter: locked."
    assert node.get_parameter("gain").value == 0.7

    def veto(params: list[Parameter]) -> SetParametersResult:
        for p in params:
            if p.name == "gain" and p.value < 0:
                return SetParametersResult(successful=False, reason="gain must be >= 0")
        return SetParametersResult(successful=True)

    node.add_on_set_parameters_callback(veto)
    (r,) = node.set_parameters([Parameter("gain", value=-1.0)])
    assert not r.successful
    assert r.reason == "gain must be >= 0"
    assert node.get_parameter("gain").value == 0.7
    with pytest.raises(TypeError, match="not one of the allowed types"):
        node.declare_parameter("other", object())
    with pytest.raises(ParameterNotDeclaredException):
        node.set_parameters([Parameter("undeclared", value=1)])


def test_use_sim_time_switches_the_clock(ctx) -> None:
    node = Node("n", context=ctx)
    assert node.get_parameter("use_sim_time").value is False
    assert not node.get_clock().ros_time_is_active
    (r,) = node.set_parameters([Parameter("use_sim_time", value=True)])
    assert r.successful
    assert node.get_clock().ros_time_is_active
    assert node.get_clock().now().nanoseconds == 0  # no /clock yet
    (bad,) = node.set_parameters([Parameter("use_sim_time", value=1)])
    assert not bad.successful


@pytest.mark.parametrize(
    ("text", "value"),
    [("true", True), ("False", False), ("3", 3), ("0.5", 0.5), ("abc", "abc"),
     ("[1, 2]", [1, 2]), ("'7'", "7")],
)
def test_parse_parameter_value(text: str, value: object) -> None:
    parsed = parse_parameter_value(text)
    assert parsed == value
    assert type(parsed) is type(value)


def test_log_level_argument_and_rclpy_init_signature() -> None:
    from posekit.runtime.context import init
    from posekit.runtime.logging import LoggingSeverity, get_logger_level

    context = Context()
    init(["prog", "--ros-args", "--log-level", "lvl_node:=debug"], context=context,
         domain_id=3)
    try:
        assert get_logger_level("lvl_node") == LoggingSeverity.DEBUG
        with pytest.raises(ValueError, match="Couldn't parse log level"):
            Context().init(["--ros-args", "--log-level", "loud"])
        with pytest.raises(ValueError, match="unknown ROS arguments"):
            Context().init(["--ros-args", "--no-such-flag", "x"])
    finally:
        context.shutdown()
