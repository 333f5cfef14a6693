// Frame names as an HTML layer over the canvas, placed in screen space so they never overlap
// (RViz2 draws them where the frames are, and around a robot they pile up). Each label is
// wanted at its frame's projected origin; a label that would cover one already placed moves
// up or down by whole label heights (0, -1, +1, -2, +2, ... rows) to the nearest free slot,
// with a thin leader line to its frame; when no slot within MAX_ROWS is free it is hidden.

const MAX_ROWS = 12;
const GAP = 1;     // px between labels

function overlaps(a, b) {
  return a.x < b.x + b.w + GAP && b.x < a.x + a.w + GAP && a.y < b.y + b.h + GAP && b.y < a.y + a.h + GAP;
}

// items: [{name, x, y, w, h}] (anchor x, y in px; label size w, h). Returns name -> {x, y,
// shifted} (top-left of the label) for the labels placed; the others do not fit.
export function placeLabels(items) {
  const placed = [];
  const out = new Map();
  const sorted = [...items].sort((a, b) => a.y - b.y || a.x - b.x || (a.name < b.name ? -1 : 1));
  for (const it of sorted) {
    const base = { x: it.x + 4, y: it.y - it.h - 2, w: it.w, h: it.h };
    for (let k = 0; k <= 2 * MAX_ROWS; k += 1) {
      const row = k === 0 ? 0 : (k % 2 ? -1 : 1) * Math.ceil(k / 2);
      const rect = { ...base, y: base.y + row * (it.h + GAP) };
      if (!placed.some((p) => overlaps(p, rect))) {
        placed.push(rect);
        out.set(it.name, { x: rect.x, y: rect.y, shifted: row !== 0 });
        break;
      }
    }
  }
  return out;
}

// The HTML layer: one span per frame name, plus an SVG for leader lines.
export function createLabelLayer(container) {
  const layer = document.createElement("div");
  layer.id = "tf-labels";
  const svg = document.createElementNS("http://www.w3.org/2000/svg", "svg");
  svg.setAttribute("class", "leaders");
  layer.append(svg);
  container.append(layer);
  const spans = new Map();   // name -> {el, w, h}

  function span(name) {
    let s = spans.get(name);
    if (!s) {
      const el = document.createElement("span");
      el.className = "tf-label";
      el.dataset.frame = name;
      el.textContent = name;
      layer.append(el);
      s = { el, w: el.offsetWidth, h: el.offsetHeight };
      spans.set(name, s);
    }
    return s;
  }

  // items: [{name, x, y, stale}] anchors in px relative to the container; everything else
  // is hidden. Returns the number of labels that did not fit.
  function update(items) {
    const want = items.map((it) => { const s = span(it.name); return { ...it, w: s.w, h: s.h }; });
    const where = placeLabels(want);
    const lines = [];
    const shown = new Set();
    for (const it of want) {
      const s = spans.get(it.name);
      const p = where.get(it.name);
      if (!p) continue;
      shown.add(it.name);
      s.el.style.transform = `translate(${Math.round(p.x)}px, ${Math.round(p.y)}px)`;
      s.el.classList.toggle("stale", Boolean(it.stale));
      if (p.shifted) {
        const ly = p.y < it.y ? p.y + s.h : p.y;
        lines.push(`<line x1="${it.x}" y1="${it.y}" x2="${p.x}" y2="${ly}"/>`);
      }
    }
    for (const [name, s] of spans) s.el.hidden = !shown.has(name);
    svg.innerHTML = lines.join("");
    return want.length - shown.size;
  }

  return { update, clear: () => update([]) };
}
