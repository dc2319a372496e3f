// Engram's web views: a hash router over four views, and the helpers they share.
// No build step: ES modules served as they are; libraries are vendored under vendor/.

const views = {
  graph: () => import("./graph.js"),
  scene: () => import("./scene3d.js"),
  episodes: () => import("./episodes.js"),
  query: () => import("./query.js"),
};
const started = {};

export async function getJSON(url) {
  const answer = await fetch(url, { headers: { Accept: "application/json" } });
  if (!answer.ok) {
    let detail = answer.statusText;
    try { detail = (await answer.json()).detail || detail; } catch (_) { /* not JSON */ }
    const error = new Error(`${answer.status}: ${detail}`);
    error.status = answer.status;
    throw error;
  }
  return answer.json();
}

const scripts = {};

// A classic script (a vendored library) loaded once, when a view first needs it.
export function loadScript(src) {
  scripts[src] ??= new Promise((resolve, reject) => {
    const tag = document.createElement("script");
    tag.src = src;
    tag.onload = resolve;
    tag.onerror = () => reject(new Error(`could not load ${src}`));
    document.head.append(tag);
  });
  return scripts[src];
}

export function authHeaders() {
  const token = document.getElementById("token").value.trim();
  return token ? { Authorization: `Bearer ${token}` } : {};
}

// One memory directive through the ARMOR interface (pin, unpin, restore), as any client writes.
export async function directive(command, first, second, args) {
  const answer = await fetch("/armor_interface_srv", {
    method: "POST",
    headers: { "Content-Type": "application/json", ...authHeaders() },
    body: JSON.stringify({ armor_request: {
      client_name: "web", reference_name: "engram", command,
      primary_command_spec: first, secondary_command_spec: second, args } }),
  });
  if (answer.status === 401) throw new Error("this server needs its token: enter it at the top right");
  const body = await answer.json();
  if (!answer.ok) throw new Error(body.detail || answer.statusText);
  const response = body.armor_response;
  if (!response.success) throw new Error(response.error_description || "the directive failed");
  return response;
}

export function element(tag, attributes = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attributes)) {
    if (key === "class") node.className = value;
    else if (key.startsWith("on")) node.addEventListener(key.slice(2), value);
    else node.setAttribute(key, value);
  }
  for (const child of children.flat()) {
    if (child !== null && child !== undefined) node.append(child instanceof Node ? child : String(child));
  }
  return node;
}

export function showError(container, error) {
  container.replaceChildren(element("p", { class: "error" }, String(error.message || error)));
}

async function route() {
  const [name, ...rest] = (location.hash.slice(1) || "graph").split("/");
  const view = views[name] ? name : "graph";
  for (const section of document.querySelectorAll(".view")) {
    section.classList.toggle("active", section.id === `view-${view}`);
  }
  for (const link of document.querySelectorAll("nav a")) {
    link.classList.toggle("active", link.dataset.view === view);
  }
  const module = await views[view]();
  if (!started[view]) {
    started[view] = true;
    await module.start();
  }
  await module.show(rest.map(decodeURIComponent));
  document.body.dataset.view = view;
}

window.addEventListener("hashchange", () => route().catch(console.warn));
route().catch(console.warn);
