// Episodes: a timeline by activity with participants, annotation ranges, stored scenes,
// augmentation runs and ratings; an episode's channels with coverage, decimated plots, camera
// frames with a scrubber, and replay controls over /episodes/{id}/streams/replay.
import { element, getJSON, loadScript, request, showBanner, showError } from "./app.js";

let timeline = null, episodes = [], replayAbort = null;
const SHOWN = 200; // episodes drawn on the timeline: the newest

// vis-timeline renders a string content or title as HTML: every user string goes in as the
// text of an element of its own (one per item: the timeline moves it into its DOM).
const text = (value) => element("span", {}, value);

function items() {
  const groups = new Map(), rows = [];
  const group = (name) => {
    if (!groups.has(name)) groups.set(name, { id: name, content: text(name) });
    return name;
  };
  for (const e of episodes) {
    const end = e.end || new Date().toISOString();
    const who = e.participants.length ? " — " + e.participants.join(", ") : "";
    rows.push({ id: `episode:${e.id}`, group: group(e.activity), start: e.begin, end, className: "episode",
      content: text(`${e.activity}${who}`),
      title: text(`${e.id}: ${e.activity} (${e.activity_type ?? "no type"})`) });
    for (const [i, a] of e.annotations.entries()) {
      if (a.start) rows.push({ id: `annotation:${e.id}:${i}`, group: group("annotations"), start: a.start,
        end: a.end || undefined, className: "annotation", content: text(`${a.key}: ${a.value}`), type: a.end ? "range" : "point" });
    }
    for (const s of e.scenes) {
      if (s.created) rows.push({ id: `scene:${s.name}`, group: group("scenes"), start: s.created, type: "point",
        className: "scene", content: text(`${s.name} (${s.cls ?? "?"})`) });
    }
    for (const r of e.runs) {
      if (r.started) rows.push({ id: `run:${e.id}:${r.id}`, group: group("augmentation runs"), start: r.started,
        end: r.ended && r.ended > r.started ? r.ended : undefined, type: r.ended && r.ended > r.started ? "range" : "point",
        className: "run", content: text(`${r.name} v${r.version}`) });
    }
    for (const [i, r] of e.ratings.entries()) {
      rows.push({ id: `rating:${e.id}:${i}`, group: group("ratings"), start: r.time, type: "point",
        className: "rating", content: text(`${r.person}: ${r.value}/10`) });
    }
  }
  return { groups: [...groups.values()], rows };
}

function coverageBar(channel) {
  const top = Math.max(1, ...channel.coverage);
  return element("div", { class: "coverage", title: `${channel.samples} samples` },
    channel.coverage.map((n) => element("span", { style: `opacity:${n ? 0.25 + 0.75 * n / top : 0}` })));
}

function decodeImage(value) {
  const bytes = Uint8Array.from(atob(value.b64), (c) => c.charCodeAt(0));
  const [height, width, channels = 1] = value.shape;
  const rgba = new Uint8ClampedArray(width * height * 4);
  for (let i = 0; i < width * height; i++) {
    for (let c = 0; c < 3; c++) rgba[4 * i + c] = bytes[i * channels + Math.min(c, channels - 1)];
    rgba[4 * i + 3] = 255;
  }
  return new ImageData(rgba, width, height);
}

function paint(canvas, value) {
  const image = decodeImage(value);
  canvas.width = image.width; canvas.height = image.height;
  canvas.getContext("2d").putImageData(image, 0, 0);
  canvas.dataset.painted = String(Number(canvas.dataset.painted || 0) + 1);
}

// Read NDJSON frames from the replay endpoint, calling onFrame for each, until done or aborted.
async function replay(id, params, onFrame, signal) {
  const answer = await request(`/episodes/${encodeURIComponent(id)}/streams/replay?${params}`, { signal });
  if (!answer.ok) throw new Error(`replay: ${answer.status}`);
  const reader = answer.body.getReader();
  const decoder = new TextDecoder();
  let buffer = "";
  for (;;) {
    const { value, done } = await reader.read();
    if (done) break;
    buffer += decoder.decode(value, { stream: true });
    let newline;
    while ((newline = buffer.indexOf("\n")) >= 0) {
      const line = buffer.slice(0, newline); buffer = buffer.slice(newline + 1);
      if (line && onFrame(JSON.parse(line)) === false) { reader.cancel(); return; }
    }
  }
}

async function plotChannel(id, channel, box) {
  const data = await getJSON(`/views/episodes/${encodeURIComponent(id)}/plot?channel=${encodeURIComponent(channel.name)}&points=2000`);
  const palette = ["#1565c0", "#c62828", "#2e7d32", "#6a1b9a", "#ef6c00", "#00838f"];
  const opts = { width: 520, height: 200, title: `${channel.name} (${data.samples} samples, ${data.t.length} points)`,
    scales: { x: { time: false } }, axes: [{ label: "s" }, {}],
    series: [{ label: "t (s)" }, ...data.series.map((name, i) => ({ label: name, stroke: palette[i % palette.length] }))] };
  const holder = element("div", { class: "plot", "data-channel": channel.name, "data-points": String(data.t.length) });
  box.append(holder);
  return new uPlot(opts, [data.t, ...data.values], holder);
}

async function select(id) {
  const panel = document.getElementById("episode-detail");
  if (replayAbort) replayAbort.abort();
  const episode = episodes.find((e) => e.id === id);
  if (!episode) return;
  const header = element("div", {}, element("h2", {}, `${episode.activity} (${episode.id})`),
    element("p", {}, `${episode.begin} → ${episode.end ?? "running"} · ${episode.participants.join(", ") || "no participants"}`));
  if (!episode.channels) {
    panel.replaceChildren(header, element("p", { class: "muted" }, "No stream was recorded in this episode."));
    panel.dataset.episode = id;
    return;
  }
  let list;
  try { list = await getJSON(`/views/episodes/${encodeURIComponent(id)}/channels`); }
  catch (error) { showError(panel, error); return; }
  const table = element("table", { class: "channels" },
    element("tr", {}, ["channel", "kind", "samples", "coverage", "first (s)", "last (s)"].map((h) => element("th", {}, h))),
    list.channels.map((c) => element("tr", {}, element("td", {}, c.name), element("td", {}, c.kind),
      element("td", {}, c.samples), element("td", {}, coverageBar(c)),
      element("td", {}, c.first_s?.toFixed(2) ?? "-"), element("td", {}, c.last_s?.toFixed(2) ?? "-"))));
  const plots = element("div", { class: "plots" });
  const cameraBox = element("div", { class: "camera" });
  const position = element("span", { class: "position" }, "frame -");
  const seek = element("input", { type: "range", min: "1", max: String(list.frames), value: "1", id: "replay-seek" });
  const speed = element("select", { id: "replay-speed" }, ["0.5", "1", "2", "5", "10"].map((s) =>
    element("option", s === "1" ? { value: s, selected: "" } : { value: s }, `${s}×`)));
  const play = element("button", { id: "replay-play" }, "Play");
  const stop = element("button", { id: "replay-stop" }, "Stop");
  panel.replaceChildren(header, table,
    element("div", { class: "replay" }, "Replay", play, stop, speed, "seek", seek, position), plots, cameraBox);
  panel.dataset.episode = id;
  const charts = [];
  for (const c of list.channels.filter((c) => c.numeric)) charts.push(await plotChannel(id, c, plots));
  const cameras = {};
  for (const c of list.channels.filter((c) => c.image)) {
    const frames = await getJSON(`/views/episodes/${encodeURIComponent(id)}/frames?channel=${encodeURIComponent(c.name)}`);
    const canvas = element("canvas", { "data-channel": c.name });
    const scrub = element("input", { type: "range", min: "0", max: String(Math.max(0, frames.frames.length - 1)), value: "0", class: "scrubber" });
    const caption = element("span", {}, `${c.name}: frame ${frames.frames[0] ?? "-"}`);
    cameras[c.name] = canvas;
    const showFrame = async () => {
      const frame = frames.frames[Number(scrub.value)];
      caption.textContent = `${c.name}: frame ${frame}`;
      await replay(id, new URLSearchParams({ mode: "frames", start_frame: frame, channels: c.name }),
        (line) => { for (const s of line.samples) if (s.provider === c.name) paint(canvas, s.value); return false; });
    };
    scrub.addEventListener("input", () => showFrame().catch(showBanner));
    cameraBox.append(element("div", {}, caption), canvas, element("div", {}, scrub));
    if (frames.frames.length) await showFrame();
  }
  const startNs = list.start_ns;
  play.addEventListener("click", async () => {
    if (replayAbort) replayAbort.abort();
    replayAbort = new AbortController();
    const params = new URLSearchParams({ mode: "realtime", speed: speed.value, start_frame: seek.value });
    try {
      await replay(id, params, (line) => {
        seek.value = String(line.frame);
        position.textContent = `frame ${line.frame} · ${((line.time_ns - startNs) / 1e9).toFixed(2)} s`;
        const t = (line.time_ns - startNs) / 1e9;
        for (const chart of charts) {
          const left = chart.valToPos(t, "x");
          if (Number.isFinite(left)) chart.setCursor({ left, top: 10 });
        }
        for (const s of line.samples) if (cameras[s.provider]) paint(cameras[s.provider], s.value);
      }, replayAbort.signal);
    } catch (error) { if (error.name !== "AbortError") showBanner(error); }
  });
  stop.addEventListener("click", () => replayAbort && replayAbort.abort());
}

export async function start() {
  await loadScript("vendor/vis-timeline-graph2d.min.js"); // 0.5 MB: only for this view
  const page = await getJSON(`/views/episodes?limit=${SHOWN}&newest=true`);
  episodes = page.episodes;
  const { groups, rows } = items();
  const container = document.getElementById("timeline");
  if (page.total > episodes.length) {
    container.before(element("p", { class: "muted", id: "timeline-note" },
      `Showing the newest ${episodes.length} of ${page.total} episodes.`));
  }
  container.dataset.episodes = String(episodes.length);
  timeline = new vis.Timeline(container, new vis.DataSet(rows), new vis.DataSet(groups),
    { stack: true, zoomKey: "ctrlKey", orientation: "top", margin: { item: 6 } });
  timeline.on("select", ({ items: chosen }) => {
    const first = chosen.find((i) => i.startsWith("episode:"));
    if (first) select(first.slice("episode:".length));
  });
  timeline.on("changed", () => { container.dataset.drawn = String(container.querySelectorAll(".vis-item").length); });
}

export async function show(args) {
  timeline.redraw();
  timeline.fit({ animation: false });
  if (args[0]) { timeline.setSelection([`episode:${args[0]}`]); await select(args[0]); }
}
