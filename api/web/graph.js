// The memory graph: classes as nodes sized by score and coloured by level, direct subclass
// edges top-down by complexity; a class's detail with its score history and pin / restore.
import { directive, element, getJSON, loadScript, showBanner, showError } from "./app.js";
import { historyPanel } from "./history.js";

const COLOURS = { HIGH: "#2e7d32", LOW: "#f9a825", WEAK: "#c62828" };
const DAGRE_LIMIT = 300; // above this many nodes, rows by complexity (dagre is too slow there)
let cy = null;
let nodes = [];

function layoutOptions(count) {
  if (count <= DAGRE_LIMIT) {
    return { name: "dagre", rankDir: "TB", nodeSep: 18, rankSep: 60, animate: false, fit: true };
  }
  // Large memories: one row per complexity, simplest on top, placed without a layout pass.
  const rows = new Map();
  for (const node of nodes) {
    if (!rows.has(node.complexity)) rows.set(node.complexity, []);
    rows.get(node.complexity).push(node.name);
  }
  const position = {};
  [...rows.keys()].sort((a, b) => a - b).forEach((complexity, row) => {
    rows.get(complexity).forEach((name, column) => { position[name] = { x: column * 70, y: row * 120 }; });
  });
  return { name: "preset", positions: (n) => position[n.id()], fit: true, animate: false };
}

function elements() {
  const present = new Set(nodes.map((n) => n.name));
  const out = nodes.map((n) => ({
    group: "nodes",
    data: { id: n.name, size: 18 + 42 * n.score, colour: COLOURS[n.level] || "#888" },
    classes: [n.pinned ? "pinned" : "", n.forgotten ? "forgotten" : ""].join(" ").trim(),
  }));
  for (const n of nodes) {
    for (const parent of n.parents) {
      if (present.has(parent)) out.push({ group: "edges", data: { id: `${parent}>${n.name}`, source: parent, target: n.name } });
    }
  }
  return out;
}

// Memories beyond this many classes are drawn by a plain canvas overview (rows by complexity,
// simplest on top): cytoscape needs tens of seconds for 10,000 nodes here. ?overview forces it.
const OVERVIEW_LIMIT = new URLSearchParams(location.search).has("overview") ? 0 : 2000;
let overview = null;

function overviewLayout() {
  const rows = new Map();
  for (const node of nodes) {
    if (!rows.has(node.complexity)) rows.set(node.complexity, []);
    rows.get(node.complexity).push(node);
  }
  const keys = [...rows.keys()].sort((a, b) => a - b);
  const widest = Math.max(...keys.map((k) => rows.get(k).length));
  const placed = new Map();
  keys.forEach((k, row) => {
    const members = rows.get(k);
    members.forEach((node, column) => {
      placed.set(node.name, { node, x: (column + 0.5) * widest / members.length, y: row + 0.5 });
    });
  });
  return { placed, width: widest, height: keys.length };
}

// Edges as one-pixel lines blended straight into the canvas's pixels: tens of thousands of
// anti-aliased strokes cost the rasteriser most of a second, this a few tens of milliseconds.
const EDGE = [120, 130, 140], EDGE_ALPHA = 0.22;
const BLEND = EDGE.map((c) => Uint8Array.from({ length: 256 }, (_, v) => Math.round(v + (c - v) * EDGE_ALPHA)));

function clip(x0, y0, x1, y1, w, h) { // Liang-Barsky against [0, w-1] x [0, h-1]
  let t0 = 0, t1 = 1;
  const dx = x1 - x0, dy = y1 - y0;
  for (const [p, q] of [[-dx, x0], [dx, w - 1 - x0], [-dy, y0], [dy, h - 1 - y0]]) {
    if (p === 0) { if (q < 0) return null; continue; }
    const t = q / p;
    if (p < 0) { if (t > t1) return null; if (t > t0) t0 = t; } else { if (t < t0) return null; if (t < t1) t1 = t; }
  }
  return [x0 + t0 * dx, y0 + t0 * dy, x0 + t1 * dx, y0 + t1 * dy];
}

function drawEdges(g, w, h, segments) { // onto a white canvas
  const image = g.createImageData(w, h), px = image.data;
  px.fill(255);
  const [r, gr, b] = BLEND;
  for (let i = 0; i < segments.length; i += 4) {
    const c = clip(segments[i], segments[i + 1], segments[i + 2], segments[i + 3], w, h);
    if (!c) continue;
    let x = Math.round(c[0]), y = Math.round(c[1]);
    const x1 = Math.round(c[2]), y1 = Math.round(c[3]);
    const dx = Math.abs(x1 - x), dy = -Math.abs(y1 - y), stepX = x < x1 ? 1 : -1, stepY = y < y1 ? 1 : -1;
    let error = dx + dy;
    for (;;) { // Bresenham
      const k = 4 * (y * w + x);
      px[k] = r[px[k]]; px[k + 1] = gr[px[k + 1]]; px[k + 2] = b[px[k + 2]];
      if (x === x1 && y === y1) break;
      const e2 = 2 * error;
      if (e2 >= dy) { error += dy; x += stepX; }
      if (e2 <= dx) { error += dx; y += stepY; }
    }
  }
  g.putImageData(image, 0, 0);
}

// Nodes are drawn at once; the edges (most of the drawing time at 10,000 classes) follow in a
// later task, after a pause in zooming and panning, under the nodes again.
let edgeTimer = null;

function drawOverview(delay = 0) {
  paintOverview(false);
  clearTimeout(edgeTimer);
  delete overview.canvas.dataset.edgesDrawn;
  const edges = () => {
    paintOverview(true);
    performance.mark("graph-edges");
    overview.canvas.dataset.edgesDrawn = "true";
  };
  // after the frame showing the nodes (a task queued from a frame callback runs after it)
  requestAnimationFrame(() => { clearTimeout(edgeTimer); edgeTimer = setTimeout(edges, delay); });
}

function paintOverview(withEdges) {
  const { canvas, layout, view } = overview;
  // A CPU-backed canvas: its pixels are written directly (the edges), with no GPU round trip.
  const g = canvas.getContext("2d", { willReadFrequently: true });
  const w = canvas.width, h = canvas.height;
  g.fillStyle = "#ffffff"; g.fillRect(0, 0, w, h);
  const sx = (x) => view.x + x * view.scale * w / layout.width;
  const sy = (y) => view.y + y * view.scale * h / layout.height;
  const query = matching !== null;
  if (withEdges) {
    const segments = [];
    for (const { node, x, y } of layout.placed.values()) {
      for (const parent of node.parents) {
        const p = layout.placed.get(parent);
        if (p) segments.push(sx(p.x), sy(p.y), sx(x), sy(y));
      }
    }
    drawEdges(g, w, h, segments);
  }
  const unit = Math.min(view.scale * w / layout.width, view.scale * h / layout.height);
  // Nodes go into one path per colour and opacity (a few fills, not one per node); nodes a few
  // pixels wide are squares, which rasterise far faster than circles and look the same.
  let matches = 0;
  const groups = new Map(), outlined = [];
  for (const { node, x, y } of layout.placed.values()) {
    const hit = query && matching.has(node.name);
    if (hit) matches += 1;
    const alpha = node.forgotten ? 0.45 : query && !hit ? 0.15 : 1;
    const colour = COLOURS[node.level] || "#888";
    const key = `${colour}|${alpha}`;
    if (!groups.has(key)) groups.set(key, { colour, alpha, items: [] });
    const r = Math.max(1.5, unit * (0.15 + 0.3 * node.score));
    groups.get(key).items.push(sx(x), sy(y), r);
    if (node.pinned || hit || node.name === overview.selected) outlined.push([node, sx(x), sy(y), r]);
  }
  for (const { colour, alpha, items } of groups.values()) {
    g.globalAlpha = alpha; g.fillStyle = colour; g.beginPath();
    for (let i = 0; i < items.length; i += 3) {
      const px = items[i], py = items[i + 1], r = items[i + 2];
      if (r < 3) { g.rect(px - r, py - r, 2 * r, 2 * r); } else { g.moveTo(px + r, py); g.arc(px, py, r, 0, 2 * Math.PI); }
    }
    g.fill();
  }
  g.globalAlpha = 1; g.lineWidth = 2;
  for (const [node, px, py, r] of outlined) {
    g.strokeStyle = node.name === overview.selected ? "#000" : "#1565c0";
    g.beginPath(); g.arc(px, py, r, 0, 2 * Math.PI); g.stroke();
  }
  g.globalAlpha = 1;
  document.getElementById("graph-count").dataset.matches = String(matches);
  overview.screen = (x, y) => [sx(x), sy(y)];
  if (layout.placed.size <= 200) { // where each class is drawn, for scripts and tests
    overview.canvas.dataset.positions = JSON.stringify([...layout.placed.values()].map(
      ({ node, x, y }) => ({ name: node.name, x: sx(x), y: sy(y) })));
  }
}

function showOverview() {
  const box = document.getElementById("cy");
  if (!overview) {
    const canvas = element("canvas", { id: "graph-overview" });
    canvas.style.cssText = "position:absolute;inset:0;z-index:10;background:#fff";
    box.append(canvas);
    overview = { canvas, view: { x: 0, y: 0, scale: 1 }, selected: null };
    canvas.addEventListener("wheel", (e) => {
      e.preventDefault();
      const f = e.deltaY < 0 ? 1.25 : 0.8, v = overview.view;
      v.x = e.offsetX - (e.offsetX - v.x) * f; v.y = e.offsetY - (e.offsetY - v.y) * f; v.scale *= f;
      drawOverview(150);
    }, { passive: false });
    let drag = null;
    canvas.addEventListener("mousedown", (e) => { drag = { x: e.offsetX, y: e.offsetY, moved: false }; });
    canvas.addEventListener("mousemove", (e) => {
      if (!drag) return;
      overview.view.x += e.offsetX - drag.x; overview.view.y += e.offsetY - drag.y;
      drag.moved = drag.moved || Math.abs(e.offsetX - drag.x) + Math.abs(e.offsetY - drag.y) > 2;
      drag.x = e.offsetX; drag.y = e.offsetY; drawOverview(150);
    });
    canvas.addEventListener("mouseup", (e) => {
      const moved = drag && drag.moved; drag = null;
      if (moved) return;
      let best = null, distance = 12 * 12;
      for (const { node, x, y } of overview.layout.placed.values()) {
        const [px, py] = overview.screen(x, y);
        const d = (px - e.offsetX) ** 2 + (py - e.offsetY) ** 2;
        if (d < distance) { best = node; distance = d; }
      }
      if (best) { overview.selected = best.name; drawOverview(); select(best.name); }
    });
  }
  box.style.position = "relative";
  overview.canvas.width = box.clientWidth; overview.canvas.height = box.clientHeight;
  overview.canvas.hidden = false;
  overview.layout = overviewLayout();
  drawOverview();
}

async function load() {
  const trash = document.getElementById("graph-trash").checked;
  performance.mark("graph-load");
  const page = await getJSON(`/views/classes?trash=${trash}&relations=false`);
  performance.mark("graph-fetched");
  nodes = page.classes;
  document.getElementById("graph-count").textContent =
    `${page.total} classes${trash ? " (with the trash)" : ""}`;
  if (nodes.length > OVERVIEW_LIMIT) {
    if (cy) cy.elements().remove();
    showOverview();
    performance.mark("graph-drawn");
    requestAnimationFrame(() => performance.mark("graph-frame")); // the frame showing them
    document.getElementById("cy").dataset.nodes = String(nodes.length);
    document.getElementById("cy").dataset.edges = String(nodes.reduce((n, c) => n + c.parents.length, 0));
    return;
  }
  await graph();
  if (overview) overview.canvas.hidden = true;
  const big = nodes.length > DAGRE_LIMIT;
  cy.startBatch();
  cy.elements().remove();
  cy.style(styles(big));
  cy.add(elements());
  cy.endBatch();
  performance.mark("graph-added");
  cy.layout(layoutOptions(nodes.length)).run();
  performance.mark("graph-drawn");
  requestAnimationFrame(() => performance.mark("graph-frame"));
  applySearch();
  document.getElementById("cy").dataset.nodes = String(cy.nodes().length);
  document.getElementById("cy").dataset.edges = String(cy.edges().length);
}

// The classes matching the search box (names, or relations such as "sphere isAboveOf"), asked
// of the server, which holds every class's relations; null when the box is empty.
let matching = null, searchTimer = null;

async function search() {
  const query = document.getElementById("graph-search").value.trim();
  const trash = document.getElementById("graph-trash").checked;
  if (!query) {
    matching = null;
  } else {
    const params = new URLSearchParams({ q: query, trash, relations: "false", limit: "50000" });
    const page = await getJSON(`/views/classes?${params}`);
    matching = new Set(page.classes.map((c) => c.name));
  }
  applySearch();
}

function applySearch() {
  if (overview && !overview.canvas.hidden) { drawOverview(); return; }
  cy.batch(() => {
    cy.nodes().removeClass("match dim");
    if (matching === null) return;
    cy.nodes().forEach((node) => node.addClass(matching.has(node.id()) ? "match" : "dim"));
  });
  document.getElementById("graph-count").dataset.matches = String(matching ? cy.nodes(".match").length : 0);
}

function counters(node, detail) {
  const rows = [
    ["score (normalised)", node.score.toFixed(3)],
    ["level", element("span", { class: `level-${node.level}` }, node.level)],
    ["stored level", detail.stored_level ?? "none yet"],
    ["complexity", node.complexity],
    ["stored", node.store_count], ["retrieved", node.retrieve_count],
    ["scenes", node.items], ["weak passes", detail.consecutive_weak ?? "-"],
    ["created", detail.created ?? "-"], ["last accessed", detail.last_accessed ?? "-"],
    ["parents", node.parents.join(", ") || "-"], ["children", detail.children.join(", ") || "-"],
  ];
  return element("table", { class: "counters" },
    rows.map(([k, v]) => element("tr", {}, element("th", {}, k), element("td", {}, v))));
}

async function select(name) {
  const panel = document.getElementById("class-detail");
  try {
    const detail = await getJSON(`/views/classes/${encodeURIComponent(name)}`);
    const node = detail.node;
    const message = element("p", { class: "action-message" });
    const act = async (command, args) => {
      try {
        await directive("MEMORY", command, "", args);
        message.textContent = `${command.toLowerCase()}: done`;
        await load();
        await select(name);
      } catch (error) { message.textContent = error.message; message.className = "error"; }
    };
    const actions = node.forgotten
      ? [element("button", { id: "restore", onclick: () => act("RESTORE", [node.iri]) }, "Restore from the trash")]
      : [element("button", { id: "pin", onclick: () => act(node.pinned ? "UNPIN" : "PIN", [node.iri]) },
        node.pinned ? "Unpin" : "Pin (never forget)")];
    panel.replaceChildren(
      element("h2", {}, node.name, node.pinned ? " (pinned)" : "", node.forgotten ? " (forgotten)" : ""),
      element("p", { class: "words" }, detail.words),
      counters(node, detail), historyPanel(node),
      element("h3", {}, "Stored scenes"),
      element("ul", { class: "scenes" }, detail.scenes.length
        ? detail.scenes.map((s) => element("li", {},
          element("a", { href: `#scene/${encodeURIComponent(s.name)}` }, s.name), ` ${s.created ?? ""}`))
        : element("li", { class: "muted" }, "none")),
      element("div", { class: "actions" }, actions), message,
    );
    panel.dataset.selected = node.name;
  } catch (error) { showError(panel, error); }
}

// Large memories draw without labels (but on the selected and matching classes) and with plain
// edges: text and arrow heads for 10,000 classes would take seconds to draw.
function styles(big) {
  return [
    { selector: "node", style: { width: "data(size)", height: "data(size)", "background-color": "data(colour)",
      label: big ? "" : "data(id)", "font-size": 9, "min-zoomed-font-size": 7, "text-valign": "bottom" } },
    { selector: "node.pinned", style: { "border-width": 4, "border-color": "#1565c0" } },
    { selector: "node.forgotten", style: { "border-width": 2, "border-style": "dashed", "border-color": "#555", opacity: 0.45 } },
    { selector: "node.match", style: { label: "data(id)", "overlay-color": "#1565c0", "overlay-opacity": 0.25, "overlay-padding": 6 } },
    { selector: "node.dim", style: { opacity: 0.15 } },
    { selector: "node:selected", style: { label: "data(id)", "border-width": 4, "border-color": "#000" } },
    { selector: "edge", style: big
      ? { width: 0.6, "line-color": "#c3c9cf", "curve-style": "haystack" }
      : { width: 1.2, "line-color": "#9aa4ae", "target-arrow-shape": "triangle",
        "target-arrow-color": "#9aa4ae", "curve-style": "straight", "arrow-scale": 0.7 } },
  ];
}

// cytoscape (and dagre) are loaded and started only for memories small enough to draw with
// them: a memory of 10,000 classes paints its canvas overview without parsing them at all.
async function graph() {
  if (cy) return cy;
  await loadScript("vendor/cytoscape.min.js");
  await loadScript("vendor/cytoscape-dagre.min.js");
  cy = cytoscape({
    container: document.getElementById("cy"),
    hideEdgesOnViewport: true,
    textureOnViewport: true,
    minZoom: 0.02,
    style: styles(false),
  });
  window.engramGraph = cy; // for scripts and tests driving the page
  cy.on("tap", "node", (event) => select(event.target.id()));
  return cy;
}

export async function start() {
  document.getElementById("graph-trash").addEventListener("change", () => load().then(search));
  document.getElementById("graph-search").addEventListener("input", () => {
    clearTimeout(searchTimer);
    searchTimer = setTimeout(() => search().catch(showBanner), 150);
  });
  await load();
}

export async function show() {
  if (cy) cy.resize();
}
