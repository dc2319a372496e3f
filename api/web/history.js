// A class's score history: GET /memory/history?class=IRI gives its events, oldest first
// ({time, kind, score, level}, score being the raw score ζ, unbounded); drawn with uPlot as the
// raw score (left axis, from 0 to its largest value), the level as steps (right axis) and each event as a mark coloured by its kind, with the latest events as
// a table. A server without the endpoint (404) gets a plain message instead of a chart.
import { element, getJSON } from "./app.js";

const LEVELS = ["WEAK", "LOW", "HIGH"]; // a class's levels (memory_class_scores.rq)
export const KIND_COLOURS = {
  learned: "#1565c0", reinforced: "#2e7d32", retrieved: "#00838f", rescored: "#9e9e9e",
  level: "#6a1b9a", forgotten: "#c62828", restored: "#ef6c00", pinned: "#283593", unpinned: "#8d6e63",
};
const TABLE_ROWS = 8;

function checked(body) {
  if (!body || !Array.isArray(body.events)) throw new Error("the answer has no list of events");
  return body.events
    .map((e, order) => ({ ...e, order, at: Date.parse(e.time) / 1000 }))
    .filter((e) => Number.isFinite(e.at))
    .sort((a, b) => a.at - b.at || a.order - b.order);
}

function chart(events, box) {
  const t = events.map((e) => e.at);
  const score = events.map((e) => (typeof e.score === "number" ? e.score : null));
  const level = events.map((e) => (LEVELS.includes(e.level) ? LEVELS.indexOf(e.level) : null));
  const marks = (u) => {
    const { ctx, bbox } = u;
    const size = 6 * devicePixelRatio;
    ctx.save();
    events.forEach((e, i) => {
      const x = u.valToPos(t[i], "x", true);
      ctx.fillStyle = KIND_COLOURS[e.kind] || "#555";
      ctx.fillRect(x - size / 2, bbox.top + bbox.height - size, size, size);
    });
    ctx.restore();
  };
  const opts = {
    width: 320, height: 170, title: "raw score ζ and level over time",
    series: [
      {},
      { label: "raw score ζ", scale: "score", stroke: "#1565c0", width: 2, spanGaps: true,
        points: { show: true, size: 5 } },
      { label: "level", scale: "level", stroke: "#6a1b9a", dash: [4, 3], spanGaps: true,
        paths: uPlot.paths.stepped({ align: 1 }), value: (u, v) => (v === null ? "-" : LEVELS[v]) },
    ],
    scales: { score: { range: (u, min, max) => [0, Math.max(1, max ?? 0) * 1.1] }, level: { range: [-0.2, 2.2] } },
    axes: [
      {},
      { scale: "score", size: 36 },
      { scale: "level", side: 1, size: 68, splits: () => [0, 1, 2], values: (u, ticks) => ticks.map((v) => LEVELS[v] ?? ""),
        grid: { show: false } },
    ],
    hooks: { draw: [marks] },
  };
  requestAnimationFrame(() => {
    opts.width = Math.max(240, Math.min(360, box.clientWidth || opts.width));
    box.uplot = new uPlot(opts, [t, score, level], box);
    box.dataset.drawn = "true";
  });
}

function legend(events) {
  const counts = new Map();
  for (const e of events) counts.set(e.kind, (counts.get(e.kind) || 0) + 1);
  return element("p", { class: "kinds" }, [...counts].map(([kind, n]) =>
    element("span", { class: "kind" }, element("i", { style: `background:${KIND_COLOURS[kind] || "#555"}` }), `${kind} ${n}`)));
}

function table(events) {
  const latest = events.slice(-TABLE_ROWS).reverse();
  return element("table", { class: "events" },
    element("tr", {}, ["time", "event", "raw score ζ", "level"].map((h) => element("th", {}, h))),
    latest.map((e) => element("tr", {},
      element("td", {}, e.time.replace("T", " ").replace(/\.\d+/, "").replace(/\+00:00$|Z$/, " UTC")),
      element("td", {}, e.kind),
      element("td", {}, typeof e.score === "number" ? e.score.toFixed(3) : "-"),
      element("td", { class: e.level ? `level-${e.level}` : "" }, e.level ?? "-"))));
}

function say(box, state, text) {
  box.dataset.history = state;
  box.replaceChildren(element("p", { class: state === "error" ? "error" : "muted history-note" }, text));
}

// The history panel of class `node` ({name, iri}); filled when the answer arrives.
export function historyPanel(node) {
  const box = element("div", { class: "history", id: "class-history" });
  box.dataset.history = "loading";
  box.append(element("p", { class: "muted" }, "Reading the score history…"));
  (async () => {
    let events;
    try {
      events = checked(await getJSON(`/memory/history?class=${encodeURIComponent(node.iri)}`));
    } catch (error) {
      if (error.status === 404) {
        say(box, "missing", `No score history for ${node.name}: this server does not keep one ` +
          "(GET /memory/history answered 404).");
      } else {
        say(box, "error", `The score history could not be read: ${error.message}`);
      }
      return;
    }
    if (!events.length) { say(box, "empty", `No events recorded for ${node.name} yet.`); return; }
    const plot = element("div", { class: "history-chart" });
    box.replaceChildren(plot, legend(events), table(events));
    box.dataset.history = "shown";
    box.dataset.events = String(events.length);
    chart(events, plot);
  })();
  return box;
}
