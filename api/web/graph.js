// The memory graph: classes as nodes sized by score and coloured by level, direct subclass
// edges top-down by complexity; a class's detail with pin / restore.
import { directive, element, getJSON, showError } from "./app.js";

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

async function load() {
  const trash = document.getElementById("graph-trash").checked;
  const page = await getJSON(`/views/classes?trash=${trash}`);
  nodes = page.classes;
  document.getElementById("graph-count").textContent =
    `${page.total} classes${trash ? " (with the trash)" : ""}`;
  const big = nodes.length > DAGRE_LIMIT;
  cy.startBatch();
  cy.elements().remove();
  cy.style(styles(big));
  cy.add(elements());
  cy.endBatch();
  cy.layout(layoutOptions(nodes.length)).run();
  applySearch();
  document.getElementById("cy").dataset.nodes = String(cy.nodes().length);
  document.getElementById("cy").dataset.edges = String(cy.edges().length);
}

function applySearch() {
  const query = document.getElementById("graph-search").value.trim().toLowerCase();
  cy.batch(() => {
    cy.nodes().removeClass("match dim");
    if (!query) return;
    const matching = new Set(nodes.filter((n) => n.name.toLowerCase().includes(query)
      || n.relations.some((r) => r.toLowerCase().includes(query))).map((n) => n.name));
    cy.nodes().forEach((node) => node.addClass(matching.has(node.id()) ? "match" : "dim"));
  });
  const count = cy.nodes(".match").length;
  document.getElementById("graph-count").dataset.matches = String(count);
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

function historyChart(detail) {
  const box = element("div", { class: "history" });
  const points = detail.history;
  if (!points.length) return box;
  const t = points.map((p) => Date.parse(p.time) / 1000);
  const s = points.map((p) => p.score);
  const opts = { width: 340, height: 140, title: "normalised score over time",
    series: [{}, { label: "score", stroke: "#1565c0", points: { show: true, size: 6 } }],
    scales: { y: { range: [0, 1] } } };
  requestAnimationFrame(() => new uPlot(opts, [t, s], box));
  return box;
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
      element("h2", {}, node.name, node.pinned ? " 📌" : "", node.forgotten ? " (forgotten)" : ""),
      element("p", { class: "words" }, detail.words),
      counters(node, detail), historyChart(detail),
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

export async function start() {
  cy = cytoscape({
    container: document.getElementById("cy"),
    hideEdgesOnViewport: true,
    textureOnViewport: true,
    minZoom: 0.02,
    style: styles(false),
  });
  window.engramGraph = cy; // for scripts and tests driving the page
  cy.on("tap", "node", (event) => select(event.target.id()));
  document.getElementById("graph-trash").addEventListener("change", () => load());
  document.getElementById("graph-search").addEventListener("input", applySearch);
  await load();
}

export async function show() {
  cy.resize();
}
