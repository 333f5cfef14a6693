// posekit viewer page: WebSocket client, panels and controls; the scene is drawn by
// scene3d.js (three.js / WebGL) or, when WebGL or three.js is unavailable, scene2d.js.
// Protocol: see src/posekit/viewer/server.py. Displays added from the topic list:
// display_manager.js and the modules in displays/.

import { createDisplayManager, loadDisplayModules } from "./display_manager.js";
import { newestImageLoader } from "./image_loader.js";

const params = new URLSearchParams(location.search);
const STALE_S = Number(params.get("stale") || 1.0);          // frames older than this: grey
const ODOM_TOPICS = { filtered: "/odometry/filtered", wheels: "/odometry/wheels" };

const $ = (id) => document.getElementById(id);

// Introspection for tests and scripts (read-only use).
const debug = (window.posekitViewer = {
  renderer: "none", rendererNote: "", renders: 0, tfMessages: 0, odomMessages: 0,
  graphMessages: 0, imageUpdates: {}, frames: [], fixedFrame: null, fixedFrameError: null,
  trails: {}, connected: false, paused: false,
});

const state = {
  fixedFrame: params.get("fixed_frame") || null,
  paused: false,
  ws: null,
  hello: null,
  lastTf: null,
  lastOdom: null,
  imageTopics: [],
  watched: new Set(),
  dirty: true,
  fps: Number(params.get("fps") || 30),
};

// The displays added from the topic list (display_manager.js), once the modules are loaded.
let displays = null;

// RViz2's TF display options (per-frame axes and names, marker scale).
const tfOptions = { hidden: new Set(), noName: new Set(), scale: 1.0 };
let knownFrames = [];

function applyTfOptions() {
  if (scene) scene.setTfOptions(tfOptions);
  debug.tfOptions = { hidden: [...tfOptions.hidden].sort(), noName: [...tfOptions.noName].sort(), scale: tfOptions.scale };
  for (const box of document.querySelectorAll("#tf-tree input[data-kind]")) {
    const set = box.dataset.kind === "show" ? tfOptions.hidden : tfOptions.noName;
    box.checked = !set.has(box.dataset.frame);
  }
  state.dirty = true;
}

const visibility = () => ({
  grid: $("show-grid").checked,
  tf: $("show-tf").checked,
  names: $("show-names").checked,
  robot: $("show-robot").checked,
  [ODOM_TOPICS.filtered]: $("show-odom-filtered").checked,
  [ODOM_TOPICS.wheels]: $("show-odom-wheels").checked,
  truth: $("show-truth").checked,
  world: $("show-world").checked,
  goal: $("show-goal").checked,
  detections: $("show-detections").checked,
});

// ------------------------------------------------------------------------------ scene
let scene = null;

// Why the 3D view could not start, said as what to do about it.
async function fallbackReason(err) {
  const detail = err && err.message ? err.message : String(err);
  let threeServed = false;
  try {
    threeServed = (await fetch("/vendor/three/build/three.module.js", { method: "HEAD" })).ok;
  } catch (_) {
    threeServed = false;
  }
  if (!threeServed) {
    return "2D top-down view: three.js is missing from this posekit installation " +
      "(posekit/viewer/web/vendor/three). Reinstall posekit with " +
      "pip install --force-reinstall 'posekit[viewer]', then reload this page.";
  }
  if (/WebGL/i.test(detail)) {
    return "2D top-down view: this browser has no WebGL. Turn on hardware acceleration " +
      "(or use a browser with WebGL), then reload this page.";
  }
  return `2D top-down view: the 3D view failed to start (${detail}); reload the page, ` +
    "and check the browser console for the cause.";
}

async function createScene() {
  const container = $("view");
  const want2d = params.get("renderer") === "2d";
  if (!want2d) {
    try {
      const mod = await import("./scene3d.js");
      scene = await mod.createScene3D(container);
      debug.renderer = "webgl";
    } catch (err) {
      debug.rendererNote = await fallbackReason(err);
      console.warn(debug.rendererNote, err);
    }
  } else {
    debug.rendererNote = "2D top-down view (renderer=2d)";
  }
  if (!scene) {
    const mod = await import("./scene2d.js");
    scene = mod.createScene2D(container);
    debug.renderer = "2d";
  }
  if (debug.rendererNote) {
    $("renderer-note").textContent = debug.rendererNote;
    $("renderer-note").hidden = false;
  }
  scene.setVisibility(visibility());
  scene.setTfOptions(tfOptions);
  debug.labels = () => scene.labelState();
  debug.detections = () => (scene.detections ? scene.detections() : {});
}

// Render loop capped at state.fps (30 by default) so a laptop stays cool.
let lastRender = 0;
function loop(now) {
  requestAnimationFrame(loop);
  if (!scene) return;
  const interval = 1000 / state.fps;
  if (now - lastRender < interval - 1) return;
  if (!state.dirty && !scene.needsRender()) return;
  lastRender = now;
  state.dirty = false;
  scene.render();
  debug.renders += 1;
}

// ------------------------------------------------------------------------------ socket
function send(obj) {
  if (state.ws && state.ws.readyState === WebSocket.OPEN) state.ws.send(JSON.stringify(obj));
}

function connect() {
  const proto = location.protocol === "https:" ? "wss:" : "ws:";
  const ws = new WebSocket(`${proto}//${location.host}/ws`);
  ws.binaryType = "arraybuffer";
  state.ws = ws;
  ws.onopen = () => {
    debug.connected = true;
    setConnection("connected", "ok");
    if (state.fixedFrame) send({ op: "fixed_frame", frame: state.fixedFrame });
    if (state.paused) send({ op: "pause", paused: true });
    updateWatch(true);
    if (displays) displays.onConnected();
  };
  ws.onclose = () => {
    debug.connected = false;
    setConnection("disconnected — retrying", "bad");
    setTimeout(connect, 1000);
  };
  ws.onmessage = (ev) => {
    if (typeof ev.data !== "string") { onImage(ev.data); return; }
    const msg = JSON.parse(ev.data);
    switch (msg.type) {
      case "hello": onHello(msg); break;
      case "tf": onTf(msg); break;
      case "odom": onOdom(msg); break;
      case "graph": onGraph(msg); break;
      case "goal_sent": debug.goalSent = msg; break;
      case "initial_pose_sent": debug.initialPoseSent = msg; break;
      case "display": if (!state.paused && displays) displays.onMessages(msg.topic, msg.messages); break;
      case "error": console.warn("viewer server:", msg.message); break;
      default: break;
    }
  };
}

function setConnection(text, cls) {
  const el = $("connection");
  el.textContent = text;
  el.className = `status ${cls}`;
}

function onHello(msg) {
  state.hello = msg;
  if (!state.fixedFrame) state.fixedFrame = msg.fixed_frame;
  if (!params.get("fps") && msg.fps) state.fps = msg.fps;
  if (scene) scene.setWorld(msg.world);
  debug.world = msg.world ? msg.world.name : null;
  fillFixedFrames([]);
  // A configuration the server was started with (posekit view --config FILE), once, unless
  // the URL names one.
  if (msg.config && !params.get("view") && !state.serverConfigApplied) {
    state.serverConfigApplied = true;
    try {
      applyConfig(msg.config);
    } catch (err) {
      showConfigError(err);
    }
  }
  state.dirty = true;
}

function onTf(msg) {
  if (state.paused) return;
  if (msg.fixed !== state.fixedFrame) return;   // an answer for a previous choice
  state.lastTf = msg;
  debug.tf = msg;
  debug.tfMessages += 1;
  debug.frames = msg.frames.map((f) => f[0]);
  debug.fixedFrame = msg.fixed;
  debug.fixedFrameError = msg.error;
  const banner = $("fixed-frame-status");
  if (msg.error) {
    banner.textContent = msg.error;
    banner.hidden = false;
  } else {
    banner.hidden = true;
  }
  $("sim-time").textContent = `t = ${msg.now.toFixed(2)} s`;
  fillFixedFrames(debug.frames);
  if (scene) scene.setFrames(msg, STALE_S);
  if (displays) displays.onFrames();
  state.dirty = true;
}

function onOdom(msg) {
  if (state.paused) return;
  state.lastOdom = msg;
  debug.odomMessages += 1;
  for (const [topic, d] of Object.entries(msg.displays)) debug.trails[topic] = d.trail.length;
  if (scene) scene.setOdometry(msg.displays, state.hello);
  state.dirty = true;
}

// The clock line: sim time, wall time, real-time factor (state from the server).
function fillClock(clock) {
  if (!clock) return;
  debug.clock = clock;
  const wall = new Date(clock.wall * 1000).toISOString().slice(11, 19) + " UTC";
  const rtf = clock.rtf === null ? "—" : `${clock.rtf.toFixed(2)}×`;
  const el = $("clock");
  el.textContent = clock.sim === null
    ? `sim — (wall clock) · wall ${wall} · RTF ${rtf}`
    : `sim ${clock.sim.toFixed(2)} s · wall ${wall} · RTF ${rtf}`;
  el.classList.toggle("slow", clock.rtf !== null && clock.rtf < 0.9);
  el.dataset.source = clock.source;
  debug.clockText = el.textContent;
  $("topics-hz").textContent = clock.rate_clock === "sim" ? "Hz (sim)" : "Hz";
}

function onGraph(msg) {
  if (state.paused) return;
  debug.graphMessages += 1;
  fillClock(msg.clock);
  debug.goal = msg.goal;
  if (scene) scene.setGoal(msg.goal);
  fillTree(msg.tree);
  fillTopics(msg.topics);
  state.topics = msg.topics;
  addCameras(msg.topics);
  state.imageTopics = msg.images;
  fillCameraTopics(msg.images);
  updateWatch(false);
}

// ------------------------------------------------------------------------------ cameras
// "Cameras": a Camera display (camera.js: frustum and image) for every camera_info topic as
// it appears; a camera whose display the user removed is not added again. Unticked, the
// Camera displays are hidden.
const CAMERA_INFO = "sensor_msgs/msg/CameraInfo";
let camerasHandled = new Set();

function addCameras(topics) {
  if (!displays || !$("show-cameras").checked) return;
  for (const t of topics) {
    if (t.type !== CAMERA_INFO || camerasHandled.has(t.name)) continue;
    camerasHandled.add(t.name);
    const exists = displays.state().displays.some((d) => d.display === "Camera" && d.topic === t.name);
    if (!exists) {
      try { displays.add("Camera", t.name, t.type); } catch (err) { console.warn("viewer: no Camera display", err); }
    }
  }
}

$("show-cameras").addEventListener("change", () => {
  if (!displays) return;
  const on = $("show-cameras").checked;
  for (const d of displays.state().displays) if (d.display === "Camera") displays.setEnabled(d.id, on);
  if (on && state.topics) addCameras(state.topics);
});

// ------------------------------------------------------------------------------ controls
function fillFixedFrames(frames) {
  const select = $("fixed-frame");
  const names = new Set(frames);
  if (state.fixedFrame) names.add(state.fixedFrame);
  const sorted = [...names].sort();
  const current = [...select.options].map((o) => o.value);
  if (current.join("\n") !== sorted.join("\n")) {
    select.replaceChildren(...sorted.map((n) => new Option(n, n)));
  }
  if (state.fixedFrame) select.value = state.fixedFrame;
}

$("fixed-frame").addEventListener("change", (ev) => {
  state.fixedFrame = ev.target.value;
  state.lastTf = null;
  send({ op: "fixed_frame", frame: state.fixedFrame });
  if (scene) scene.resetTrails();
});

$("pause").addEventListener("click", () => {
  state.paused = !state.paused;
  debug.paused = state.paused;
  const button = $("pause");
  button.textContent = state.paused ? "Resume" : "Pause";
  button.setAttribute("aria-pressed", String(state.paused));
  send({ op: "pause", paused: state.paused });
});

for (const input of document.querySelectorAll(".toggles input")) {
  input.addEventListener("change", () => {
    if (scene) scene.setVisibility(visibility());
    state.dirty = true;
  });
}

// RViz2's pose tools: press on the ground for the position, drag for the heading, release
// to publish in the Fixed Frame (the server publishes). One pose per activation, as in RViz2.
// * 2D Goal Pose: geometry_msgs/PoseStamped on goal_pose;
// * 2D Pose Estimate: geometry_msgs/PoseWithCovarianceStamped on initialpose (RViz2's
//   covariance: 0.25 m² in x and y, (pi/12)² rad² in yaw).
const TOOLS = {
  goal: { button: "goal-tool", op: "goal", debugKey: "goalTool" },
  pose: { button: "pose-tool", op: "initial_pose", debugKey: "poseTool" },
};
const poseTool = { kind: null, from: null, yaw: 0 };

function setTool(kind) {
  poseTool.kind = kind;
  poseTool.from = null;
  for (const [k, t] of Object.entries(TOOLS)) {
    debug[t.debugKey] = k === kind;
    $(t.button).setAttribute("aria-pressed", String(k === kind));
  }
  $("view").classList.toggle("goal-tool", Boolean(kind));
  if (scene) { scene.setControlsEnabled(!kind); scene.setDraft(null, 0); }
  state.dirty = true;
}

for (const kind of Object.keys(TOOLS)) {
  $(TOOLS[kind].button).addEventListener("click", () => setTool(poseTool.kind === kind ? null : kind));
}

function goalPointer(kind, ev) {
  if (!poseTool.kind || !scene || ev.button > 0) return;
  const p = scene.pickGround(ev.clientX, ev.clientY);
  if (kind === "down") {
    if (!p) return;
    poseTool.from = p;
    poseTool.yaw = 0;
  } else if (poseTool.from && p) {
    const dx = p.x - poseTool.from.x, dy = p.y - poseTool.from.y;
    if (Math.hypot(dx, dy) > 1e-3) poseTool.yaw = Math.atan2(dy, dx);
  }
  if (!poseTool.from) return;
  ev.preventDefault();
  if (kind === "up") {
    const { from, yaw } = poseTool;
    send({ op: TOOLS[poseTool.kind].op, frame: state.fixedFrame, x: from.x, y: from.y, yaw });
    setTool(null);
  } else {
    scene.setDraft(poseTool.from, poseTool.yaw, poseTool.kind);
  }
  state.dirty = true;
}

// ------------------------------------------------------------------------------ saved views
// A view configuration (JSON, version 1): the fixed frame, the camera, every display toggle,
// the TF display options and the image panels. "Save view" downloads it, "Load view" reads
// it back, "Link" puts it in the URL (?view=<base64url JSON>) and a page opened with that
// URL starts from it. Unknown keys are ignored; wrong values are skipped and named.
const CONFIG_VERSION = 1;
const toggleIds = () => [...document.querySelectorAll(".toggles input")].map((i) => i.id);

function viewConfig() {
  return {
    posekit_view: CONFIG_VERSION,
    fixed_frame: state.fixedFrame,
    renderer: scene ? scene.kind : null,
    view: scene ? scene.getView() : null,
    displays: Object.fromEntries(toggleIds().map((id) => [id.replace(/^show-/, ""), $(id).checked])),
    tf: { hidden: [...tfOptions.hidden].sort(), no_name: [...tfOptions.noName].sort(), marker_scale: tfOptions.scale },
    topic_displays: displays ? displays.toConfig() : [],
    cameras_handled: [...camerasHandled].sort(),
    panels: {
      camera_topic: $("camera-topic").value || null,
      open: Object.fromEntries([...document.querySelectorAll("#panels details")].map((d) => [d.id, d.open])),
    },
  };
}

function applyConfig(cfg) {
  const problems = [];
  if (!cfg || typeof cfg !== "object" || cfg.posekit_view !== CONFIG_VERSION) {
    throw new Error(`not a posekit view configuration (version ${CONFIG_VERSION})`);
  }
  const names = (v) => Array.isArray(v) && v.every((n) => typeof n === "string" && n.length <= 256);
  if (typeof cfg.fixed_frame === "string" && cfg.fixed_frame && cfg.fixed_frame.length <= 256) {
    if (cfg.fixed_frame !== state.fixedFrame) {
      state.fixedFrame = cfg.fixed_frame;
      state.lastTf = null;
      send({ op: "fixed_frame", frame: state.fixedFrame });
      if (scene) scene.resetTrails();
      fillFixedFrames(debug.frames);
    }
  } else if (cfg.fixed_frame !== undefined) problems.push("fixed_frame");
  if (cfg.view !== undefined && !(scene && cfg.renderer === scene.kind && scene.setView(cfg.view))) {
    problems.push("view");
  }
  for (const [key, on] of Object.entries(cfg.displays || {})) {
    const box = $(`show-${key}`);
    if (box && box.closest(".toggles") && typeof on === "boolean") box.checked = on;
    else problems.push(`displays.${key}`);
  }
  const tf = cfg.tf || {};
  if (names(tf.hidden)) tfOptions.hidden = new Set(tf.hidden); else if (tf.hidden !== undefined) problems.push("tf.hidden");
  if (names(tf.no_name)) tfOptions.noName = new Set(tf.no_name); else if (tf.no_name !== undefined) problems.push("tf.no_name");
  if (Number.isFinite(tf.marker_scale) && tf.marker_scale >= 0.1 && tf.marker_scale <= 10) {
    tfOptions.scale = tf.marker_scale;
    $("marker-scale").value = String(tf.marker_scale);
  } else if (tf.marker_scale !== undefined) problems.push("tf.marker_scale");
  if (cfg.topic_displays !== undefined) {
    if (displays) problems.push(...displays.fromConfig(cfg.topic_displays));
    else problems.push("topic_displays");
  }
  if (names(cfg.cameras_handled)) camerasHandled = new Set(cfg.cameras_handled);
  else if (cfg.cameras_handled !== undefined) problems.push("cameras_handled");
  const panels = cfg.panels || {};
  for (const [id, open] of Object.entries(panels.open || {})) {
    const d = $(id);
    if (d && d.tagName === "DETAILS" && typeof open === "boolean") d.open = open;
  }
  if (typeof panels.camera_topic === "string") {
    state.preferredCamera = panels.camera_topic;
    const select = $("camera-topic");
    if ([...select.options].some((o) => o.value === panels.camera_topic)) select.value = panels.camera_topic;
  }
  if (scene) scene.setVisibility(visibility());
  applyTfOptions();
  updateWatch(true);
  debug.configProblems = problems;
  const note = $("config-note");
  note.hidden = problems.length === 0;
  note.textContent = problems.length ? `view loaded; skipped: ${problems.join(", ")}` : "";
  state.dirty = true;
}

function encodeConfig(cfg) {
  const bytes = new TextEncoder().encode(JSON.stringify(cfg));
  let bin = "";
  for (const b of bytes) bin += String.fromCharCode(b);
  return btoa(bin).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

function decodeConfig(text) {
  const bin = atob(text.replace(/-/g, "+").replace(/_/g, "/"));
  return JSON.parse(new TextDecoder().decode(Uint8Array.from(bin, (c) => c.charCodeAt(0))));
}

function showConfigError(err) {
  const note = $("config-note");
  note.textContent = `view not loaded: ${err.message || err}`;
  note.hidden = false;
  debug.configError = note.textContent;
}

$("config-save").addEventListener("click", () => {
  const blob = new Blob([JSON.stringify(viewConfig(), null, 2) + "\n"], { type: "application/json" });
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = "posekit-view.json";
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
});

$("config-load").addEventListener("change", async (ev) => {
  const file = ev.target.files && ev.target.files[0];
  ev.target.value = "";
  if (!file) return;
  try {
    if (file.size > 1 << 20) throw new Error("file larger than 1 MiB");
    applyConfig(JSON.parse(await file.text()));
    debug.configLoaded = (debug.configLoaded || 0) + 1;
  } catch (err) {
    showConfigError(err);
  }
});

$("config-link").addEventListener("click", () => {
  const url = new URL(location.href);
  for (const key of ["view", "camera", "target", "fixed_frame"]) url.searchParams.delete(key);
  url.searchParams.set("view", encodeConfig(viewConfig()));
  history.replaceState(null, "", url);
  debug.viewUrl = url.href;
});

debug.viewConfig = viewConfig;

// ------------------------------------------------------------------------------ panels
function cell(text, cls) {
  const td = document.createElement("td");
  td.textContent = text;
  if (cls) td.className = cls;
  return td;
}

function checkCell(frame, kind) {
  const td = document.createElement("td");
  const box = document.createElement("input");
  box.type = "checkbox";
  box.dataset.frame = frame;
  box.dataset.kind = kind;
  box.title = kind === "show" ? `show ${frame}` : `show the name of ${frame}`;
  box.checked = !(kind === "show" ? tfOptions.hidden : tfOptions.noName).has(frame);
  td.append(box);
  return td;
}

$("tf-tree").addEventListener("change", (ev) => {
  const box = ev.target;
  if (!box.dataset || !box.dataset.kind) return;
  const set = box.dataset.kind === "show" ? tfOptions.hidden : tfOptions.noName;
  if (box.checked) set.delete(box.dataset.frame); else set.add(box.dataset.frame);
  applyTfOptions();
});

$("marker-scale").addEventListener("input", (ev) => {
  const v = Number(ev.target.value);
  if (Number.isFinite(v) && v >= 0.1 && v <= 10) { tfOptions.scale = v; applyTfOptions(); }
});
$("tf-show-all").addEventListener("click", () => { tfOptions.hidden.clear(); tfOptions.noName.clear(); applyTfOptions(); });
$("tf-hide-all").addEventListener("click", () => { for (const f of knownFrames) tfOptions.hidden.add(f); applyTfOptions(); });
$("tf-names-none").addEventListener("click", () => { for (const f of knownFrames) tfOptions.noName.add(f); applyTfOptions(); });

// The frame rows are rebuilt only when the tree's shape changes, so a checkbox a user is
// clicking stays in the page; rates, ages and staleness are updated in place.
function fillTree(tree) {
  knownFrames = [...new Set([...tree.map((f) => f.name), ...tree.map((f) => f.parent)])].filter(Boolean);
  const body = $("tf-tree").tBodies[0];
  // Depth-first order under each root, indented, like rqt_tf_tree read top-down.
  const children = new Map();
  const names = new Set(tree.map((f) => f.name));
  for (const f of tree) {
    if (!children.has(f.parent)) children.set(f.parent, []);
    children.get(f.parent).push(f);
  }
  const roots = [...new Set(tree.map((f) => f.parent))].filter((p) => !names.has(p)).sort();
  const entries = [];  // [frame name, depth, the frame's tree entry (none for a root)]
  const walk = (name, depth) => {
    for (const f of (children.get(name) || []).sort((a, b) => a.name.localeCompare(b.name))) {
      entries.push([f.name, depth, f]);
      if (depth < 64) walk(f.name, depth + 1);
    }
  };
  for (const root of roots) {
    entries.push([root, 0, null]);
    walk(root, 1);
  }
  const key = entries.map(([name, depth, f]) => `${name} ${depth} ${f ? `${f.parent} ${f.static}` : ""}`).join("\n");
  if (body.dataset.key !== key) {
    body.dataset.key = key;
    body.replaceChildren(...entries.map(([name, depth, f]) => {
      const tr = document.createElement("tr");
      tr.dataset.frame = name;
      tr.append(
        checkCell(name, "show"),
        checkCell(name, "name"),
        cell(`${"\u00a0".repeat(depth)}${name}`),
        cell(f ? f.parent : ""),
        cell("", "num"),
        cell("", "num"),
      );
      return tr;
    }));
  }
  entries.forEach(([, , f], i) => {
    const tr = body.rows[i];
    if (!tr || !f) return;
    const stale = !f.static && f.age !== null && f.age > STALE_S;
    const cls = `${f.static ? "static" : ""} ${stale ? "stale" : ""}`;
    if (tr.className !== cls) tr.className = cls;
    const rate = f.static ? "static" : f.rate.toFixed(1);
    const age = f.static || f.age === null ? "" : f.age.toFixed(2);
    if (tr.cells[4].textContent !== rate) tr.cells[4].textContent = rate;
    if (tr.cells[5].textContent !== age) tr.cells[5].textContent = age;
  });
}

// The topic rows are rebuilt only when the topics change (their buttons stay put); the
// rates are updated in place.
function fillTopics(topics) {
  const body = $("topics").tBodies[0];
  const key = topics.map((t) => `${t.name} ${t.type} ${t.error || ""}`).join("\n");
  if (body.dataset.key !== key) {
    body.dataset.key = key;
    body.replaceChildren(...topics.map((t) => {
      const tr = document.createElement("tr");
      tr.dataset.topic = t.name;
      tr.append(cell(t.name), cell(t.type.replace("/msg/", "/")), cell("", "num"), addCell(t));
      if (t.error) tr.title = t.error;
      return tr;
    }));
  }
  topics.forEach((t, i) => {
    const td = body.rows[i] && body.rows[i].cells[2];
    const text = t.rate.toFixed(1);
    if (td && td.textContent !== text) td.textContent = text;
  });
}

// One "+ Name" button per display module that draws the topic's type.
function addCell(topic) {
  const td = document.createElement("td");
  for (const mod of displays ? displays.forType(topic.type) : []) {
    const b = document.createElement("button");
    b.type = "button";
    b.className = "add-display";
    b.dataset.addDisplay = mod.name;
    b.textContent = `+ ${mod.name}`;
    b.title = `add a ${mod.name} display for ${topic.name}`;
    b.addEventListener("click", () => {
      try {
        displays.add(mod.name, topic.name, topic.type);
      } catch (err) {
        showConfigError(err);
      }
    });
    td.append(b);
  }
  return td;
}

const isAruco = (t) => t.endsWith("aruco_detection_image");
const CAMERA_PREFERENCE = ["/oak/rgb/color", "/overhead_camera/image_raw"];

function fillCameraTopics(images) {
  const select = $("camera-topic");
  const cams = images.filter((t) => !isAruco(t));
  const current = [...select.options].map((o) => o.value);
  if (current.join("\n") === cams.join("\n")) return;
  const previous = select.value;
  select.replaceChildren(...cams.map((t) => new Option(t, t)));
  const preferred = [state.preferredCamera, ...CAMERA_PREFERENCE].find((t) => cams.includes(t)) || cams[0];
  select.value = cams.includes(previous) ? previous : (preferred || "");
  $("camera-info").textContent = cams.length ? "waiting for an image…" : "no image topic";
}

$("camera-topic").addEventListener("change", () => updateWatch(true));
$("camera-topic").addEventListener("click", (ev) => ev.stopPropagation());
for (const id of ["camera-panel", "aruco-panel"]) {
  $(id).addEventListener("toggle", () => updateWatch(true));
}

// Images are sent only for panels that are open (the server encodes nothing otherwise).
function updateWatch(force) {
  const want = new Set();
  const cam = $("camera-topic").value;
  if ($("camera-panel").open && cam) want.add(cam);
  const aruco = state.imageTopics.find(isAruco);
  if ($("aruco-panel").open && aruco) want.add(aruco);
  if (displays) for (const t of displays.imageTopics()) want.add(t);
  const same = want.size === state.watched.size && [...want].every((t) => state.watched.has(t));
  if (same && !force) return;
  state.watched = want;
  send({ op: "watch", topics: [...want] });
}

// The panels' images, newest only (image_loader.js); the info line follows the image shown.
const panelImages = {};
for (const target of ["camera", "aruco"]) {
  panelImages[target] = newestImageLoader($(`${target}-image`), (header) => {
    debug.imageUpdates[header.topic] = (debug.imageUpdates[header.topic] || 0) + 1;
    $(`${target}-info`).textContent =
      `${header.topic}  ${header.width}×${header.height} ${header.encoding}  stamp ${header.stamp.toFixed(3)} s`;
  });
}

function onImage(buffer) {
  if (state.paused) return;
  const view = new DataView(buffer);
  const headerLength = view.getUint32(0, false);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, headerLength)));
  const blob = new Blob([new Uint8Array(buffer, 4 + headerLength)], { type: "image/jpeg" });
  if (displays) displays.onImage(header.topic, blob, header);
  const target = isAruco(header.topic) ? "aruco" : (header.topic === $("camera-topic").value ? "camera" : null);
  if (target) panelImages[target].show(blob, header);
}

// ------------------------------------------------------------------------------ start
await createScene();
displays = createDisplayManager(await loadDisplayModules(), {
  scene,
  send,
  requestRender: () => { state.dirty = true; },
  fixedFrame: () => state.fixedFrame,
  now: () => (state.lastTf ? state.lastTf.now : null),
  topics: () => state.topics || [],
  panels: $("panels"),
  list: $("display-list"),
  watchImages: () => updateWatch(false),
  builtin: {
    // The TF display (tf.js) drives the toolbar's TF toggles and the marker scale.
    tf(o) {
      if (o.visible !== undefined) $("show-tf").checked = o.visible;
      if (o.names !== undefined) $("show-names").checked = o.names;
      if (o.scale !== undefined) { tfOptions.scale = o.scale; $("marker-scale").value = String(o.scale); }
      if (scene) scene.setVisibility(visibility());
      applyTfOptions();
    },
  },
});
debug.displays = () => displays.state();
debug.addDisplay = (name, topic, type, options) => displays.add(name, topic, type, options);
if (params.get("view")) {
  try {
    applyConfig(decodeConfig(params.get("view")));
  } catch (err) {
    showConfigError(err);
  }
}
scene.canvas.addEventListener("pointerdown", (ev) => goalPointer("down", ev));
window.addEventListener("pointermove", (ev) => goalPointer("move", ev));
window.addEventListener("pointerup", (ev) => goalPointer("up", ev));
debug.project = (x, y, z = 0) => scene.projectPoint(x, y, z);
connect();
requestAnimationFrame(loop);
