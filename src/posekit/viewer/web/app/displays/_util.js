// Helpers shared by the display modules (files starting with "_" are not displays).
// Units: metres, radians; poses are ROS geometry_msgs/Pose objects ({position, orientation}).

// A three.js Matrix4 for a geometry_msgs/Pose (missing or null fields count as 0, w as 1).
export function poseMatrix(THREE, pose, m = new THREE.Matrix4()) {
  const p = (pose && pose.position) || {};
  const q = (pose && pose.orientation) || {};
  const num = (v, d) => (typeof v === "number" && Number.isFinite(v) ? v : d);
  const quat = new THREE.Quaternion(num(q.x, 0), num(q.y, 0), num(q.z, 0), num(q.w, 1));
  if (quat.lengthSq() < 1e-12) quat.set(0, 0, 0, 1); else quat.normalize();
  return m.compose(new THREE.Vector3(num(p.x, 0), num(p.y, 0), num(p.z, 0)), quat, new THREE.Vector3(1, 1, 1));
}

// Whether every number of a pose is finite (a display skips a pose that is not).
export function poseFinite(pose) {
  const p = (pose && pose.position) || {}, q = (pose && pose.orientation) || {};
  return [p.x, p.y, p.z, q.x, q.y, q.z, q.w].every((v) => typeof v === "number" && Number.isFinite(v));
}

// A material of a display colour ("#rrggbb") and alpha (0..1).
export function material(THREE, color, alpha = 1, kind = "basic") {
  const opts = { color: new THREE.Color(color), transparent: alpha < 1, opacity: alpha, depthWrite: alpha >= 1 };
  return kind === "standard" ? new THREE.MeshStandardMaterial({ ...opts, roughness: 0.6 }) : new THREE.MeshBasicMaterial(opts);
}

// RViz2's arrow: a shaft (cylinder) then a head (cone) along +x from the origin.
export function makeArrow(THREE, o, mat) {
  const group = new THREE.Group();
  const shaft = new THREE.CylinderGeometry(o.shaftRadius, o.shaftRadius, o.shaftLength, 16);
  shaft.rotateZ(-Math.PI / 2);
  shaft.translate(o.shaftLength / 2, 0, 0);
  const head = new THREE.ConeGeometry(o.headRadius, o.headLength, 16);
  head.rotateZ(-Math.PI / 2);
  head.translate(o.shaftLength + o.headLength / 2, 0, 0);
  group.add(new THREE.Mesh(shaft, mat), new THREE.Mesh(head, mat));
  return group;
}

// Red/green/blue cylinders along x/y/z (RViz2's Axes shape).
export function makeAxes(THREE, length, radius, alpha = 1) {
  const group = new THREE.Group();
  const dirs = [[1, 0, 0, 0xff0000], [0, 1, 0, 0x00ff00], [0, 0, 1, 0x0000ff]];
  for (const [x, y, z, color] of dirs) {
    const g = new THREE.CylinderGeometry(radius, radius, length, 12);
    g.translate(0, length / 2, 0);
    const mesh = new THREE.Mesh(g, material(THREE, `#${color.toString(16).padStart(6, "0")}`, alpha));
    mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), new THREE.Vector3(x, y, z));
    group.add(mesh);
  }
  return group;
}

// Free the geometries and materials (and textures) under obj, and empty it.
export function disposeTree(obj) {
  obj.traverse((o) => {
    if (o.geometry) o.geometry.dispose();
    const mats = Array.isArray(o.material) ? o.material : o.material ? [o.material] : [];
    for (const m of mats) { if (m.map) m.map.dispose(); m.dispose(); }
  });
  obj.clear();
}

// Seconds of a builtin_interfaces/Time.
export const stampSeconds = (stamp) => (stamp ? (stamp.sec || 0) + (stamp.nanosec || 0) * 1e-9 : 0);

// The display options RViz2's Pose-like displays share (arrow or axes shape).
export const ARROW_OPTIONS = {
  shape: { type: "enum", choices: ["Arrow", "Axes"], default: "Arrow", label: "Shape" },
  color: { type: "color", default: "#ff1900", label: "Color" },
  alpha: { type: "number", default: 1, min: 0, max: 1, step: 0.1, label: "Alpha" },
  shaft_length: { type: "number", default: 1, min: 0.001, max: 100, step: 0.05, label: "Shaft Length" },
  shaft_radius: { type: "number", default: 0.05, min: 0.0001, max: 10, step: 0.01, label: "Shaft Radius" },
  head_length: { type: "number", default: 0.3, min: 0.001, max: 100, step: 0.05, label: "Head Length" },
  head_radius: { type: "number", default: 0.1, min: 0.0001, max: 10, step: 0.01, label: "Head Radius" },
  axes_length: { type: "number", default: 1, min: 0.001, max: 100, step: 0.05, label: "Axes Length" },
  axes_radius: { type: "number", default: 0.1, min: 0.0001, max: 10, step: 0.01, label: "Axes Radius" },
};

// An arrow or axes for one pose with the ARROW_OPTIONS values.
export function makePoseShape(THREE, o) {
  if (o.shape === "Axes") return makeAxes(THREE, o.axes_length, o.axes_radius, o.alpha);
  return makeArrow(THREE, {
    shaftLength: o.shaft_length, shaftRadius: o.shaft_radius,
    headLength: o.head_length, headRadius: o.head_radius,
  }, material(THREE, o.color, o.alpha));
}

// An arrow of total length L in RViz2's proportions (shaft 77 %, radii L/20 and L/10).
export function makeArrowOfLength(THREE, L, mat) {
  return makeArrow(THREE, { shaftLength: 0.77 * L, shaftRadius: L / 20, headLength: 0.23 * L, headRadius: L / 10 }, mat);
}

// A copy of `shape` at every pose (in the group's frame), added to `group`.
export function addAtPoses(THREE, group, shape, poses) {
  for (const p of poses) {
    const s = shape.clone();
    s.matrixAutoUpdate = false;
    poseMatrix(THREE, p, s.matrix);
    group.add(s);
  }
}

// The display object of a display drawing the newest message of poses (PoseArray, Path):
// `draw(msg, options)` redraws `group` (placed in the message's header frame); the status
// and `info` count `msg.poses`.
export function newestPosesDisplay(ctx, group, options, draw) {
  let o = options, last = null;
  const redraw = () => { disposeTree(group); if (last) draw(last, o); };
  return {
    update(msg) {
      last = msg;
      const placed = ctx.attach(group, msg.header.frame_id);
      ctx.setStatus(placed ? "ok" : "warn", placed ? `${msg.poses.length} poses` : `no transform from [${msg.header.frame_id}]`);
      redraw();
    },
    setOptions(next) { o = next; redraw(); },
    dispose() { disposeTree(group); },
    info: () => (last ? { frame: last.header.frame_id, poses: last.poses.length } : null),
  };
}
