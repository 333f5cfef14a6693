// TF (RViz2's TF display): the page's own frame axes, names and links (scene3d.js, with the
// TF tree panel's per-frame boxes); this display switches them on and sets their options.
export default {
  name: "TF",
  types: ["tf2_msgs/msg/TFMessage"],
  messages: false,
  needs3d: false,
  options: {
    show_names: { type: "bool", default: true, label: "Show Names" },
    marker_scale: { type: "number", default: 1, min: 0.1, max: 10, step: 0.1, label: "Marker Scale" },
  },
  create(ctx, topic, options) {
    const apply = (o, visible = true) => ctx.builtin.tf({ visible, names: o.show_names, scale: o.marker_scale });
    apply(options);
    let o = options;
    return {
      update() {},
      setOptions(next) { o = next; apply(o); },
      setEnabled(on) { apply(o, on); },
      dispose() { ctx.builtin.tf({ visible: false }); },
    };
  },
};
