// Helpers of the point displays (LaserScan, PointCloud2): colouring and one THREE.Points per
// cloud. Colours are RViz2's "Color Transformer" choices: a flat colour, a scalar (intensity,
// range, a coordinate) mapped to a rainbow or between two colours, or the points' own rgb.

// Options the point displays share (RViz2's names).
export const POINT_OPTIONS = {
  size: { type: "number", default: 0.03, min: 0.0001, max: 10, step: 0.01, label: "Size (m)" },
  alpha: { type: "number", default: 1, min: 0, max: 1, step: 0.1, label: "Alpha" },
  use_rainbow: { type: "bool", default: true, label: "Use rainbow" },
  min_color: { type: "color", default: "#000000", label: "Min Color" },
  max_color: { type: "color", default: "#ffffff", label: "Max Color" },
  autocompute_value_bounds: { type: "bool", default: true, label: "Autocompute Value Bounds" },
  min_value: { type: "number", default: 0, min: -1e9, max: 1e9, step: 0.1, label: "Min Value" },
  max_value: { type: "number", default: 1, min: -1e9, max: 1e9, step: 0.1, label: "Max Value" },
  color: { type: "color", default: "#ffffff", label: "Color" },
};

// Rainbow of t in [0, 1]: blue (0) through cyan, green, yellow to red (1); [r, g, b] in 0..1.
export function rainbow(t) {
  const h = (1 - Math.min(1, Math.max(0, t))) * 4;  // 4 = blue ... 0 = red
  const i = Math.floor(h), f = h - i;
  switch (i) {
    case 0: return [1, f, 0];          // red -> yellow
    case 1: return [1 - f, 1, 0];      // yellow -> green
    case 2: return [0, 1, f];          // green -> cyan
    case 3: return [0, 1 - f, 1];      // cyan -> blue
    default: return [0, 0, 1];
  }
}

function hexRgb(hex) {
  const v = parseInt(hex.slice(1), 16);
  return [((v >> 16) & 255) / 255, ((v >> 8) & 255) / 255, (v & 255) / 255];
}

// Per-point colours (Float32Array, 3 per point) of `values` (n numbers) with the options'
// bounds and map; returns {colors, min, max} (the bounds used).
export function scalarColors(values, n, o) {
  let lo = o.min_value, hi = o.max_value;
  if (o.autocompute_value_bounds) {
    lo = Infinity; hi = -Infinity;
    for (let i = 0; i < n; i += 1) {
      const v = values[i];
      if (v < lo) lo = v;
      if (v > hi) hi = v;
    }
    if (!(lo <= hi)) { lo = 0; hi = 1; }
  }
  const span = hi - lo > 1e-12 ? hi - lo : 1;
  const colors = new Float32Array(3 * n);
  const a = hexRgb(o.min_color), b = hexRgb(o.max_color);
  for (let i = 0; i < n; i += 1) {
    const t = Math.min(1, Math.max(0, (values[i] - lo) / span));
    const c = o.use_rainbow ? rainbow(t) : [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])];
    colors[3 * i] = c[0]; colors[3 * i + 1] = c[1]; colors[3 * i + 2] = c[2];
  }
  return { colors, min: lo, max: hi };
}

// Flat colour for n points.
export function flatColors(hex, n) {
  const c = hexRgb(hex);
  const colors = new Float32Array(3 * n);
  for (let i = 0; i < n; i += 1) { colors[3 * i] = c[0]; colors[3 * i + 1] = c[1]; colors[3 * i + 2] = c[2]; }
  return colors;
}

// sRGB component (0..1) -> linear, what three.js's colour management expects of vertex colours.
const linear = (c) => (c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4);

// One THREE.Points of positions (Float32Array, 3 per point) and sRGB colours (0..1, converted
// in place to the renderer's linear working space), squares of `size` metres facing the
// camera (size attenuated with distance, as RViz2's "Flat Squares").
export function makePoints(THREE, positions, colors, o) {
  if (!THREE.ColorManagement || THREE.ColorManagement.enabled) {
    for (let i = 0; i < colors.length; i += 1) colors[i] = linear(colors[i]);
  }
  const geom = new THREE.BufferGeometry();
  geom.setAttribute("position", new THREE.BufferAttribute(positions, 3));
  geom.setAttribute("color", new THREE.BufferAttribute(colors, 3));
  const mat = new THREE.PointsMaterial({
    size: o.size, sizeAttenuation: true, vertexColors: true,
    transparent: o.alpha < 1, opacity: o.alpha, depthWrite: o.alpha >= 1,
  });
  const points = new THREE.Points(geom, mat);
  points.matrixAutoUpdate = false;
  points.frustumCulled = false;
  return points;
}

// Free a THREE.Points (or any object with geometry and material).
export function disposePoints(obj) {
  if (obj.geometry) obj.geometry.dispose();
  if (obj.material) obj.material.dispose();
  obj.removeFromParent();
}
