// Axes (RViz2's Axes display): red, green and blue cylinders along x, y and z of a chosen TF
// frame ("Reference Frame", empty: the fixed frame), "Length" and "Radius" in metres.
import { disposeTree, makeAxes } from "./_util.js";

export default {
  name: "Axes",
  types: ["tf2_msgs/msg/TFMessage"],
  messages: false,
  options: {
    reference_frame: { type: "string", default: "base_link", label: "Reference Frame" },
    length: { type: "number", default: 1, min: 0.0001, max: 1000, step: 0.1, label: "Length" },
    radius: { type: "number", default: 0.1, min: 0.0001, max: 100, step: 0.01, label: "Radius" },
    alpha: { type: "number", default: 1, min: 0, max: 1, step: 0.1, label: "Alpha" },
  },
  create(ctx, topic, options) {
    const { THREE } = ctx;
    const group = new THREE.Group();
    ctx.root.add(group);
    let o = options;
    const frameOf = () => o.reference_frame || ctx.fixedFrame();
    const build = () => {
      disposeTree(group);
      group.add(makeAxes(THREE, o.length, o.radius, o.alpha));
      const placed = ctx.attach(group, frameOf());
      ctx.setStatus(placed ? "ok" : "warn", placed ? `at [${frameOf()}]` : `no frame [${frameOf()}]`);
    };
    build();
    ctx.onFrames(() => {
      const known = Boolean(ctx.lookup(frameOf()));
      ctx.setStatus(known ? "ok" : "warn", known ? `at [${frameOf()}]` : `no frame [${frameOf()}]`);
    });
    return {
      update() {},
      setOptions(next) { o = next; build(); },
      dispose() { ctx.detach(group); disposeTree(group); },
      info() { return { frame: frameOf(), placed: Boolean(ctx.lookup(frameOf())) }; },
    };
  },
};
