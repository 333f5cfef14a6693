import os
import tempfile

from rclpy.parameter import parameter_dict_from_yaml_file, parameter_value_to_python

# rclpy's parameter_dict_from_yaml_file on files written here: selection of node sections,
# the /** wildcard, merging, nested names, the namespace prefix and how each value is typed.
FILES = {
    "one node": """
talker:
  ros__parameters:
    rate: 10
    gain: 0.5
    name: "robot"
    quoted_int: '1'
    flag: yes
    on_word: on
    hex: 0x10
    octal: 010
    exp_no_dot: 1e3
    exp_dot: 1.0e3
    empty:
    tilde: ~
    ints: [1, 2, 3]
    floats: [1.5, 2.5]
    mixed_numbers: [1, 2.5]
    strings: [a, b]
    bools: [true, false]
    mixed: [1, a]
    empty_list: []
    pid:
      kp: 1.0
      limits: {low: -1, high: 1}
""",
    "wildcard and node": """
/**:
  ros__parameters:
    use_sim_time: true
    shared: from wildcard
    pid: {kp: 1.0, ki: 0.1}
listener:
  ros__parameters:
    shared: from node
    pid: {kd: 0.5}
""",
    "namespaced keys": """
/robot/talker:
  ros__parameters:
    rate: 5
robot:
  talker:
    ros__parameters:
      rate: 7
""",
    "no parameters": """
talker:
  rate: 10
""",
    "not a mapping": """
- a
- b
""",
}


def write(text):
    handle, path = tempfile.mkstemp(suffix=".yaml")
    with os.fdopen(handle, "w") as f:
        f.write(text)
    return path


def summary(params):
    return sorted(
        (name, msg.name, msg.value.type, plain(parameter_value_to_python(msg.value)))
        for name, msg in params.items()
    )


PATHS = {label: write(text) for label, text in FILES.items()}
try:
    show("one node", lambda: summary(parameter_dict_from_yaml_file(PATHS["one node"])))
    show("one node, namespace", lambda: summary(parameter_dict_from_yaml_file(
        PATHS["one node"], target_nodes=["talker"], namespace="ns.")))
    show("target missing", lambda: parameter_dict_from_yaml_file(
        PATHS["one node"], target_nodes=["listener"]))
    show("wildcard only", lambda: summary(parameter_dict_from_yaml_file(
        PATHS["wildcard and node"], use_wildcard=True, target_nodes=[])))
    show("wildcard then node", lambda: summary(parameter_dict_from_yaml_file(
        PATHS["wildcard and node"], use_wildcard=True, target_nodes=["listener"])))
    show("node without wildcard", lambda: summary(parameter_dict_from_yaml_file(
        PATHS["wildcard and node"], target_nodes=["listener"])))
    show("all nodes skip wildcard", lambda: summary(parameter_dict_from_yaml_file(
        PATHS["wildcard and node"])))
    show("literal namespaced key", lambda: summary(parameter_dict_from_yaml_file(
        PATHS["namespaced keys"], target_nodes=["/robot/talker"])))
    show("nested namespace key", lambda: parameter_dict_from_yaml_file(
        PATHS["namespaced keys"], target_nodes=["robot"]))
    show("no ros__parameters", lambda: parameter_dict_from_yaml_file(PATHS["no parameters"]))
    kind("not a mapping", lambda: parameter_dict_from_yaml_file(PATHS["not a mapping"]))
    kind("missing file", lambda: parameter_dict_from_yaml_file("/nonexistent/params.yaml"))
finally:
    for path in PATHS.values():
        os.unlink(path)
