// LaserScan (RViz2's LaserScan display): each beam's return as a point in the scan's frame,
// coloured by intensity, range or a flat colour; with a decay time, past scans stay where
// they were taken (their frame's pose in the fixed frame when they arrived) until they are
// older than the decay time (message stamps), as RViz2 keeps them.
// Beams with a non-finite range or one outside [range_min, range_max] are not drawn (REP 117).
import { POINT_OPTIONS, disposePoints, flatColors, makePoints, scalarColors } from "./_points.js";

const stamp = (h) => (h && h.stamp ? (h.stamp.sec || 0) + (h.stamp.nanosec || 0) * 1e-9 : 0);

// Points (x, y, z) and per-point values of a scan: {positions, ranges, intensities, n}.
export function scanPoints(msg) {
  const ranges = msg.ranges || [];
  const inten = msg.intensities || [];
  const count = ranges.length;
  const positions = new Float32Array(3 * count);
  const r = new Float32Array(count), it = new Float32Array(count);
  let n = 0;
  for (let i = 0; i < count; i += 1) {
    const d = ranges[i];
    if (!(typeof d === "number" && Number.isFinite(d)) || d < msg.range_min || d > msg.range_max) continue;
    const a = msg.angle_min + i * msg.angle_increment;
    positions[3 * n] = d * Math.cos(a);
    positions[3 * n + 1] = d * Math.sin(a);
    positions[3 * n + 2] = 0;
    r[n] = d;
    it[n] = i < inten.length && Number.isFinite(inten[i]) ? inten[i] : 0;
    n += 1;
  }
  return { positions: positions.subarray(0, 3 * n), ranges: r.subarray(0, n), intensities: it.subarray(0, n), n };
}

export default {
  name: "LaserScan",
  types: ["sensor_msgs/msg/LaserScan"],
  queue: 10,
  options: {
    color_transformer: { type: "enum", choices: ["Intensity", "Range", "FlatColor"], default: "Intensity", label: "Color Transformer" },
    decay_time: { type: "number", default: 0, min: 0, max: 600, step: 0.1, label: "Decay Time (s)" },
    ...POINT_OPTIONS,
  },
  create(ctx, topic, options) {
    const { THREE } = ctx;
    let o = options;
    const kept = [];           // {points, t, frame, scan}
    const colorsOf = (scan) => {
      if (o.color_transformer === "FlatColor") return flatColors(o.color, scan.n);
      const values = o.color_transformer === "Range" ? scan.ranges : scan.intensities;
      return scalarColors(values, scan.n, o).colors;
    };
    const build = (scan) => makePoints(THREE, scan.positions, colorsOf(scan), o);
    const drop = (entry) => { ctx.detach(entry.points); disposePoints(entry.points); };
    return {
      update(msg) {
        const frame = (msg.header && msg.header.frame_id) || "";
        const scan = scanPoints(msg);
        const t = stamp(msg.header);
        const points = build(scan);
        ctx.root.add(points);
        if (o.decay_time > 0) {
          const m = ctx.lookup(frame);      // frozen where the scan was taken
          if (!m) { disposePoints(points); ctx.setStatus("warn", `no transform from [${frame}]`); return; }
          points.matrix.copy(m);
        } else {
          ctx.attach(points, frame);        // follows its frame
        }
        kept.push({ points, t, frame, scan });
        const keepAfter = o.decay_time > 0 ? t - o.decay_time : Infinity;
        while (kept.length > 1 && (kept[0].t <= keepAfter || o.decay_time <= 0)) drop(kept.shift());
        ctx.setStatus(ctx.lookup(frame) ? "ok" : "warn",
          ctx.lookup(frame) ? `${scan.n} points` : `no transform from [${frame}]`);
      },
      setOptions(next) {
        o = next;
        for (const entry of kept) {
          const fresh = build(entry.scan);
          fresh.matrix.copy(entry.points.matrix);
          ctx.root.add(fresh);
          if (o.decay_time <= 0) ctx.attach(fresh, entry.frame);
          drop(entry);
          entry.points = fresh;
        }
        while (o.decay_time <= 0 && kept.length > 1) drop(kept.shift());
      },
      dispose() { while (kept.length) drop(kept.shift()); },
      info() {
        const last = kept[kept.length - 1];
        return last ? { frame: last.frame, points: last.scan.n, scans: kept.length } : null;
      },
    };
  },
};
