"""The scenario framework on its own (no robot): registry, parameter routing, start and run.

Oracles: the routing rules the module documents (defaults, then every plain user parameter,
then the user's ``node.param``), the parameter values the started nodes report
(``get_parameter``), the executor's simulated clock, a counting timer of a tiny test node
(its period fixed here), and the wall clock for ``realtime`` pacing.
"""

from __future__ import annotations

import re
import time
from collections.abc import Mapping
from typing import Any

import pytest

from posekit.launch import LaunchDescription
from posekit.launch.scenarios import (
    ScenarioError,
    get_scenario,
    register_scenario,
    run_scenario,
    scenario_names,
    scenario_node,
    scenario_value,
    start_scenario,
)
from posekit.runtime.logging import LoggingSeverity
from posekit.runtime.node import Node


class _Ticker(Node):
    """Counts its timer (``period`` s of node time) and logs each tick."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("ticker", **kwargs)
        self.declare_parameter("period", 0.5)
        self.declare_parameter("gain", 1.0)
        self.ticks = 0
        self.create_timer(self.get_parameter("period").value, self._tick)

    def _tick(self) -> None:
        self.ticks += 1
        self.get_logger().info(f"tick {self.ticks}")


class _Other(Node):
    def __init__(self, **kwargs: Any) -> None:
        super().__init__("other", **kwargs)
        self.declare_parameter("gain", 1.0)


def _two_nodes(params: Mapping[str, Any], seed: int) -> LaunchDescription:
    return LaunchDescription([
        scenario_node(_Ticker, "ticker", {"gain": 2.0}, params),
        scenario_node(_Other, "other", None, params),
    ])


@pytest.fixture
def ticker_scenario() -> str:
    name = "test_launch_ticker"
    register_scenario(name, _two_nodes, description="two tiny nodes", replace=True)
    return name


def test_registry_names_describes_and_refuses_duplicates(ticker_scenario: str) -> None:
    assert ticker_scenario in scenario_names()
    assert scenario_names() == sorted(scenario_names())
    assert get_scenario(ticker_scenario).description == "two tiny nodes"
    with pytest.raises(ScenarioError, match="already registered"):
        register_scenario(ticker_scenario, _two_nodes)
    with pytest.raises(ScenarioError, match="non-empty"):
        register_scenario("", _two_nodes)
    with pytest.raises(ScenarioError, match=r"unknown scenario 'nope'; available: .*ticker"):
        get_scenario("nope")


def test_parameters_route_plain_to_all_and_scoped_to_one(ticker_scenario: str) -> None:
    params = {"gain": 3.0, "other.gain": 4.0}
    assert scenario_value(params, "ticker", "gain", 0.0) == 3.0
    assert scenario_value(params, "other", "gain", 0.0) == 4.0
    assert scenario_value({}, "other", "gain", 7.0) == 7.0
    run = start_scenario(ticker_scenario, params)
    try:
        assert run.node("ticker").get_parameter("gain").value == 3.0  # user beats default
        assert run.node("other").get_parameter("gain").value == 4.0   # scoped beats plain
    finally:
        run.shutdown()


def test_unknown_or_bad_parameters_are_named(ticker_scenario: str) -> None:
    with pytest.raises(ScenarioError, match=re.escape("unknown parameter(s) ['gian']")) as info:
        start_scenario(ticker_scenario, {"gian": 1.0})
    assert "gain, period" in str(info.value)  # the declared ones, listed
    with pytest.raises(ScenarioError, match=re.escape("unknown parameter(s) ['other.period']")):
        start_scenario(ticker_scenario, {"other.period": 1.0})
    with pytest.raises(ScenarioError, match="cannot start"):
        start_scenario(ticker_scenario, {"period": "fast"})


def test_run_steps_simulated_time_and_collects_logs(ticker_scenario: str) -> None:
    result = run_scenario(ticker_scenario, {"period": 0.25}, until_sim_time=2.0)
    assert result.sim_time == pytest.approx(2.0)
    assert result.node("ticker").ticks == 8  # 2 s / 0.25 s
    ticks = [r.message for r in result.logs
             if r.name == "ticker" and r.severity == LoggingSeverity.INFO]
    assert ticks == [f"tick {i}" for i in range(1, 9)]
    kept = run_scenario(ticker_scenario, {"period": 0.25}, until_sim_time=2.0,
                        max_log_records=3)
    assert [r.message for r in kept.logs if r.name == "ticker"] == ["tick 6", "tick 7", "tick 8"]


def test_stop_when_ends_the_run_at_the_next_step(ticker_scenario: str) -> None:
    result = run_scenario(ticker_scenario, until_sim_time=10.0, step=0.5,
                          stop_when=lambda run: run.node("ticker").ticks >= 3)
    assert result.node("ticker").ticks == 3
    assert result.sim_time == pytest.approx(1.5)


def test_bad_run_arguments_are_refused_before_starting(ticker_scenario: str) -> None:
    for kwargs, message in (({"until_sim_time": -1.0}, "until_sim_time"),
                            ({"step": 0.0}, "step"), ({"max_log_records": -1}, "max_log")):
        with pytest.raises(ScenarioError, match=message):
            run_scenario(ticker_scenario, **kwargs)


def test_a_scenario_that_follows_another_clock_needs_the_network() -> None:
    register_scenario("test_launch_follower", _two_nodes, replace=True, follows_clock=True)
    with pytest.raises(ScenarioError, match="needs a network transport"):
        start_scenario("test_launch_follower")


def test_realtime_paces_to_the_wall_clock(ticker_scenario: str) -> None:
    t0 = time.perf_counter()
    result = run_scenario(ticker_scenario, until_sim_time=0.3, realtime=True)
    assert time.perf_counter() - t0 >= 0.29
    assert result.wall_time >= 0.29
