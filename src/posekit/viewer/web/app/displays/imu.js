// Imu (the rviz_imu_plugin display the lecture's RViz2 uses): at the message frame's origin,
// axes showing the message's orientation (relative to the fixed frame, or composed with the
// frame's own orientation when "Fixed Frame Orientation" is off) and an arrow for the linear
// acceleration (a vector in the message frame, "Acceleration Scale" metres per m/s^2).
import { disposeTree, makeArrow, makeAxes, material } from "./_util.js";

const finite = (...v) => v.every((x) => typeof x === "number" && Number.isFinite(x));

export default {
  name: "Imu",
  types: ["sensor_msgs/msg/Imu"],
  options: {
    show_axes: { type: "bool", default: true, label: "Enable Axes" },
    axes_length: { type: "number", default: 0.5, min: 0.001, max: 100, step: 0.05, label: "Axes Length" },
    axes_radius: { type: "number", default: 0.02, min: 0.0001, max: 10, step: 0.005, label: "Axes Radius" },
    fixed_frame_orientation: { type: "bool", default: true, label: "Fixed Frame Orientation" },
    show_acceleration: { type: "bool", default: true, label: "Enable Acceleration" },
    acc_scale: { type: "number", default: 0.1, min: 0.0001, max: 100, step: 0.05, label: "Acceleration Scale" },
    acc_color: { type: "color", default: "#ffff00", label: "Acceleration Color" },
    alpha: { type: "number", default: 1, min: 0, max: 1, step: 0.1, label: "Alpha" },
  },
  create(ctx, topic, options) {
    const { THREE } = ctx;
    const group = new THREE.Group();        // at the frame's origin, fixed-frame axes
    group.matrixAutoUpdate = false;
    ctx.root.add(group);
    let o = options, last = null, axes = null, arrow = null;
    const rebuild = () => {
      disposeTree(group);
      axes = makeAxes(THREE, o.axes_length, o.axes_radius, o.alpha);
      arrow = makeArrow(THREE, { shaftLength: 0.8, shaftRadius: 0.03, headLength: 0.2, headRadius: 0.07 },
        material(THREE, o.acc_color, o.alpha));
      group.add(axes, arrow);
    };
    const place = () => {
      if (!last) { group.visible = false; return; }
      const frame = (last.header && last.header.frame_id) || "";
      const m = ctx.lookup(frame);
      if (!m) { group.visible = false; ctx.setStatus("warn", `no transform from [${frame}]`); return; }
      const pos = new THREE.Vector3(), frameQ = new THREE.Quaternion(), scale = new THREE.Vector3();
      m.decompose(pos, frameQ, scale);
      group.matrix.makeTranslation(pos.x, pos.y, pos.z);
      group.matrixWorldNeedsUpdate = true;
      group.visible = true;
      const q = last.orientation || {};
      axes.visible = o.show_axes && finite(q.x, q.y, q.z, q.w) && (q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w) > 1e-12;
      if (axes.visible) {
        const mq = new THREE.Quaternion(q.x, q.y, q.z, q.w).normalize();
        axes.quaternion.copy(o.fixed_frame_orientation ? mq : frameQ.clone().multiply(mq));
      }
      const a = last.linear_acceleration || {};
      const acc = finite(a.x, a.y, a.z) ? new THREE.Vector3(a.x, a.y, a.z).applyQuaternion(frameQ) : null;
      const len = acc ? acc.length() * o.acc_scale : 0;
      arrow.visible = o.show_acceleration && len > 1e-9;
      if (arrow.visible) {
        arrow.quaternion.setFromUnitVectors(new THREE.Vector3(1, 0, 0), acc.clone().normalize());
        arrow.scale.set(len, len, len);
      }
      ctx.setStatus("ok", acc ? `|a| = ${acc.length().toFixed(3)} m/s²` : "no acceleration");
    };
    rebuild();
    ctx.onFrames(place);
    return {
      update(msg) { last = msg; place(); },
      setOptions(next) { o = next; rebuild(); place(); },
      dispose() { disposeTree(group); },
      info() {
        if (!last) return null;
        const q = last.orientation || {};
        return { frame: (last.header && last.header.frame_id) || "", orientation: [q.x, q.y, q.z, q.w],
                 axes: Boolean(axes && axes.visible), acceleration: Boolean(arrow && arrow.visible) };
      },
    };
  },
};
