// The display framework (RViz2's "Displays" panel): displays added for topics, each one a
// module under app/displays/ (the server lists them at /api/displays). The contract a
// module follows is written down in docs/viewer.md ("Writing a display"):
//
//   export default {
//     name: "Odometry",                       // shown in the list and the config files
//     types: ["nav_msgs/msg/Odometry"],       // the ROS types it draws
//     queue: 1,                               // messages kept per send (1: newest only)
//     messages: true,                         // false: no message feed (images, TF)
//     options: { color: { type: "color", default: "#ff1900", label: "Color" }, ... },
//     create(ctx, topic, options) { return { update(msg), setOptions(o), dispose() }; },
//   };
//
// Messages arrive as JSON objects (posekit.viewer.display_feed.message_to_json): packed
// arrays ({"$bin", dtype, shape}) are turned into TypedArrays here before update(msg).

const TYPED = {
  int8: Int8Array, uint8: Uint8Array, int16: Int16Array, uint16: Uint16Array,
  int32: Int32Array, uint32: Uint32Array, int64: BigInt64Array, uint64: BigUint64Array,
  float32: Float32Array, float64: Float64Array,
};
const MAX_DISPLAYS = 64;

// Packed arrays -> TypedArrays (little-endian raw bytes), everywhere in a message.
export function unpackMessage(value) {
  if (Array.isArray(value)) {
    for (let i = 0; i < value.length; i += 1) value[i] = unpackMessage(value[i]);
    return value;
  }
  if (value && typeof value === "object") {
    if (typeof value.$bin === "string" && TYPED[value.dtype]) {
      const bin = atob(value.$bin);
      const bytes = new Uint8Array(bin.length);
      for (let i = 0; i < bin.length; i += 1) bytes[i] = bin.charCodeAt(i);
      const Typed = TYPED[value.dtype];
      return new Typed(bytes.buffer, 0, bytes.length / Typed.BYTES_PER_ELEMENT);
    }
    for (const key of Object.keys(value)) value[key] = unpackMessage(value[key]);
  }
  return value;
}

// An option value checked against its schema entry; undefined when it does not fit.
function checkOption(spec, value) {
  switch (spec.type) {
    case "color": return typeof value === "string" && /^#[0-9a-fA-F]{6}$/.test(value) ? value : undefined;
    case "number": {
      if (typeof value !== "number" || !Number.isFinite(value)) return undefined;
      if (spec.min !== undefined && value < spec.min) return undefined;
      if (spec.max !== undefined && value > spec.max) return undefined;
      return value;
    }
    case "bool": return typeof value === "boolean" ? value : undefined;
    case "enum": return (spec.choices || []).includes(value) ? value : undefined;
    case "string": return typeof value === "string" && value.length <= 256 ? value : undefined;
    default: return undefined;
  }
}

function defaults(module) {
  return Object.fromEntries(Object.entries(module.options || {}).map(([k, s]) => [k, s.default]));
}

// Load every display module the server lists; a module that fails to load or does not have
// the shape above is left out with a console warning (the page keeps working).
export async function loadDisplayModules() {
  const modules = [];
  let list = [];
  try {
    list = (await (await fetch("/api/displays")).json()).modules || [];
  } catch (err) {
    console.warn("viewer: cannot list the display modules", err);
  }
  for (const path of list) {
    try {
      const mod = (await import(path)).default;
      if (!mod || typeof mod.name !== "string" || !Array.isArray(mod.types) || typeof mod.create !== "function") {
        throw new Error("not a display module (name, types, create)");
      }
      modules.push({ queue: 1, messages: true, options: {}, ...mod, path });
    } catch (err) {
      console.warn(`viewer: display module ${path} not loaded:`, err);
    }
  }
  return modules;
}

// host: { scene, send(obj), requestRender(), fixedFrame(), now(), panels (element),
//         list (element), watchImages(), builtin }
export function createDisplayManager(modules, host) {
  const byName = new Map(modules.map((m) => [m.name, m]));
  const displays = [];                     // {id, module, topic, type, enabled, options, instance, ...}
  const subscriptions = new Map();         // topic -> {type, queue, listeners: Set}
  const imageWatches = new Map();          // topic -> Set(callback)
  const attached = new Map();              // Object3D -> frame
  const frameListeners = new Set();
  let nextId = 1;
  const stats = { messages: {} };

  const forType = (type) => modules.filter((m) => m.types.includes(type));

  function resubscribe(topic) {
    const sub = subscriptions.get(topic);
    if (sub) host.send({ op: "display_subscribe", topic, type: sub.type, queue: sub.queue });
  }

  function subscribe(topic, type, queue, listener) {
    let sub = subscriptions.get(topic);
    if (!sub) {
      sub = { type, queue: 1, listeners: new Set() };
      subscriptions.set(topic, sub);
    }
    sub.listeners.add(listener);
    listener.queue = queue;
    const wanted = Math.max(...[...sub.listeners].map((l) => l.queue || 1));
    if (wanted !== sub.queue || sub.listeners.size === 1) {
      sub.queue = wanted;
      resubscribe(topic);
    }
    return () => {
      sub.listeners.delete(listener);
      if (sub.listeners.size === 0) {
        subscriptions.delete(topic);
        host.send({ op: "display_unsubscribe", topic });
      }
    };
  }

  function watchImage(topic, callback) {
    if (!imageWatches.has(topic)) imageWatches.set(topic, new Set());
    imageWatches.get(topic).add(callback);
    host.watchImages();
    return () => {
      const set = imageWatches.get(topic);
      if (set) { set.delete(callback); if (!set.size) imageWatches.delete(topic); }
      host.watchImages();
    };
  }

  // A display's server-side wants (its topics' messages, its images) are held only while it
  // is enabled, as RViz2's displays subscribe on enable and unsubscribe on disable: the
  // server then follows a topic only while some enabled display shows it.
  function want(entry, start) {
    const w = { start, stop: null };
    entry.wants.add(w);
    if (entry.enabled) w.stop = start();
    return () => {
      if (w.stop) w.stop();
      w.stop = null;
      entry.wants.delete(w);
    };
  }

  function holdWants(entry) {
    for (const w of entry.wants) {
      if (entry.enabled && !w.stop) w.stop = w.start();
      else if (!entry.enabled && w.stop) { w.stop(); w.stop = null; }
    }
  }

  function place(obj, frame) {
    const m = host.scene.framePose ? host.scene.framePose(frame) : null;
    obj.visible = Boolean(m) && obj.userData.wantVisible !== false;
    if (m) { obj.matrix.copy(m); obj.matrixWorldNeedsUpdate = true; }
    return Boolean(m);
  }

  function makeContext(entry) {
    const three = host.scene.three || null;
    const root = three ? new three.Group() : null;
    if (root) host.scene.displayRoot.add(root);
    const cleanups = [];
    const ctx = {
      THREE: three,
      root,
      topic: entry.topic,
      type: entry.type,
      fixedFrame: host.fixedFrame,
      now: host.now,
      // The graph's topics as the topic list shows them: [{name, type, rate, ...}].
      topics: () => (host.topics ? host.topics() : []),
      requestRender: host.requestRender,
      // The page's own drawings a display may drive (the TF display: host.builtin.tf).
      builtin: host.builtin || {},
      // T_fixed_frame (a new THREE.Matrix4) at the latest time, or null when unknown.
      lookup(frame) {
        const m = host.scene.framePose ? host.scene.framePose((frame || "").replace(/^\//, "")) : null;
        return m ? m.clone() : null;
      },
      // Keep obj (matrixAutoUpdate off) at frame's pose in the fixed frame; hidden while
      // the frame is unknown. Returns whether it is placed now.
      attach(obj, frame) {
        obj.matrixAutoUpdate = false;
        attached.set(obj, { frame: (frame || "").replace(/^\//, ""), entry });
        return place(obj, attached.get(obj).frame);
      },
      detach(obj) { attached.delete(obj); },
      onFrames(cb) { frameListeners.add(cb); cleanups.push(() => frameListeners.delete(cb)); },
      subscribe(topic, type, queue, cb) {
        const listener = (msg) => cb(msg);
        const off = want(entry, () => subscribe(topic, type, queue, listener));
        cleanups.push(off);
        return off;
      },
      watchImage(topic, cb) {
        const off = want(entry, () => watchImage(topic, cb));
        cleanups.push(off);
        return off;
      },
      panel(title) {
        const d = document.createElement("details");
        d.open = true;
        d.className = "display-panel";
        d.dataset.displayId = String(entry.id);
        const s = document.createElement("summary");
        s.textContent = title;
        const body = document.createElement("div");
        body.className = "display-panel-body";
        d.append(s, body);
        host.panels.prepend(d);
        cleanups.push(() => d.remove());
        return body;
      },
      setStatus(level, text) {
        if (entry.status.level === level && entry.status.text === text) return;
        entry.status = { level, text };
        showStatus(entry);
      },
    };
    entry.cleanups = cleanups;
    entry.root = root;
    return ctx;
  }

  function add(name, topic, type, options = {}, enabled = true) {
    const module = byName.get(name);
    if (!module) throw new Error(`no display named ${name}`);
    if (!module.types.includes(type)) throw new Error(`${name} does not draw ${type}`);
    if (displays.length >= MAX_DISPLAYS) throw new Error(`at most ${MAX_DISPLAYS} displays`);
    const problems = [];
    const opts = defaults(module);
    for (const [k, v] of Object.entries(options || {})) {
      const spec = module.options[k];
      const ok = spec ? checkOption(spec, v) : undefined;
      if (ok === undefined) problems.push(`${name} ${topic}: option ${k}`);
      else opts[k] = ok;
    }
    const entry = { id: nextId++, module, topic, type, enabled: Boolean(enabled), options: opts, status: { level: "ok", text: "" }, wants: new Set() };
    const ctx = makeContext(entry);
    if (!ctx.THREE && module.needs3d !== false) {
      entry.status = { level: "warn", text: "needs the 3D view" };
      entry.instance = { update() {}, setOptions() {}, dispose() {} };
    } else {
      try {
        entry.instance = module.create(ctx, topic, { ...opts });
      } catch (err) {
        entry.status = { level: "error", text: String(err.message || err) };
        entry.instance = { update() {}, setOptions() {}, dispose() {} };
      }
    }
    if (module.messages !== false) {
      ctx.subscribe(topic, type, module.queue || 1, (msg) => {
        if (!entry.enabled) return;
        try {
          entry.instance.update(msg);
          if (entry.status.level === "error") { entry.status = { level: "ok", text: "" }; showStatus(entry); }
        } catch (err) {
          entry.status = { level: "error", text: String(err.message || err) };
          showStatus(entry);
        }
        host.requestRender();
      });
    }
    displays.push(entry);
    setEnabled(entry.id, entry.enabled);
    renderList();
    host.requestRender();
    return { id: entry.id, problems };
  }

  function find(id) { return displays.find((d) => d.id === id); }

  function remove(id) {
    const i = displays.findIndex((d) => d.id === id);
    if (i < 0) return;
    const [entry] = displays.splice(i, 1);
    for (const [obj, a] of attached) if (a.entry === entry) attached.delete(obj);
    try { entry.instance.dispose(); } catch (err) { console.warn("display dispose failed", err); }
    for (const off of entry.cleanups) off();
    if (entry.root) entry.root.removeFromParent();
    renderList();
    host.requestRender();
  }

  function setEnabled(id, on) {
    const entry = find(id);
    if (!entry) return;
    entry.enabled = Boolean(on);
    holdWants(entry);
    if (entry.enabledEl) entry.enabledEl.checked = entry.enabled;
    if (entry.root) entry.root.visible = entry.enabled;
    if (entry.instance.setEnabled) entry.instance.setEnabled(entry.enabled);
    host.requestRender();
  }

  function setOption(id, key, value) {
    const entry = find(id);
    if (!entry) return false;
    const spec = entry.module.options[key];
    const ok = spec ? checkOption(spec, value) : undefined;
    if (ok === undefined) return false;
    entry.options = { ...entry.options, [key]: ok };
    try { entry.instance.setOptions({ ...entry.options }); } catch (err) {
      entry.status = { level: "error", text: String(err.message || err) };
      showStatus(entry);
    }
    host.requestRender();
    return true;
  }

  // -- what the server sends
  function onMessages(topic, messages) {
    const sub = subscriptions.get(topic);
    if (!sub) return;
    stats.messages[topic] = (stats.messages[topic] || 0) + messages.length;
    for (const raw of messages) {
      const msg = unpackMessage(raw);
      for (const l of sub.listeners) l(msg);
    }
  }

  function onFrames() {
    for (const [obj, a] of attached) place(obj, a.frame);
    for (const cb of frameListeners) {
      try { cb(); } catch (err) { console.warn("display onFrames failed", err); }
    }
  }

  function onImage(topic, blob, header) {
    const set = imageWatches.get(topic);
    if (!set) return false;
    for (const cb of set) cb(blob, header);
    return set.size > 0;
  }

  function onConnected() { for (const topic of subscriptions.keys()) resubscribe(topic); }

  // -- the saved configuration: [{display, topic, type, enabled, options}]
  function toConfig() {
    return displays.map((d) => ({ display: d.module.name, topic: d.topic, type: d.type, enabled: d.enabled, options: { ...d.options } }));
  }

  function fromConfig(list) {
    const problems = [];
    if (!Array.isArray(list)) return ["topic_displays"];
    for (const d of [...displays]) remove(d.id);
    list.forEach((item, i) => {
      try {
        if (!item || typeof item !== "object" || typeof item.topic !== "string" || !item.topic.startsWith("/") || item.topic.length > 256 || typeof item.type !== "string") {
          throw new Error("not a display");
        }
        const r = add(item.display, item.topic, item.type, item.options || {}, item.enabled !== false);
        problems.push(...r.problems);
      } catch (err) {
        problems.push(`topic_displays[${i}] (${err.message || err})`);
      }
    });
    return problems;
  }

  // -- the Displays panel
  function optionInput(entry, key, spec) {
    const label = document.createElement("label");
    label.textContent = `${spec.label || key} `;
    let input;
    if (spec.type === "enum") {
      input = document.createElement("select");
      for (const c of spec.choices) input.append(new Option(String(c), String(c)));
      input.value = String(entry.options[key]);
    } else {
      input = document.createElement("input");
      input.type = spec.type === "color" ? "color" : spec.type === "bool" ? "checkbox" : spec.type === "number" ? "number" : "text";
      if (spec.type === "bool") input.checked = Boolean(entry.options[key]);
      else input.value = String(entry.options[key]);
      if (spec.type === "number") {
        for (const a of ["min", "max", "step"]) if (spec[a] !== undefined) input[a] = String(spec[a]);
      }
    }
    input.dataset.option = key;
    input.addEventListener(spec.type === "bool" || spec.type === "enum" || spec.type === "color" ? "change" : "input", () => {
      const v = spec.type === "bool" ? input.checked : spec.type === "number" ? Number(input.value) : input.value;
      setOption(entry.id, key, v);
    });
    label.append(input);
    return label;
  }

  // One row per display, built once; a status change updates its text only.
  function makeRow(entry) {
    const row = document.createElement("details");
    row.className = "display";
    row.dataset.displayId = String(entry.id);
    row.dataset.display = entry.module.name;
    row.dataset.topic = entry.topic;
    const summary = document.createElement("summary");
    const enabled = document.createElement("input");
    enabled.type = "checkbox";
    enabled.checked = entry.enabled;
    enabled.className = "display-enabled";
    enabled.title = "show this display";
    enabled.addEventListener("click", (ev) => ev.stopPropagation());
    enabled.addEventListener("change", () => setEnabled(entry.id, enabled.checked));
    const title = document.createElement("span");
    title.textContent = ` ${entry.module.name} ${entry.topic} `;
    const status = document.createElement("span");
    status.className = "display-status";
    const removeButton = document.createElement("button");
    removeButton.type = "button";
    removeButton.className = "display-remove";
    removeButton.title = "remove this display";
    removeButton.textContent = "✕";
    removeButton.addEventListener("click", (ev) => { ev.preventDefault(); remove(entry.id); });
    summary.append(enabled, title, status, removeButton);
    const form = document.createElement("div");
    form.className = "display-options";
    for (const [key, spec] of Object.entries(entry.module.options || {})) form.append(optionInput(entry, key, spec));
    row.append(summary, form);
    entry.row = row;
    entry.statusEl = status;
    entry.enabledEl = enabled;
    showStatus(entry);
    return row;
  }

  function showStatus(entry) {
    if (!entry.statusEl) return;
    const cls = `display-status ${entry.status.level}`;
    if (entry.statusEl.className !== cls) entry.statusEl.className = cls;
    if (entry.statusEl.textContent !== entry.status.text) entry.statusEl.textContent = entry.status.text;
  }

  function renderList() {
    const list = host.list;
    if (!list) return;
    const rows = displays.map((entry) => entry.row || makeRow(entry));
    const current = [...list.children];
    if (current.length !== rows.length || current.some((el, i) => el !== rows[i])) list.replaceChildren(...rows);
  }

  return {
    modules,
    forType,
    add,
    remove,
    setEnabled,
    setOption,
    onMessages,
    onFrames,
    onImage,
    onConnected,
    toConfig,
    fromConfig,
    imageTopics: () => [...imageWatches.keys()],
    // Page state for tests and scripts.
    state: () => ({
      displays: displays.map((d) => ({ id: d.id, display: d.module.name, topic: d.topic, type: d.type, enabled: d.enabled, options: { ...d.options }, status: { ...d.status }, info: d.instance.info ? d.instance.info() : null })),
      subscriptions: Object.fromEntries([...subscriptions].map(([t, s]) => [t, { type: s.type, queue: s.queue }])),
      messages: { ...stats.messages },
    }),
  };
}
