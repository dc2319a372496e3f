// The SPARQL page over the read-only /sparql endpoint: the project's prefixes, the analyst's
// usual questions, results as a table, CSV download.
import { element, getJSON, loading, request, showBanner } from "./app.js";

// The prefixes and the examples live in query-examples.json: a test runs each example against
// the demo's memory.
let PREFIXES = "", EXAMPLES = {};

function text() { return document.getElementById("query-text").value; }

async function ask(accept) {
  const answer = await request("/sparql", {
    method: "POST",
    headers: { "Content-Type": "application/x-www-form-urlencoded", Accept: accept },
    body: new URLSearchParams({ query: text() }),
  });
  if (!answer.ok) {
    let detail = answer.statusText;
    try { detail = (await answer.json()).detail || detail; } catch (_) { detail = await answer.text(); }
    throw new Error(`${answer.status}: ${detail}`);
  }
  return answer;
}

function cell(term) {
  if (!term) return "";
  if (term.type === "uri") return term.value.replace("https://w3id.org/engram/ontology#", "engram:");
  return term.value;
}

async function run() {
  const info = document.getElementById("query-info");
  const box = document.getElementById("query-results");
  info.textContent = "running…";
  try {
    const started = performance.now();
    const body = await (await ask("application/sparql-results+json")).json();
    if (body.boolean !== undefined) { box.replaceChildren(element("p", {}, String(body.boolean))); return; }
    const vars = body.head.vars;
    const rows = body.results.bindings;
    box.replaceChildren(element("table", { class: "results" },
      element("tr", {}, vars.map((v) => element("th", {}, v))),
      rows.map((row) => element("tr", {}, vars.map((v) => element("td", {}, cell(row[v])))))));
    info.textContent = `${rows.length} rows in ${Math.round(performance.now() - started)} ms`;
    box.dataset.rows = String(rows.length);
  } catch (error) {
    info.textContent = "";
    box.replaceChildren(element("p", { class: "error" }, error.message));
    showBanner(error);
  }
}

async function csv() {
  try {
    const blob = await (await ask("text/csv")).blob();
    const link = element("a", { href: URL.createObjectURL(blob), download: "engram-query.csv" });
    document.body.append(link);
    link.click();
    link.remove();
  } catch (error) {
    document.getElementById("query-results").replaceChildren(element("p", { class: "error" }, error.message));
    showBanner(error);
  }
}

export async function start() {
  ({ prefixes: PREFIXES, examples: EXAMPLES } = await getJSON("query-examples.json"));
  const examples = document.getElementById("query-examples");
  examples.replaceChildren(...Object.keys(EXAMPLES).map((name) => element("option", { value: name }, name)));
  const load = () => { document.getElementById("query-text").value = PREFIXES + EXAMPLES[examples.value]; };
  examples.addEventListener("change", load);
  load();
  document.getElementById("query-run").addEventListener("click", () => loading(run));
  document.getElementById("query-csv").addEventListener("click", () => loading(csv));
}

export async function show() {}
