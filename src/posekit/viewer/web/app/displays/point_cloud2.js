// PointCloud2 (RViz2's PointCloud2 display): the cloud's points in its header frame as squares
// of "Size (m)", coloured by their own rgb (RGB8), their intensity, one coordinate in the
// fixed frame (AxisColor) or a flat colour; "Auto" picks RGB8, then Intensity, then AxisColor
// as RViz2 prefers the cloud's own channels. The server sends clouds compact
// (posekit.viewer.cloud_feed): finite points only, float32, thinned to at most 100k points.
import { POINT_OPTIONS, disposePoints, flatColors, makePoints, scalarColors } from "./_points.js";

export default {
  name: "PointCloud2",
  types: ["sensor_msgs/msg/PointCloud2"],
  options: {
    color_transformer: { type: "enum", choices: ["Auto", "RGB8", "Intensity", "AxisColor", "FlatColor"], default: "Auto", label: "Color Transformer" },
    axis: { type: "enum", choices: ["X", "Y", "Z"], default: "Z", label: "Axis" },
    ...POINT_OPTIONS,
    size: { ...POINT_OPTIONS.size, default: 0.01 },
  },
  create(ctx, topic, options) {
    const { THREE } = ctx;
    let o = options, last = null, points = null, shown = null;
    const transformerOf = (msg) => {
      if (o.color_transformer !== "Auto") return o.color_transformer;
      if (msg.rgb && msg.rgb.length) return "RGB8";
      if (msg.intensity && msg.intensity.length) return "Intensity";
      return "AxisColor";
    };
    const draw = () => {
      if (points) { ctx.detach(points); disposePoints(points); points = null; }
      if (!last) return;
      const msg = last;
      const frame = (msg.header && msg.header.frame_id) || "";
      const positions = Float32Array.from(msg.points || []);
      const n = positions.length / 3;
      const kind = transformerOf(msg);
      let colors;
      if (kind === "RGB8" && msg.rgb && msg.rgb.length === 3 * n) {
        colors = new Float32Array(3 * n);
        for (let i = 0; i < 3 * n; i += 1) colors[i] = msg.rgb[i] / 255;
      } else if (kind === "Intensity" && msg.intensity && msg.intensity.length === n) {
        colors = scalarColors(msg.intensity, n, o).colors;
      } else if (kind === "AxisColor") {
        const m = ctx.lookup(frame) || new THREE.Matrix4();
        const k = { X: 0, Y: 1, Z: 2 }[o.axis];
        const e = m.elements;  // column-major: row k of the rotation, then translation
        const values = new Float32Array(n);
        for (let i = 0; i < n; i += 1) {
          const x = positions[3 * i], y = positions[3 * i + 1], z = positions[3 * i + 2];
          values[i] = e[k] * x + e[4 + k] * y + e[8 + k] * z + e[12 + k];
        }
        colors = scalarColors(values, n, o).colors;
      } else {
        colors = flatColors(o.color, n);
      }
      points = makePoints(THREE, positions, colors, o);
      shown = { frame, points: n, total: msg.total, stride: msg.stride, transformer: kind };
      ctx.root.add(points);
      const placed = ctx.attach(points, frame);
      ctx.setStatus(placed ? "ok" : "warn", placed
        ? `${n} of ${msg.total} points (every ${msg.stride}${msg.stride > 1 ? "th row and column" : ""})`
        : `no transform from [${frame}]`);
    };
    return {
      update(msg) {
        if (!msg || msg.points === undefined) throw new Error("the server sent the cloud uncompacted");
        last = msg;
        draw();
      },
      setOptions(next) { o = next; draw(); },
      dispose() { if (points) { ctx.detach(points); disposePoints(points); } },
      info() { return shown; },
    };
  },
};
