"""Prints, one JSON line per case, what rclpy makes of command-line ROS arguments.

Run by tests/runtime/test_arguments.py twice (tests/_support/differential.py): under the real
ROS 2 Jazzy rclpy and under posekit.rclpy; the test compares the two outputs.
"""

import json
import os
import sys
import tempfile

from rclpy.logging import get_logger
from rclpy.node import Node
from rclpy.utilities import remove_ros_args

import rclpy


def val(v):
    if isinstance(v, (list, tuple)) or type(v).__name__ in ("array", "ndarray"):
        return [val(x) for x in v]
    if isinstance(v, float) and v != v:
        return "nan"
    if isinstance(v, float) and v in (float("inf"), float("-inf")):
        return str(v)
    return v


def node_view(node):
    ps = {}
    for name, p in sorted(node.get_parameters_by_prefix("").items()):
        ps[name] = [p.type_.name, val(p.value)]
    return {
        "name": node.get_name(),
        "ns": node.get_namespace(),
        "params": ps,
        "chatter": node.resolve_topic_name("chatter"),
        "srv": node.resolve_service_name("chatter"),
        "abs": node.resolve_topic_name("/abs/topic"),
        "priv": node.resolve_topic_name("~/priv"),
    }


def run(case, argv, node_name="talker", namespace=None, cli_args=None, loggers=()):
    out = {"case": case}
    old = sys.argv
    sys.argv = list(argv)
    try:
        try:
            rclpy.init(args=None)
        except Exception as exc:
            out["init_error"] = type(exc).__name__
            out["init_msg"] = str(exc)
            print(json.dumps(out), flush=True)
            return
        try:
            kw = {"automatically_declare_parameters_from_overrides": True}
            if namespace is not None:
                kw["namespace"] = namespace
            if cli_args is not None:
                kw["cli_args"] = cli_args
            node = Node(node_name, **kw)
            out.update(node_view(node))
            node.destroy_node()
        except Exception as exc:
            out["node_error"] = type(exc).__name__
            out["node_msg"] = str(exc)
        for lg in loggers:
            out["level:" + lg] = int(get_logger(lg).get_effective_level())
    finally:
        sys.argv = old
        rclpy.try_shutdown()
    print(json.dumps(out), flush=True)


P = ["prog", "--ros-args", "-p"]
values = [
    "7",
    "-3",
    "+4",
    "0x10",
    "010",
    "1e3",
    "1.5e-3",
    ".5",
    "5.",
    "7.0",
    "true",
    "True",
    "TRUE",
    "yes",
    "Y",
    "y",
    "on",
    "off",
    "no",
    "n",
    "N",
    "false",
    "hello",
    "'7'",
    '"true"',
    "[1, 2]",
    "[1.0, 2.5]",
    "[a, b]",
    "[true, false]",
    "nan",
    ".inf",
    "-.inf",
    ".nan",
    "1_000",
    "~",
    "null",
    "",
    "hello world",
    "a:b",
    "{a: 1}",
    "[1, a]",
    "[1, 2.0]",
    "0",
    "-0.0",
    "1e400",
    "99999999999999999999",
    "'x'",
]
for i, v in enumerate(values):
    run(f"p{i}:{v}", [*P, f"x:={v}"])
run("argv-goal", ["my_node.py", "--ros-args", "-p", "goal_x:=7.0"])
run("long-param", ["prog", "--ros-args", "--param", "a:=1", "--param", "a:=2"])
run("nested-name", ["prog", "--ros-args", "-p", "a.b.c:=1", "-p", "use_sim_time:=true"])
run("node-param", ["prog", "--ros-args", "-p", "talker:x:=1", "-p", "other:y:=2"])
run("remap-topic", ["prog", "--ros-args", "-r", "chatter:=/foo"])
run("remap-rel", ["prog", "--ros-args", "-r", "chatter:=bar"], namespace="/ns0")
run("remap-abs-lhs", ["prog", "--ros-args", "-r", "/chatter:=baz"])
run("remap-node", ["prog", "--ros-args", "-r", "__node:=renamed"])
run("remap-name", ["prog", "--ros-args", "-r", "__name:=renamed"])
run("remap-ns", ["prog", "--ros-args", "-r", "__ns:=/ns1"])
run("remap-ns-chatter", ["prog", "--ros-args", "-r", "__ns:=/ns1", "-r", "chatter:=c2"])
run(
    "remap-nodespec",
    ["prog", "--ros-args", "-r", "talker:chatter:=bar", "-r", "other:chatter:=baz"],
)
run("remap-nodespec-other", ["prog", "--ros-args", "-r", "other:chatter:=baz"])
run(
    "remap-nodespec-node",
    ["prog", "--ros-args", "-r", "talker:__node:=x", "-r", "other:__node:=y"],
)
run("remap-first-wins", ["prog", "--ros-args", "-r", "chatter:=a", "-r", "chatter:=b"])
run("remap-two-node", ["prog", "--ros-args", "-r", "__node:=a", "-r", "__node:=b"])
run("remap-priv", ["prog", "--ros-args", "-r", "~/priv:=pub"])
run("remap-to-priv", ["prog", "--ros-args", "-r", "chatter:=~/mine"])
run("remap-after-rename", ["prog", "--ros-args", "-r", "__node:=x", "-r", "x:chatter:=q"])
run("remap-ns-rel", ["prog", "--ros-args", "-r", "__ns:=rel"])
# rcl remaps the namespace with rules for the node's new name, not its old one
run("remap-ns-after-rename", ["prog", "--ros-args", "-r", "__node:=n2", "-r", "n2:__ns:=/foo"])
run("remap-ns-old-name-after-rename",
    ["prog", "--ros-args", "-r", "__node:=n2", "-r", "talker:__ns:=/foo", "-r", "__ns:=/ns1"])
run("remap-ns-new-name-before-rename",
    ["prog", "--ros-args", "-r", "n2:__ns:=/foo", "-r", "__ns:=/ns1", "-r", "__node:=n2"])
run("remap-ns-after-rename-local", ["prog", "--ros-args", "-r", "n2:__ns:=/foo"],
    cli_args=["--ros-args", "-r", "__node:=n2", "-r", "__ns:=/ns1"])
run("remap-bad-node", ["prog", "--ros-args", "-r", "__node:=1bad"])
run("remap-bad-topic", ["prog", "--ros-args", "-r", "chatter:=bad name"])
run("remap-rostopic", ["prog", "--ros-args", "-r", "rostopic://chatter:=x"])
run("node-param-ns", ["prog", "--ros-args", "-p", "talker:x:=1", "-p", "other:w:=4"],
    namespace="/ns0")
run("node-param-slash", ["prog", "--ros-args", "-p", "/ns0/talker:y:=2"])
run("node-param-wildcard", ["prog", "--ros-args", "-p", "*:z:=3"])
run("remap-rosservice", ["prog", "--ros-args", "-r", "rosservice://chatter:=svc"])
run("remap-node-rostopic", ["prog", "--ros-args", "-r", "talker:rostopic://chatter:=t"])
run("enclave", ["prog", "--ros-args", "-e", "/foo", "--enclave", "/bar"])
run(
    "misc-flags",
    [
        "prog",
        "--ros-args",
        "--disable-rosout-logs",
        "--enable-stdout-logs",
        "--disable-external-lib-logs",
    ],
)
run("trail-p", ["prog", "--ros-args", "-p"])
run("p-noassign", ["prog", "--ros-args", "-p", "novalue"])
run("p-empty-name", ["prog", "--ros-args", "-p", ":=1"])
run("trail-r", ["prog", "--ros-args", "-r"])
run("r-noassign", ["prog", "--ros-args", "-r", "abc"])
run("unknown", ["prog", "--ros-args", "--bogus", "-p", "a:=1"])
run("unknown2", ["prog", "--ros-args", "extra"])
run("after-end", ["prog", "--ros-args", "-p", "a:=1", "--", "-p", "b:=2"])
run(
    "two-sections",
    ["prog", "x", "--ros-args", "-p", "a:=1", "--", "y", "--ros-args", "-p", "b:=2"],
)
run("no-section", ["prog", "-p", "a:=1"])
run("params-missing", ["prog", "--ros-args", "--params-file", "/nonexistent/params.yaml"])
run("trail-params", ["prog", "--ros-args", "--params-file"])
d = tempfile.mkdtemp()
print(json.dumps({"case": "tmpdir", "dir": d}), flush=True)


def yfile(name, text):
    p = os.path.join(d, name)
    with open(p, "w") as f:
        f.write(text)
    return p


f1 = yfile(
    "a.yaml",
    """
/**:
  ros__parameters:
    all_x: 1
    shared: from_all
talker:
  ros__parameters:
    shared: from_talker
    goal:
      x: 2.5
      y: [1, 2]
      names: [a, 'b']
    flag: yes
    q: "3"
other:
  ros__parameters:
    other_only: 3
""",
)
run("pfile", ["prog", "--ros-args", "--params-file", f1])
run("pfile-then-p", ["prog", "--ros-args", "--params-file", f1, "-p", "shared:=cli"])
run("p-then-pfile", ["prog", "--ros-args", "-p", "shared:=cli", "--params-file", f1])
f2 = yfile(
    "b.yaml",
    """
/ns1/talker:
  ros__parameters:
    a: 1
/ns1:
  talker:
    ros__parameters:
      b: 2
/*/talker:
  ros__parameters:
    c: 3
/**/talker:
  ros__parameters:
    d: 4
/ns1/*:
  ros__parameters:
    e: 5
/ns2/talker:
  ros__parameters:
    f: 6
""",
)
run("pfile-ns", ["prog", "--ros-args", "--params-file", f2], namespace="/ns1")
run("pfile-ns-root", ["prog", "--ros-args", "--params-file", f2])
f3 = yfile(
    "c.yaml",
    """
talker:
  ros__parameters:
    bad: [1, a]
""",
)
run("pfile-mixed", ["prog", "--ros-args", "--params-file", f3])
f4 = yfile(
    "d.yaml",
    """
talker:
  not_params:
    a: 1
""",
)
run("pfile-noros", ["prog", "--ros-args", "--params-file", f4])
f5 = yfile("e.yaml", "talker: [unbalanced\n")
run("pfile-badyaml", ["prog", "--ros-args", "--params-file", f5])
f6 = yfile(
    "f.yaml",
    """
talker:
  ros__parameters:
    use_sim_time: true
    rate: 10
    ratef: 10.0
    s: hi
""",
)
run("pfile-simtime", ["prog", "--ros-args", "--params-file", f6])
run("cli-args", ["prog"], cli_args=["--ros-args", "-p", "a:=1", "-r", "chatter:=c"])
run(
    "cli-args-global",
    ["prog", "--ros-args", "-p", "a:=1", "-p", "b:=g"],
    cli_args=["--ros-args", "-p", "b:=local"],
)
run(
    "cli-args-remap-order",
    ["prog", "--ros-args", "-r", "chatter:=global"],
    cli_args=["--ros-args", "-r", "chatter:=local"],
)
run("cli-args-bad", ["prog"], cli_args=["--ros-args", "--bogus"])
run("cli-args-nonros", ["prog"], cli_args=["hello", "--ros-args", "-p", "a:=1"])
for i, argv in enumerate(
    [
        ["prog", "a", "--ros-args", "-p", "x:=1", "--", "b"],
        ["prog", "--ros-args", "-r", "a:=b", "--ros-args", "-p", "c:=1", "--", "d"],
        ["prog", "--", "x"],
        ["prog", "--ros-args"],
        ["prog", "--ros-args", "--", "--", "z"],
        ["prog", "--ros-args", "-p", "x:=1", "tail"],
        ["prog", "--ros-args", "--bogus"],
        [],
    ]
):
    try:
        print(json.dumps({"case": f"remove{i}", "out": remove_ros_args(args=argv)}), flush=True)
    except Exception as exc:
        print(
            json.dumps({"case": f"remove{i}", "error": type(exc).__name__, "msg": str(exc)}),
            flush=True,
        )
old = sys.argv
sys.argv = ["prog", "q", "--ros-args", "-p", "x:=1"]
print(json.dumps({"case": "remove-sysargv", "out": remove_ros_args()}), flush=True)
sys.argv = old

run(
    "loglevel",
    ["prog", "--ros-args", "--log-level", "debug"],
    loggers=("talker", "other", "some.child"),
)
run(
    "loglevel-named",
    ["prog", "--ros-args", "--log-level", "talker:=warn", "--log-level", "other:=ERROR"],
    loggers=("talker", "other", "x"),
)
run("loglevel-bad", ["prog", "--ros-args", "--log-level", "verbose"])
