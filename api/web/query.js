// The SPARQL page over the read-only /sparql endpoint: the project's prefixes, the analyst's
// usual questions, results as a table, CSV download.
import { element, loading, request, showBanner } from "./app.js";

const PREFIXES = `PREFIX engram: <https://w3id.org/engram/ontology#>
PREFIX rdf: <http://www.w3.org/1999/02/22-rdf-syntax-ns#>
PREFIX rdfs: <http://www.w3.org/2000/01/rdf-schema#>
PREFIX owl: <http://www.w3.org/2002/07/owl#>
PREFIX xsd: <http://www.w3.org/2001/XMLSchema#>
PREFIX prov: <http://www.w3.org/ns/prov#>
`;

const EXAMPLES = {
  "The best classes by score": `SELECT ?class ?score ?level WHERE {
  GRAPH <https://w3id.org/engram/graph/memory> {
    ?class engram:score ?score .
    OPTIONAL { ?class engram:level ?level }
  }
} ORDER BY DESC(?score) LIMIT 20`,
  "The last time HyungJin did something": `SELECT ?episode ?activity ?begin WHERE {
  ?episode a engram:Episode ; engram:activityName ?activity ; prov:startedAtTime ?begin ;
           prov:wasAssociatedWith/rdfs:label "HyungJin" .
} ORDER BY DESC(?begin) LIMIT 1`,
  "Scenes with a sphere": `SELECT ?scene ?class ?created WHERE {
  GRAPH <https://w3id.org/engram/graph/episodic> {
    ?scene a engram:ExperiencedScene ; a ?class ; engram:created ?created ;
           engram:hasPrimitive/a engram:Sphere .
    FILTER (?class != engram:ExperiencedScene)
  }
} ORDER BY DESC(?created) LIMIT 50`,
  "What is in the trash": `SELECT ?item ?forgotten WHERE {
  GRAPH <https://w3id.org/engram/graph/trash> { ?item engram:forgottenAt ?forgotten }
} ORDER BY DESC(?forgotten)`,
  "Triples per graph": `SELECT ?graph (COUNT(*) AS ?triples) WHERE { GRAPH ?graph { ?s ?p ?o } }
GROUP BY ?graph ORDER BY DESC(?triples)`,
};

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
  const examples = document.getElementById("query-examples");
  examples.replaceChildren(...Object.keys(EXAMPLES).map((name) => element("option", { value: name }, name)));
  const load = () => { document.getElementById("query-text").value = PREFIXES + EXAMPLES[examples.value]; };
  examples.addEventListener("change", load);
  load();
  document.getElementById("query-run").addEventListener("click", () => loading(run));
  document.getElementById("query-csv").addEventListener("click", () => loading(csv));
}

export async function show() {}
