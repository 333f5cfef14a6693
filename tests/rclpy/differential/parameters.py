import os
import tempfile

from rcl_interfaces.msg import (
    FloatingPointRange,
    IntegerRange,
    ParameterDescriptor,
    ParameterValue,
    SetParametersResult,
)
from rclpy.parameter import Parameter, get_parameter_value, parameter_value_to_python

import rclpy

rclpy.init()
node = rclpy.create_node("diff_params", parameter_overrides=[
    Parameter("over_double", value=2.5), Parameter("over_str", value="from launch"),
    Parameter("over_int", value=1),
])

# -- Parameter objects and types ------------------------------------------------------
for value in [None, True, 3, 2.5, "s", [b"a"], [True, False], [1, 2], [1.5], ["a"], [],
              (1, 2)]:
    show(f"type_of {value!r}", lambda value=value: Parameter.Type.from_parameter_value(value))
show("type_of mixed", lambda: Parameter.Type.from_parameter_value([1, "a"]))
show("type_of dict", lambda: Parameter.Type.from_parameter_value({"a": 1}))
show("Parameter int as double", lambda: Parameter("x", Parameter.Type.DOUBLE, 1))
show("Parameter ok", lambda: (lambda p: (p.name, p.type_, p.value))(
    Parameter("x", Parameter.Type.DOUBLE, 1.0)))
show("Parameter not-a-type", lambda: Parameter("x", 3, 1.0).type_)
show("str(Type)", lambda: str(Parameter.Type.INTEGER_ARRAY))
show("Type value", lambda: Parameter.Type.STRING.value)
show("to msg", lambda: (lambda m: (m.name, m.value.type, m.value.integer_value))(
    Parameter("i", value=7).to_parameter_msg()))
for text in ["1", "1.0", "true", "yes", "abc", "[1, 2]", "[1.0, 2]", "['a', 'b']", "[]",
             "'3'", "", "[1, a]", "1e3", ".5"]:
    show(f"from string {text!r}", lambda text=text: (lambda v: (v.type, plain(
        parameter_value_to_python(v))))(get_parameter_value(text)))

show("from string mapping", lambda: (lambda v: (v.type, plain(
    parameter_value_to_python(v))))(get_parameter_value("{a: 1}")))

# -- declare ---------------------------------------------------------------------------
show("declare double", lambda: (lambda p: (p.type_, p.value))(
    node.declare_parameter("k_rho", 0.4)))
show("declare again", lambda: node.declare_parameter("k_rho", 0.5))
show("declare int", lambda: node.declare_parameter("count", 3).value)
show("declare override double", lambda: node.declare_parameter("over_double", 1.0).value)
show("declare int override of a double", lambda: node.declare_parameter("over_int", 0.5).value)
if node.has_parameter("over_int"):  # only where the line above differs: keep the rest equal
    node.undeclare_parameter("over_int")
show("declare override wrong type", lambda: node.declare_parameter("over_str", 1.0))
show("declare ignore override", lambda: node.declare_parameter(
    "over_str", "x", ignore_override=True).value)
show("declare None", lambda: (lambda p: (p.type_, p.value))(
    node.declare_parameter("nothing", None)))
show("declare by type", lambda: (lambda p: (p.type_, p.value))(
    node.declare_parameter("typed", Parameter.Type.INTEGER)))
show("get uninitialized", lambda: node.get_parameter("typed"))
show("get_or uninitialized", lambda: node.get_parameter_or("typed").type_)
show("declare NOT_SET type", lambda: node.declare_parameter("ns", Parameter.Type.NOT_SET))
show("declare empty name", lambda: node.declare_parameter("", 1))
class Opaque:
    def __repr__(self):
        return "Opaque()"


show("declare object", lambda: node.declare_parameter("obj", Opaque()))
show("declare list", lambda: plain(node.declare_parameter("gains", [1.0, 2.0]).value))
show("declare dynamic", lambda: node.declare_parameter(
    "dyn", 1, ParameterDescriptor(dynamic_typing=True)).value)
show("declare read only", lambda: node.declare_parameter(
    "ro", "fixed", ParameterDescriptor(read_only=True)).value)
show("declare out of range", lambda: node.declare_parameter(
    "ranged_bad", 5, ParameterDescriptor(integer_range=[IntegerRange(
        from_value=0, to_value=4, step=1)])))
show("declare ranged", lambda: node.declare_parameter(
    "ranged", 2, ParameterDescriptor(integer_range=[IntegerRange(
        from_value=0, to_value=10, step=2)])).value)
show("declare fp ranged", lambda: node.declare_parameter(
    "fp", 0.5, ParameterDescriptor(floating_point_range=[FloatingPointRange(
        from_value=0.0, to_value=1.0, step=0.25)])).value)
show("declare_parameters", lambda: [(p.name, p.value) for p in node.declare_parameters(
    "wheels", [("count", 4), ("radius", 0.05), ("name", "w", ParameterDescriptor())])])
show("declare_parameters bad tuple", lambda: node.declare_parameters("x", [("a", 1, 2, 3)]))
show("declare_parameters bad descriptor", lambda: node.declare_parameters("x", [("a", 1, 2)]))

# -- get / set ---------------------------------------------------------------------------
show("get undeclared", lambda: node.get_parameter("nope"))
show("get_or undeclared", lambda: (lambda p: (p.name, p.type_, p.value))(
    node.get_parameter_or("nope")))
show("has", lambda: (node.has_parameter("k_rho"), node.has_parameter("nope")))
show("get_parameters", lambda: [p.value for p in node.get_parameters(["k_rho", "count"])])
show("get_parameters bad", lambda: node.get_parameters([1]))


def results(params):
    return [(r.successful, r.reason) for r in node.set_parameters(params)]


show("set ok", lambda: results([Parameter("k_rho", value=1.0)]))
show("set int on double", lambda: results([Parameter("k_rho", value=1)]))
show("set str on int", lambda: results([Parameter("count", value="x")]))
show("set None on static", lambda: results([Parameter("count", value=None)]))
show("set read only", lambda: results([Parameter("ro", value="other")]))
show("set undeclared", lambda: results([Parameter("nope", value=1)]))
show("set dynamic retype", lambda: (results([Parameter("dyn", value="now a string")]),
                                    node.get_parameter("dyn").type_))
show("set range low", lambda: results([Parameter("ranged", value=-1)]))
show("set range step", lambda: results([Parameter("ranged", value=3)]))
show("set range edge", lambda: results([Parameter("ranged", value=10)]))
show("set fp step", lambda: results([Parameter("fp", value=0.3)]))
show("set fp high", lambda: results([Parameter("fp", value=1.5)]))
show("set fp ok", lambda: results([Parameter("fp", value=0.75)]))
show("set typed value", lambda: (results([Parameter("typed", value=5)]),
                                 node.get_parameter("typed").value))
show("set typed wrong", lambda: results([Parameter("typed", value=5.0)]))
show("set many", lambda: results([Parameter("k_rho", value=2.0), Parameter("count", value=1.5),
                                  Parameter("count", value=9)]))
show("values after", lambda: (node.get_parameter("k_rho").value,
                              node.get_parameter("count").value))
show("atomically bad", lambda: (lambda r: (r.successful, r.reason))(
    node.set_parameters_atomically([Parameter("k_rho", value=3.0),
                                    Parameter("count", value="x")])))
show("atomic kept", lambda: node.get_parameter("k_rho").value)
show("atomically undeclared", lambda: node.set_parameters_atomically(
    [Parameter("k_rho", value=3.0), Parameter("nope2", value=1)]))
show("set None on dynamic", lambda: (results([Parameter("dyn", value=None)]),
                                     node.has_parameter("dyn")))
kind("set not a Parameter", lambda: node.set_parameters([1]))  # names the class's module
show("set two undeclared", lambda: node.set_parameters_atomically(
    [Parameter("nope3", value=1), Parameter("nope4", value=1)]))


def veto(params):
    for p in params:
        if p.name == "count" and p.value > 100:
            return SetParametersResult(successful=False, reason="count too large")
    return SetParametersResult(successful=True)


node.add_on_set_parameters_callback(veto)
show("veto", lambda: results([Parameter("count", value=101)]))
show("veto passes", lambda: results([Parameter("count", value=50)]))
show("declare vetoed", lambda: node.declare_parameter("count2", 1000) and None)


def post(params):
    print("post-set saw:", [(p.name, p.value) for p in params])


node.add_post_set_parameters_callback(post)
show("post", lambda: results([Parameter("count", value=51)]))
node.remove_post_set_parameters_callback(post)
node.remove_on_set_parameters_callback(veto)
show("remove twice", lambda: node.remove_on_set_parameters_callback(veto))


def bad_callback(params):
    return True


node.add_on_set_parameters_callback(bad_callback)
show("bad callback", lambda: results([Parameter("count", value=52)]))
node.remove_on_set_parameters_callback(bad_callback)


def pre(params):
    return [Parameter("k_rho", value=9.0)] if params[0].name == "count" else params


node.add_pre_set_parameters_callback(pre)
show("pre rewrites", lambda: (results([Parameter("count", value=53)]),
                              node.get_parameter("k_rho").value,
                              node.get_parameter("count").value))
node.remove_pre_set_parameters_callback(pre)

# -- set_descriptor ---------------------------------------------------------------------------
def int_range(lo, hi):
    return ParameterDescriptor(type=2, integer_range=[IntegerRange(
        from_value=lo, to_value=hi, step=1)])


show("set_descriptor keeps", lambda: (lambda v: (v.type, v.integer_value))(
    node.set_descriptor("ranged", int_range(0, 100))))
show("set_descriptor alternative", lambda: (lambda v: (v.type, v.integer_value))(
    node.set_descriptor("ranged", int_range(50, 60), ParameterValue(type=2, integer_value=55))))
show("set_descriptor neither", lambda: node.set_descriptor(
    "ranged", int_range(70, 80), ParameterValue(type=2, integer_value=1)))
show("set_descriptor untyped", lambda: node.set_descriptor("ranged", ParameterDescriptor()))
show("set_descriptor read only", lambda: node.set_descriptor("ro", ParameterDescriptor()))
show("set_descriptor undeclared", lambda: node.set_descriptor("nope", ParameterDescriptor()))
show("after set_descriptor", lambda: (node.get_parameter("ranged").value,
                                      node.describe_parameter("ranged").integer_range[0].from_value))
show("rel tol", lambda: node.PARAM_REL_TOL)

# -- describe / list / types / undeclare ---------------------------------------------------
show("describe", lambda: (lambda d: (d.name, d.type, d.read_only, d.dynamic_typing))(
    node.describe_parameter("ro")))
show("describe range", lambda: (lambda d: (d.integer_range[0].step, d.type))(
    node.describe_parameter("ranged")))
show("describe undeclared", lambda: node.describe_parameter("nope"))
show("types", lambda: node.get_parameter_types(["k_rho", "count", "gains", "ro"]))
show("type undeclared", lambda: node.get_parameter_type("nope"))
show("list all", lambda: (lambda r: (sorted(r.names), sorted(r.prefixes)))(
    node.list_parameters([], 0)))
show("list depth 1", lambda: sorted(node.list_parameters([], 1).names))
show("list prefix", lambda: sorted(node.list_parameters(["wheels"], 0).names))
show("list prefix depth", lambda: sorted(node.list_parameters(["wheels"], 1).names))
show("list bad depth", lambda: node.list_parameters([], -1))
show("list bad prefixes", lambda: node.list_parameters("wheels", 0))
show("by prefix", lambda: sorted((k, v.value) for k, v in
                                 node.get_parameters_by_prefix("wheels").items()))
show("undeclare", lambda: (node.undeclare_parameter("count"), node.has_parameter("count")))
show("undeclare again", lambda: node.undeclare_parameter("count"))
show("undeclare read only", lambda: node.undeclare_parameter("ro"))
show("use_sim_time", lambda: (lambda p: (p.type_, p.value))(node.get_parameter("use_sim_time")))
show("use_sim_time int", lambda: results([Parameter("use_sim_time", value=1)]))

# -- nodes with other options -----------------------------------------------------------
loose = rclpy.create_node("diff_loose", allow_undeclared_parameters=True)
show("undeclared allowed get", lambda: (lambda p: (p.type_, p.value))(
    loose.get_parameter("free")))
show("undeclared allowed set", lambda: [
    (r.successful, r.reason) for r in loose.set_parameters([Parameter("free", value=3)])])
show("undeclared allowed after", lambda: (loose.get_parameter("free").value,
                                          loose.describe_parameter("free").dynamic_typing))
show("undeclared allowed type", lambda: loose.get_parameter_type("other"))
auto = rclpy.create_node("diff_auto", parameter_overrides=[Parameter("a", value=1)],
                         automatically_declare_parameters_from_overrides=True)
show("auto declared", lambda: (auto.has_parameter("a"), auto.get_parameter("a").value))

# -- an override's type must be the declared type: an integer is no double ---------------
params_file = os.path.join(tempfile.mkdtemp(), "params.yaml")
with open(params_file, "w") as f:
    f.write("diff_typed:\n  ros__parameters:\n    h: 1\n    h_ok: 1.0\n")
typed = rclpy.create_node("diff_typed", parameter_overrides=[
    Parameter("fa", value=[1, 2]), Parameter("ia", value=[1.0])], cli_args=[
    "--ros-args", "-p", "g:=1", "-p", "g_ok:=1.0", "--params-file", params_file])
show("declare int array override of a double array", lambda: typed.declare_parameter(
    "fa", [0.5]))
show("declare double array override of an int array", lambda: typed.declare_parameter(
    "ia", [1]))
show("declare -p int for a double", lambda: typed.declare_parameter("g", 0.0))
show("declare -p double for a double", lambda: typed.declare_parameter("g_ok", 0.0).value)
show("declare file int for a double", lambda: typed.declare_parameter("h", 0.0))
show("declare file double for a double", lambda: typed.declare_parameter("h_ok", 0.0).value)
rclpy.shutdown()
