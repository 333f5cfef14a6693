// 2D top-down fallback (canvas 2D) when WebGL or three.js is unavailable: the Fixed Frame's
// x axis points right, y up. Drag to pan, wheel to zoom. Same interface as scene3d.js.

import { placeLabels } from "./labels.js";

const ODOM_COLORS = { "/odometry/filtered": "#ff1900", "/odometry/wheels": "#2f7bff", truth: "#21c45a" };

function yawOf(qx, qy, qz, qw) {
  return Math.atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz));
}

// Apply a planar pose (x, y, yaw) to a point.
function apply(pose, px, py) {
  const c = Math.cos(pose.yaw), s = Math.sin(pose.yaw);
  return [pose.x + c * px - s * py, pose.y + s * px + c * py];
}

export function createScene2D(container) {
  const canvas = document.createElement("canvas");
  canvas.id = "scene2d";
  container.prepend(canvas);
  const ctx = canvas.getContext("2d");
  let scale = 80;                  // px per metre
  let center = { x: 2.0, y: 1.5 }; // fixed-frame point at the canvas centre
  let moved = true;
  let frames = [];
  let poses = new Map();
  let world = null;
  let odom = {};
  let hello = null;
  let vis = {};
  let staleSeconds = 1.0;

  let tfOptions = { hidden: new Set(), noName: new Set(), scale: 1.0 };
  let labels = { hidden: 0, shown: [] };
  let goal = null;          // goal_pose in its frame
  let draft = null;         // the 2D Goal Pose tool's arrow {x, y, yaw} in the fixed frame
  let panEnabled = true;
  let drag = null;
  canvas.addEventListener("mousedown", (e) => { if (panEnabled) drag = { x: e.clientX, y: e.clientY }; });
  window.addEventListener("mouseup", () => { drag = null; });
  window.addEventListener("mousemove", (e) => {
    if (!drag) return;
    center.x -= (e.clientX - drag.x) / scale;
    center.y += (e.clientY - drag.y) / scale;
    drag = { x: e.clientX, y: e.clientY };
    moved = true;
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    scale = Math.min(2000, Math.max(5, scale * Math.exp(-e.deltaY * 0.001)));
    moved = true;
  }, { passive: false });

  const toPx = (x, y) => [canvas.width / 2 + (x - center.x) * scale, canvas.height / 2 - (y - center.y) * scale];

  function line(a, b, color, width = 1) {
    ctx.strokeStyle = color;
    ctx.lineWidth = width;
    ctx.beginPath();
    ctx.moveTo(...toPx(...a));
    ctx.lineTo(...toPx(...b));
    ctx.stroke();
  }

  function polygon(points, fill, stroke) {
    ctx.beginPath();
    points.forEach((p, i) => (i ? ctx.lineTo(...toPx(...p)) : ctx.moveTo(...toPx(...p))));
    ctx.closePath();
    if (fill) { ctx.fillStyle = fill; ctx.fill(); }
    if (stroke) { ctx.strokeStyle = stroke; ctx.lineWidth = 1; ctx.stroke(); }
  }

  function arrow(pose, length, color) {
    const tip = apply(pose, length, 0);
    line([pose.x, pose.y], tip, color, 2);
    const head = Math.min(0.04, 0.5 * length);
    polygon([tip, apply(pose, length - head, head * 0.5), apply(pose, length - head, -head * 0.5)], color);
  }

  // Pose of a 4x4 row-major matrix T (planar part) composed with a frame pose.
  function planar(T, frame) {
    const local = { x: T[3], y: T[7], yaw: Math.atan2(T[4], T[0]) };
    const [x, y] = apply(frame, local.x, local.y);
    return { x, y, yaw: frame.yaw + local.yaw };
  }

  function render() {
    moved = false;
    const w = container.clientWidth || 640, h = container.clientHeight || 480;
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    ctx.fillStyle = "#30303a";
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    if (vis.grid !== false) {
      const x0 = Math.floor(center.x - w / 2 / scale), x1 = Math.ceil(center.x + w / 2 / scale);
      const y0 = Math.floor(center.y - h / 2 / scale), y1 = Math.ceil(center.y + h / 2 / scale);
      for (let x = x0; x <= x1; x++) line([x, y0], [x, y1], x === 0 ? "#8888a0" : "#4a4a55");
      for (let y = y0; y <= y1; y++) line([x0, y], [x1, y], y === 0 ? "#8888a0" : "#4a4a55");
    }
    const worldPose = world && poses.get(world.frame || "odom");
    if (worldPose && vis.world !== false) {
      for (const b of world.boxes) {
        const p = planar(b.T, worldPose), s = b.size / 2;
        polygon([apply(p, s, s), apply(p, -s, s), apply(p, -s, -s), apply(p, s, -s)], "#f4f4f0", "#999");
      }
    }
    for (const [topic, d] of Object.entries(odom)) {
      const truth = hello && topic === hello.ground_truth_topic;
      if (vis[truth ? "truth" : topic] === false) continue;
      const frame = poses.get(d.frame || "odom");
      if (!frame) continue;
      const color = truth ? ODOM_COLORS.truth : (ODOM_COLORS[topic] || "#ffaa00");
      for (const p of d.trail) {
        const [x, y] = apply(frame, p[0], p[1]);
        arrow({ x, y, yaw: frame.yaw + yawOf(p[3], p[4], p[5], p[6]) }, Math.max(0.03, 0.5 * p[7]), color);
      }
    }
    const goalFrame = goal && poses.get(goal.frame);
    if (goalFrame && vis.goal !== false) {
      const [x, y, , qx, qy, qz, qw] = goal.pose;
      const [gx, gy] = apply(goalFrame, x, y);
      arrow({ x: gx, y: gy, yaw: goalFrame.yaw + yawOf(qx, qy, qz, qw) }, 0.45, "#ff40ff");
    }
    if (draft) arrow(draft, 0.45, "#40ff40");
    const base = poses.get((hello && hello.base_frame) || "base_link");
    if (base && vis.robot !== false) {
      polygon([apply(base, 0.1, 0.075), apply(base, -0.1, 0.075), apply(base, -0.1, -0.075), apply(base, 0.1, -0.075)], "#3a3f47", "#c0392b");
      for (const [wx, wy] of [[0.053, 0.096], [0.053, -0.096], [-0.053, 0.096], [-0.053, -0.096]]) {
        const c = apply(base, wx, wy);
        polygon([[c[0] - 0.0425, c[1] - 0.02], [c[0] + 0.0425, c[1] - 0.02], [c[0] + 0.0425, c[1] + 0.02], [c[0] - 0.0425, c[1] + 0.02]], "#111");
      }
    }
    const items = [];
    if (vis.tf !== false) {
      ctx.font = "12px 'DejaVu Sans', sans-serif";
      const axis = 0.15 * tfOptions.scale;
      for (const f of frames) {
        const [name, parent, , , , , , , , age, isStatic, ok] = f;
        const p = poses.get(name);
        if (!ok || !p || tfOptions.hidden.has(name)) continue;
        const stale = !isStatic && age > staleSeconds;
        const q = poses.get(parent);
        if (q) line([p.x, p.y], [q.x, q.y], stale ? "#777" : "#f0d050");
        line([p.x, p.y], apply(p, axis, 0), stale ? "#8a8a8a" : "#ff2020", 2);
        line([p.x, p.y], apply(p, 0, axis), stale ? "#8a8a8a" : "#20d020", 2);
        if (vis.names !== false && !tfOptions.noName.has(name)) {
          const [px, py] = toPx(p.x, p.y);
          items.push({ name, x: px, y: py, w: ctx.measureText(name).width, h: 14, stale });
        }
      }
      const where = placeLabels(items);
      for (const it of items) {
        const at = where.get(it.name);
        if (!at) continue;
        if (at.shifted) line(...[[it.x, it.y], [at.x, at.y + it.h / 2]].map(fromPx), "#aaa");
        ctx.fillStyle = it.stale ? "#888" : "#fff";
        ctx.fillText(it.name, at.x, at.y + it.h - 3);
      }
      labels = { hidden: items.length - where.size, shown: [...where.keys()] };
    } else {
      labels = { hidden: 0, shown: [] };
    }
  }

  const fromPx = ([px, py]) => [center.x + (px - canvas.width / 2) / scale, center.y - (py - canvas.height / 2) / scale];

  return {
    kind: "2d",
    canvas,
    setFrames(msg, stale) {
      staleSeconds = stale;
      frames = msg.frames;
      poses = new Map();
      for (const f of frames) {
        if (f[11]) poses.set(f[0], { x: f[2], y: f[3], yaw: yawOf(f[5], f[6], f[7], f[8]) });
      }
    },
    setWorld(w) { world = w; moved = true; },
    setOdometry(displays, helloMsg) { odom = displays; hello = helloMsg; },
    resetTrails() { odom = {}; },
    setVisibility(v) { vis = v; moved = true; },
    setGoal(g) { goal = g; moved = true; },
    setTfOptions(o) { tfOptions = o; moved = true; },
    // The view (centre in the Fixed Frame, m; scale, px per m) for saved configs.
    getView: () => ({ center: [center.x, center.y], scale }),
    setView(v) {
      if (!v || !Array.isArray(v.center) || v.center.length !== 2 || !v.center.every(Number.isFinite)
          || !Number.isFinite(v.scale) || v.scale < 5 || v.scale > 2000) return false;
      center = { x: v.center[0], y: v.center[1] };
      scale = v.scale;
      moved = true;
      return true;
    },
    labelState: () => ({ ...labels, frames: frames.filter((f) => f[11] && !tfOptions.hidden.has(f[0])).map((f) => f[0]) }),
    setDraft(from, yaw) { draft = from ? { x: from.x, y: from.y, yaw } : null; moved = true; },
    pickGround(clientX, clientY) {
      const r = canvas.getBoundingClientRect();
      const px = (clientX - r.left) * (canvas.width / r.width), py = (clientY - r.top) * (canvas.height / r.height);
      return { x: center.x + (px - canvas.width / 2) / scale, y: center.y - (py - canvas.height / 2) / scale };
    },
    projectPoint(x, y) {
      const r = canvas.getBoundingClientRect();
      const [px, py] = toPx(x, y);
      return { x: r.left + px * (r.width / canvas.width), y: r.top + py * (r.height / canvas.height) };
    },
    setControlsEnabled(on) { panEnabled = on; if (!on) drag = null; },
    needsRender: () => moved,
    render,
  };
}
