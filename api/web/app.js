// Engram's web views: a hash router over four views, and the helpers they share.
// No build step: ES modules served as they are; libraries are vendored under vendor/.

const views = {
  graph: () => import("./graph.js"),
  scene: () => import("./scene3d.js"),
  episodes: () => import("./episodes.js"),
  query: () => import("./query.js"),
};
const started = {};

// fetch, with a network failure (the server stopped, the connection dropped) said in words.
export async function request(url, options = {}) {
  try {
    return await fetch(url, options);
  } catch (error) {
    if (error.name === "AbortError") throw error;
    throw new Error(`the server did not answer ${url.split("?")[0]}: is it still running?`);
  }
}

export async function getJSON(url) {
  const answer = await request(url, { headers: { Accept: "application/json" } });
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
  const answer = await request("/armor_interface_srv", {
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

// The banner over every view: what failed, in words, until the next view or a close.
export function showBanner(error) {
  const banner = document.getElementById("banner");
  banner.querySelector(".message").textContent = String(error?.message || error);
  banner.hidden = false;
}

export function clearBanner() {
  document.getElementById("banner").hidden = true;
}

let pending = 0;

// Show the loading indicator while `work` runs (nested calls share it).
export async function loading(work) {
  const indicator = document.getElementById("loading");
  pending += 1;
  indicator.hidden = false;
  document.body.dataset.loading = "true";
  try {
    return await work();
  } finally {
    pending -= 1;
    if (pending === 0) {
      indicator.hidden = true;
      delete document.body.dataset.loading;
    }
  }
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
  clearBanner();
  await loading(async () => {
    let module;
    try {
      module = await views[view]();
    } catch (error) {
      throw new Error(`the ${view} page could not be loaded from the server: is it still running?`);
    }
    started[view] ??= module.start(); // a failed start keeps saying so until a reload
    await started[view];
    await module.show(rest.map(decodeURIComponent));
  });
  document.body.dataset.view = view;
}

document.getElementById("banner-close").addEventListener("click", clearBanner);
window.addEventListener("unhandledrejection", (event) => showBanner(event.reason));
window.addEventListener("hashchange", () => route().catch(showBanner));
route().catch(showBanner);
