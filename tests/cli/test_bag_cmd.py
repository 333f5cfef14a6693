"""``posekit bag record|play|info`` on an in-process context (the tools' default transport,
Zenoh, is replaced by the ``context=`` hook)."""

from __future__ import annotations

import io
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from posekit.bag import Recorder, bag_info, format_info, read_messages
from posekit.cli.bag_cmd import info, play, record
from posekit.msgs.rosgraph_msgs import Clock
from posekit.msgs.std_msgs import String
from posekit.runtime.context import Context
from posekit.runtime.executors import SingleThreadedExecutor
from posekit.runtime.node import Node
from posekit.runtime.qos import DurabilityPolicy, QoSProfile
from posekit.runtime.sim_executor import SimulatedTimeExecutor


@pytest.fixture
def ctx() -> Iterator[Context]:
    context = Context()
    context.init(transport="inprocess")
    yield context
    context.try_shutdown()


@pytest.fixture
def small_bag(tmp_path: Path) -> Path:
    """0.5 s of /words at 10 Hz recorded in sim time starting at 20 s."""
    context = Context()
    context.init(transport="inprocess")
    try:
        executor = SimulatedTimeExecutor(context=context, start_time=20.0)
        node = Node("speaker", context=context)
        pub = node.create_publisher(String, "words", 10)
        counter = iter(range(1000))
        node.create_timer(0.1, lambda: pub.publish(String(data=f"w{next(counter)}")))
        executor.add_node(node)
        recorder = Recorder(tmp_path / "small", ["words"], context=context)
        executor.add_node(recorder.node)
        executor.run_for(0.5)
        recorder.close()
    finally:
        context.try_shutdown()
    return tmp_path / "small"


def test_record_topics_from_a_live_publisher(ctx: Context, tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    node = Node("outside", context=ctx)
    chatter = node.create_publisher(String, "chatter", 10)
    latched = node.create_publisher(
        String, "/latched", QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    )
    latched.publish(String(data="sent before recording"))
    stop = threading.Event()
    sent: list[str] = []

    def talk() -> None:
        k = 0
        while not stop.is_set():
            text = f"m{k}"
            chatter.publish(String(data=text))
            sent.append(text)
            k += 1
            time.sleep(0.005)

    thread = threading.Thread(target=talk, daemon=True)
    t_before = time.time_ns()
    thread.start()
    try:
        code = record(["-o", str(tmp_path / "rec"), "/chatter", "latched", "--duration", "0.3"],
                      context=ctx)
    finally:
        stop.set()
        thread.join()
    t_after = time.time_ns()
    assert code == 0
    assert "wrote" in capsys.readouterr().err
    messages = list(read_messages(tmp_path / "rec"))
    words = [m.decode().data for m in messages if m.topic == "/chatter"]
    assert len(words) > 5
    # A contiguous run of what was published (recording started and stopped mid-stream).
    first = sent.index(words[0])
    assert words == sent[first:first + len(words)]
    assert [m.decode().data for m in messages if m.topic == "/latched"] == [
        "sent before recording"
    ]
    # Wall-clock receive stamps (ns since the epoch) inside the recording window.
    assert all(t_before <= m.timestamp_ns <= t_after for m in messages)
    assert bag_info(tmp_path / "rec").version == 9


def test_record_all_and_metadata_version(ctx: Context, tmp_path: Path) -> None:
    node = Node("one", context=ctx)
    pub = node.create_publisher(
        String, "only", QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    )
    pub.publish(String(data="x"))
    code = record(["-o", str(tmp_path / "all"), "--all", "--metadata-version", "8",
                   "--no-compression", "--duration", "0.05"], context=ctx)
    assert code == 0
    summary = bag_info(tmp_path / "all")
    assert summary.version == 8
    assert summary.chunk_compression == ""
    # --all takes every topic, /parameter_events and /rosout too (every node has them)
    assert [t.name for t in summary.topics] == ["/only", "/parameter_events", "/rosout"]


@pytest.mark.parametrize(
    "argv",
    [
        ["-o", "X"],  # neither topics nor --all
        ["-o", "X", "--exclude-regex", "b", "/a"],  # exclusion needs --all or --regex
        ["-o", "X", "--exclude-topics", "/b", "--topics", "/a"],
        ["-o", "X", "--compression-format", "zstd", "/a"],  # a format needs a mode
        ["-o", "X", "/a", "--metadata-version", "7"],
        ["-o", "X", "/a", "--duration", "-1"],
    ],
)
def test_record_usage_errors(argv: list[str], tmp_path: Path, ctx: Context,
                             capsys: pytest.CaptureFixture[str]) -> None:
    argv = [str(tmp_path / a) if a == "X" else a for a in argv]
    assert record(argv, context=ctx) == 2
    assert "posekit bag record" in capsys.readouterr().err
    assert not (tmp_path / "X").exists()


def test_record_refuses_existing_output(tmp_path: Path, ctx: Context,
                                        capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "exists").mkdir()
    assert record(["-o", str(tmp_path / "exists"), "/a"], context=ctx) == 1
    assert "already exists." in capsys.readouterr().err  # rosbag2's wording


def test_info_prints_the_summary(small_bag: Path) -> None:
    out = io.StringIO()
    assert info([str(small_bag)], out=out) == 0
    assert out.getvalue() == format_info(bag_info(small_bag))
    assert "Topic information: Topic: /words | Type: std_msgs/msg/String | Count: 5 |" in (
        out.getvalue()
    )
    verbose = io.StringIO()
    assert info([str(small_bag), "-v"], out=verbose) == 0
    assert "Version:           9" in verbose.getvalue()
    names = io.StringIO()
    assert info([str(small_bag), "-t"], out=names) == 0
    assert names.getvalue() == "/words\n"


def test_info_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert info([str(tmp_path / "missing")]) == 1
    assert "does not exist" in capsys.readouterr().err
    assert info([]) == 2


def test_play_publishes_messages_and_clock(small_bag: Path, ctx: Context) -> None:
    listener = Node("listener", context=ctx)
    words: list[str] = []
    clocks: list[int] = []
    listener.create_subscription(String, "/words", lambda m: words.append(m.data),
                                 QoSProfile(depth=100))
    listener.create_subscription(
        Clock, "/clock", lambda m: clocks.append(m.clock.sec * 10**9 + m.clock.nanosec),
        QoSProfile(depth=1000),
    )
    assert play([str(small_bag), "--rate", "50"], context=ctx) == 0
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(listener)  # deliver what queued up while the tool played
    executor.spin_some()
    assert words == ["w0", "w1", "w2", "w3", "w4"]
    assert clocks[0] == 20_100_000_000  # bag time, not wall time
    assert clocks[-1] == 20_500_000_000
    assert clocks == sorted(clocks)


def test_play_errors(tmp_path: Path, small_bag: Path, ctx: Context,
                     capsys: pytest.CaptureFixture[str]) -> None:
    assert play([str(tmp_path / "missing")], context=ctx) == 1
    assert "does not exist" in capsys.readouterr().err
    assert play([str(small_bag), "--rate", "0"], context=ctx) == 1
    assert "rate must be > 0" in capsys.readouterr().err
    assert play([str(small_bag), "--topics", "/other"], context=ctx) == 1
    assert "not in bag" in capsys.readouterr().err
    assert play([], context=ctx) == 2


def _listen(ctx: Context, topic: str) -> tuple[Node, list[str]]:
    listener = Node(f"listener_{topic.strip('/')}", context=ctx)
    words: list[str] = []
    listener.create_subscription(String, topic, lambda m: words.append(m.data),
                                 QoSProfile(depth=100))
    return listener, words


def _deliver(ctx: Context, *nodes: Node) -> None:
    executor = SingleThreadedExecutor(context=ctx)
    for node in nodes:
        executor.add_node(node)
    executor.spin_some()


def test_play_start_offset_and_remap(small_bag: Path, ctx: Context) -> None:
    # messages at 20.1 ... 20.5 s; 0.25 s into the bag is 20.35 s
    listener, words = _listen(ctx, "/words")
    assert play([str(small_bag), "--rate", "50", "--start-offset", "0.25",
                 "--progress-bar", "0"], context=ctx) == 0
    renamed, moved = _listen(ctx, "/renamed")
    assert play([str(small_bag), "--rate", "50", "--remap", "/words:=/renamed",
                 "--progress-bar", "0"], context=ctx) == 0
    _deliver(ctx, listener, renamed)
    assert words == ["w3", "w4"]
    assert moved == ["w0", "w1", "w2", "w3", "w4"]


def test_play_topic_selection_and_usage_errors(small_bag: Path, ctx: Context,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    listener, words = _listen(ctx, "/words")
    assert play([str(small_bag), "--rate", "50", "-e", "/w.rds", "--progress-bar", "0"],
                context=ctx) == 0
    _deliver(ctx, listener)
    assert len(words) == 5
    assert play([str(small_bag), "-x", "/words"], context=ctx) == 2
    assert "no recorded topic matches" in capsys.readouterr().err
    assert play([str(small_bag), "--exclude-topics", "/words"], context=ctx) == 2
    assert play([str(small_bag), "--remap", "/words"], context=ctx) == 2
    assert "old:=new" in capsys.readouterr().err
    assert play([str(small_bag), "--remap", "/nope:=/x"], context=ctx) == 1
    assert "cannot remap ['/nope']" in capsys.readouterr().err


#: Topics where a regular expression's search and its whole-name match differ.
REGEX_TOPICS = ["/words", "/words_raw", "/robot/words", "/chatter"]


@pytest.fixture
def regex_bag(ctx: Context, tmp_path: Path) -> Path:
    """One latched String on each of :data:`REGEX_TOPICS`, recorded by name."""
    node = Node("speakers", context=ctx)
    latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    for topic in REGEX_TOPICS:
        node.create_publisher(String, topic, latched).publish(String(data=topic))
    assert record(["-o", str(tmp_path / "all"), "--topics", *REGEX_TOPICS, "--duration", "0.05"],
                  context=ctx) == 0
    assert sorted(t.name for t in bag_info(tmp_path / "all").topics) == sorted(REGEX_TOPICS)
    return tmp_path / "all"


@pytest.mark.parametrize(("options", "recorded"), [
    (["-e", "/words"], ["/robot/words", "/words", "/words_raw"]),
    (["-e", "/words", "--exclude-regex", "raw"], ["/robot/words", "/words"]),
    (["-e", "^/words$"], ["/words"]),
    (["--all-topics", "--exclude-regex", "words"], ["/chatter"]),
])
def test_record_regex_matches_part_of_a_name(regex_bag: Path, ctx: Context, tmp_path: Path,
                                             options: list[str], recorded: list[str]) -> None:
    """rosbag2 Jazzy's recorder (rosbag2_transport topic_filter.cpp) selects with
    ``std::regex_search``: a match anywhere in the name; a whole-name match would record
    ``/words`` alone in the first two cases and nothing excluded in the last."""
    del regex_bag  # its latched publishers are what is recorded
    assert record(["-o", str(tmp_path / "sel"), *options, "--duration", "0.05"],
                  context=ctx) == 0
    names = {t.name for t in bag_info(tmp_path / "sel").topics}
    assert sorted(names & set(REGEX_TOPICS)) == recorded  # (and /rosout ... with --all-topics)


@pytest.mark.parametrize(("options", "played"), [
    (["-e", "/words"], ["/words"]),
    (["-e", ".*/words.*"], ["/robot/words", "/words", "/words_raw"]),
    (["-e", "/words|/chatter"], ["/chatter", "/words"]),
    (["-x", "/words"], ["/chatter", "/robot/words", "/words_raw"]),
    (["-e", "/words.*", "-x", "/words_r"], ["/words", "/words_raw"]),
])
def test_play_regex_matches_whole_names(regex_bag: Path, options: list[str],
                                        played: list[str]) -> None:
    """rosbag2 Jazzy's player (player.cpp ``allow_topic``, and its MCAP and sqlite3 storage
    filters) selects with ``std::regex_match``: the whole topic name must match, so ``/words``
    plays ``/words`` only, where a search would also play ``/words_raw`` and
    ``/robot/words``, and ``-x /words_r`` excludes nothing."""
    other = Context()
    other.init(transport="inprocess")
    try:
        got: dict[str, list[str]] = {t: [] for t in REGEX_TOPICS}
        listener = Node("listener", context=other)
        for topic in REGEX_TOPICS:
            listener.create_subscription(String, topic, lambda m, t=topic: got[t].append(m.data),
                                         QoSProfile(depth=10))
        assert play([str(regex_bag), *options, "--rate", "20", "--progress-bar", "0",
                     "--disable-keyboard-controls"], context=other) == 0
        _deliver(other, listener)
        assert sorted(t for t, data in got.items() if data) == played
    finally:
        other.try_shutdown()


def test_play_regex_matching_no_whole_name_is_a_usage_error(
        regex_bag: Path, ctx: Context, capsys: pytest.CaptureFixture[str]) -> None:
    # "words" is in every name but is no whole one: rosbag2's player would play nothing
    assert play([str(regex_bag), "-e", "words"], context=ctx) == 2
    assert "no recorded topic matches the selection" in capsys.readouterr().err


def test_play_progress_line(small_bag: Path, ctx: Context) -> None:
    err = io.StringIO()
    assert play([str(small_bag), "--rate", "2", "--progress-bar", "50"], context=ctx,
                err=err) == 0
    updates = [u for u in err.getvalue().split("\r") if u.strip()]
    assert len(updates) >= 5  # 0.2 s of playback at 50 updates/s
    first = updates[0].split()
    assert first[:3] == ["[RUNNING]", "Bag", "Time:"]
    assert float(first[3]) == pytest.approx(20.1, abs=0.02)
    assert first[4:] == ["Duration:", first[5]]
    assert first[5].endswith("/0.400000")
    times = [float(u.split()[3]) for u in updates]
    assert times == sorted(times)


def test_record_default_name_and_split_options(ctx: Context, tmp_path: Path,
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    import datetime

    from posekit.cli.bag_cmd import default_bag_name

    assert default_bag_name(datetime.datetime(2024, 5, 6, 7, 8, 9)) == (
        "rosbag2_2024_05_06-07_08_09")
    monkeypatch.chdir(tmp_path)
    node = Node("one", context=ctx)
    pub = node.create_publisher(
        String, "only", QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    pub.publish(String(data="x"))
    before = default_bag_name()
    assert record(["--all", "--duration", "0.05", "--custom-data", "a=1", "b=x=y"],
                  context=ctx) == 0
    after = default_bag_name()
    made = [p.name for p in tmp_path.iterdir()]
    assert len(made) == 1
    assert before <= made[0] <= after
    assert sorted(p.name for p in (tmp_path / made[0]).iterdir()) == [
        "metadata.yaml", f"{made[0]}_0.mcap"]
    import yaml

    meta = yaml.safe_load((tmp_path / made[0] / "metadata.yaml").read_text())[
        "rosbag2_bagfile_information"]
    assert meta["custom_data"]["a"] == "1"
    assert meta["custom_data"]["b"] == "x=y"


PTY_PLAY = """
import sys
from posekit.cli.main import main
sys.exit(main(["bag", "play", *sys.argv[1:]]))
"""


@pytest.mark.slow
def test_play_keyboard_pause_step_resume_on_a_terminal(small_bag: Path, tmp_path: Path) -> None:
    """The real keyboard path: ``posekit bag play`` with a pseudo-terminal as stdin."""
    import os
    import pty
    import sys

    from _support.ports import free_port
    from _support.procs import Proc

    master, slave = pty.openpty()
    env = {k: v for k, v in os.environ.items() if not k.startswith(("ZENOH_", "ROS_DOMAIN"))}
    env.update(POSEKIT_ZENOH_ROUTER=f"tcp/127.0.0.1:{free_port()}", PYTHONUNBUFFERED="1")
    proc = Proc([sys.executable, "-c", PTY_PLAY, str(small_bag), "--start-paused",
                 "--progress-bar", "20"], env, stdin=slave)
    try:
        proc.wait_stderr("Press SPACE for Pause/Resume", 30, "the keyboard help")
        proc.wait_stderr("[PAUSED ]  Bag Time:     20.100000", 10, "a paused status line")
        os.write(master, b"\x1b[C")  # CURSOR_RIGHT: publish the first message
        os.write(master, b"\x1b[C")  # and the second: bag time 20.2
        proc.wait_stderr("[PAUSED ]  Bag Time:     20.200000", 10, "two steps")
        time.sleep(0.3)
        assert "[RUNNING]" not in "".join(proc.err)  # still paused after stepping
        os.write(master, b" ")  # SPACE: resume; the bag then plays to its end
        proc.finish(20, "playback after resuming")
        assert proc.popen.returncode == 0, proc.describe()
        running = [line for line in proc.err if "[RUNNING]" in line]
        assert running
        assert float(running[0].split()[3]) >= 20.2
    finally:
        proc.kill()
        os.close(master)
        os.close(slave)


def _introspected_server(ctx: Context) -> Node:
    from posekit.msgs.std_srvs import SetBool
    from posekit.runtime.services import ServiceIntrospectionState

    node = Node("switch", context=ctx)
    service = node.create_service(SetBool, "switch", lambda req, resp: resp)
    service.configure_introspection(node.get_clock(), QoSProfile(depth=10),
                                    ServiceIntrospectionState.CONTENTS)
    return node


def _call_switch_in_background(ctx: Context) -> tuple[threading.Event, threading.Thread]:
    """A client in its own executor calling /switch every 10 ms until the event is set."""
    from posekit.msgs.std_srvs import SetBool

    stop = threading.Event()

    def run() -> None:
        caller = Node("caller", context=ctx)
        client = caller.create_client(SetBool, "switch")
        while not stop.is_set():
            client.call(SetBool.Request(data=True), timeout_sec=0.5)
            time.sleep(0.01)

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    return stop, thread


@pytest.mark.parametrize("selection", [["--services", "switch"], ["--all-services"],
                                       ["--all"], ["-e", "swi"]])
def test_record_services(selection: list[str], ctx: Context, tmp_path: Path) -> None:
    server = _introspected_server(ctx)
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(server)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    stop, caller = _call_switch_in_background(ctx)
    try:
        code = record(["-o", str(tmp_path / "svc"), *selection, "--duration", "0.4"],
                      context=ctx)
    finally:
        stop.set()
        caller.join(timeout=5)
        executor.shutdown()
        spinner.join(timeout=5)
    assert code == 0
    summary = bag_info(tmp_path / "svc")
    events = [t for t in summary.topics if t.name == "/switch/_service_event"]
    assert [t.msgtype for t in events] == ["std_srvs/srv/SetBool_Event"]
    assert events[0].message_count >= 2  # REQUEST_RECEIVED and RESPONSE_SENT per call
    text = format_info(summary)
    assert ("Service information: Service: /switch | Type: std_srvs/srv/SetBool | Event Count: "
            f"{events[0].message_count} | Serialization Format: cdr") in text
    if selection[0] == "--all-services":  # services only: no topic
        assert [t.name for t in summary.topics] == ["/switch/_service_event"]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["-o", "X"], "Need to specify at least one option out of --all, --all-topics, "
                      "--all-services, --services, --topics, --topic-types or --regex"),
        (["-o", "X", "--services", "s", "--exclude-services", "s"],
         "--exclude-services argument requires either --all, --all-services or --regex"),
        (["-o", "X", "--services", "s", "--exclude-regex", "s"],
         "--exclude-regex argument requires either --all, --all-topics, --topic-types, "
         "--all-services or --regex"),
        (["-o", "X", "--topics", "/a", "--exclude-topic-types", "std_msgs/msg/String"],
         "--exclude-topic-types argument requires either --all, --all-topics or --regex"),
    ],
)
def test_record_service_usage_errors_use_jazzys_wording(
    argv: list[str], message: str, tmp_path: Path, ctx: Context,
    capsys: pytest.CaptureFixture[str],
) -> None:
    argv = [str(tmp_path / a) if a == "X" else a for a in argv]
    assert record(argv, context=ctx) == 2
    assert message in capsys.readouterr().err


def test_record_topic_types(ctx: Context, tmp_path: Path) -> None:
    node = Node("typed", context=ctx)
    node.create_publisher(String, "text", 10)
    node.create_publisher(Clock, "not_text", 10)
    code = record(["-o", str(tmp_path / "t"), "--topic-types", "std_msgs/msg/String",
                   "--duration", "0.05"], context=ctx)
    assert code == 0
    assert [t.name for t in bag_info(tmp_path / "t").topics] == ["/text"]


def test_play_services_selection_and_request_replay(ctx: Context, tmp_path: Path) -> None:
    """``--topics`` alone still plays services (rosbag2 Jazzy); ``--exclude-services``
    drops them; ``--publish-service-requests`` calls the service instead."""
    from posekit.msgs.std_srvs import SetBool

    server = _introspected_server(ctx)
    words = Node("speaker", context=ctx).create_publisher(String, "words", 10)
    executor = SingleThreadedExecutor(context=ctx)
    executor.add_node(server)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    stop, caller = _call_switch_in_background(ctx)
    talk_stop = threading.Event()

    def talk() -> None:
        while not talk_stop.is_set():
            words.publish(String(data="w"))
            time.sleep(0.02)

    talker = threading.Thread(target=talk, daemon=True)
    talker.start()
    try:
        assert record(["-o", str(tmp_path / "b"), "--topics", "/words", "--services",
                       "switch", "--duration", "0.4"], context=ctx) == 0
    finally:
        stop.set()
        talk_stop.set()
        caller.join(timeout=5)
        talker.join(timeout=5)
        executor.shutdown()
        spinner.join(timeout=5)
    bag = tmp_path / "b"
    recorded = {t.name: t.message_count for t in bag_info(bag).topics}
    assert set(recorded) == {"/words", "/switch/_service_event"}

    other = Context()
    other.init(transport="inprocess")
    try:
        from posekit.msgs.cdr import get_typestore

        listener = Node("listener", context=other)
        got: dict[str, int] = {"/words": 0, "/switch/_service_event": 0}
        listener.create_subscription(String, "/words", lambda m: got.__setitem__(
            "/words", got["/words"] + 1), 100)
        listener.create_subscription(
            get_typestore().types["std_srvs/srv/SetBool_Event"], "/switch/_service_event",
            lambda m: got.__setitem__("/switch/_service_event",
                                      got["/switch/_service_event"] + 1), 100)
        assert play([str(bag), "--topics", "/words", "--rate", "20", "--no-clock",
                     "--progress-bar", "0", "--disable-keyboard-controls"], context=other) == 0
        listen = SingleThreadedExecutor(context=other)
        listen.add_node(listener)
        listen.spin_some(0.2)
        assert got == recorded  # both kinds played

        got.update({"/words": 0, "/switch/_service_event": 0})
        assert play([str(bag), "--exclude-services", "switch", "--rate", "20", "--no-clock",
                     "--progress-bar", "0", "--disable-keyboard-controls"], context=other) == 0
        listen.spin_some(0.2)
        assert got == {"/words": recorded["/words"], "/switch/_service_event": 0}

        seen: list[bool] = []

        def serve(request: Any, response: Any) -> Any:
            seen.append(bool(request.data))
            return response

        replier = Node("replier", context=other)
        replier.create_service(SetBool, "switch", serve, qos_profile=QoSProfile(depth=1000))
        listen.add_node(replier)
        spin = threading.Thread(target=listen.spin, daemon=True)
        spin.start()
        requests = recorded["/switch/_service_event"] // 2  # REQUEST_RECEIVED of each call
        assert play([str(bag), "--services", "switch", "--exclude-topics", "/words",
                     "--publish-service-requests", "--rate", "20", "--no-clock",
                     "--progress-bar", "0", "--disable-keyboard-controls"],
                    context=other) == 0
        deadline = time.monotonic() + 5.0
        while len(seen) < requests and time.monotonic() < deadline:
            time.sleep(0.01)
        assert seen == [True] * requests, (len(seen), requests)
        listen.shutdown()
        spin.join(timeout=5)
    finally:
        other.try_shutdown()
