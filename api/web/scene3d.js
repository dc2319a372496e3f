// A stored scene in 3D: primitives as meshes at their stored centres, radii, axes and heights,
// z up, orbit controls, relations as labelled arrows on demand; live mode follows the latest scene
// stored, pushed by the server as server-sent events (/views/scenes/live).
import * as THREE from "three";
import { OrbitControls } from "./vendor/OrbitControls.js";
import { element, getJSON, showError } from "./app.js";

const FALLBACK = { Sphere: 0xf9a825, Cylinder: 0x1565c0, Cone: 0xc62828, Plane: 0x9e9e9e };
const BACKGROUND = 0xeef1f5;
let renderer, camera, scene, controls, content, current = null, live = null;

function colourOf(p) {
  if (!p.colour) return new THREE.Color(FALLBACK[p.kind]);
  return new THREE.Color().setRGB(p.colour[0], p.colour[1], p.colour[2], THREE.SRGBColorSpace);
}

function orient(mesh, axis, from) {
  if (!axis) return;
  const to = new THREE.Vector3(axis[0], axis[1], axis[2]).normalize();
  mesh.quaternion.setFromUnitVectors(from, to);
}

function meshOf(p) {
  const material = new THREE.MeshStandardMaterial({ color: colourOf(p), roughness: 0.6 });
  const radius = p.radius ?? 0.05;
  const height = p.height ?? 2 * radius;
  let mesh;
  if (p.kind === "Sphere") {
    mesh = new THREE.Mesh(new THREE.SphereGeometry(radius, 32, 16), material);
  } else if (p.kind === "Cylinder" || p.kind === "Cone") {
    const geometry = p.kind === "Cylinder"
      ? new THREE.CylinderGeometry(radius, radius, height, 32)
      : new THREE.ConeGeometry(radius, height, 32);
    mesh = new THREE.Mesh(geometry, material);
    orient(mesh, p.axis, new THREE.Vector3(0, 1, 0)); // three's cylinders stand along y
  } else {
    material.side = THREE.DoubleSide;
    material.transparent = true;
    material.opacity = 0.75;
    const size = 2 * (p.radius ?? 0.3);
    mesh = new THREE.Mesh(new THREE.PlaneGeometry(size, size), material);
    orient(mesh, p.axis, new THREE.Vector3(0, 0, 1)); // a plane's normal is its axis
  }
  mesh.position.set(p.centre[0], p.centre[1], p.centre[2]);
  mesh.userData.primitive = p.id;
  return mesh;
}

const LABEL_PX = 24, LABEL_HEIGHT = 0.03; // font size in the texture; label height in metres
const labels = []; // the relation labels drawn, text and widths: on the canvas for scripts and tests

// A relation's label as a sprite, as wide as its text (a fixed-width texture cut long ones off).
function label(text) {
  const canvas = document.createElement("canvas");
  const font = `${LABEL_PX}px sans-serif`;
  const measure = canvas.getContext("2d");
  measure.font = font;
  const textWidth = Math.ceil(measure.measureText(text).width);
  canvas.width = textWidth + LABEL_PX; canvas.height = 2 * LABEL_PX;
  const g = canvas.getContext("2d"); // resizing reset the context's state
  g.fillStyle = "rgba(255,255,255,0.85)"; g.fillRect(0, 0, canvas.width, canvas.height);
  g.fillStyle = "#1f2328"; g.font = font; g.textAlign = "center"; g.textBaseline = "middle";
  g.fillText(text, canvas.width / 2, canvas.height / 2);
  const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(canvas), depthTest: false }));
  sprite.scale.set(LABEL_HEIGHT * canvas.width / canvas.height, LABEL_HEIGHT, 1);
  labels.push({ text, textWidth, canvasWidth: canvas.width });
  return sprite;
}

function arrows(detail) {
  const group = new THREE.Group();
  const centres = Object.fromEntries(detail.primitives.map((p) => [p.id, new THREE.Vector3(...p.centre)]));
  for (const r of detail.relations) {
    const from = centres[r.subject], to = centres[r.object];
    if (!from || !to || from.distanceTo(to) < 1e-6) continue;
    const direction = to.clone().sub(from);
    const length = direction.length();
    group.add(new THREE.ArrowHelper(direction.normalize(), from, length, 0x6a1b9a, 0.03, 0.015));
    const tag = label(`${r.subject} ${r.relation} ${r.object}`);
    tag.position.copy(from.clone().lerp(to, 0.5)).add(new THREE.Vector3(0, 0, 0.02));
    group.add(tag);
  }
  group.name = "relations";
  return group;
}

function frame(detail) {
  const box = new THREE.Box3().setFromObject(content);
  const centre = box.getCenter(new THREE.Vector3());
  const size = Math.max(box.getSize(new THREE.Vector3()).length(), 0.2);
  camera.position.copy(centre).add(new THREE.Vector3(0.25 * size, -1.1 * size, 0.8 * size));
  controls.target.copy(centre);
  controls.update();
}

// Screen positions of the primitives' centres, for whoever checks what is drawn where.
function publishProjection() {
  const canvas = renderer.domElement;
  const points = content.children.filter((m) => m.userData.primitive).map((m) => {
    const v = m.position.clone().project(camera);
    return { id: m.userData.primitive, x: (v.x + 1) / 2 * canvas.clientWidth, y: (1 - v.y) / 2 * canvas.clientHeight };
  });
  canvas.dataset.projected = JSON.stringify(points);
}

function render() {
  renderer.render(scene, camera);
  if (content) publishProjection();
}

function draw(detail) {
  current = detail;
  if (content) scene.remove(content);
  content = new THREE.Group();
  for (const p of detail.primitives) content.add(meshOf(p));
  labels.length = 0;
  if (document.getElementById("scene-relations").checked) content.add(arrows(detail));
  scene.add(content);
  frame(detail);
  render();
  const canvas = renderer.domElement;
  canvas.dataset.scene = detail.scene.name;
  canvas.dataset.primitives = String(detail.primitives.length);
  canvas.dataset.labels = JSON.stringify(labels);
  document.getElementById("scene-info").textContent =
    `${detail.scene.name}: stored as ${detail.scene.cls ?? "?"} at ${detail.scene.created ?? "?"}`;
  document.getElementById("scene-detail").replaceChildren(
    element("h2", {}, detail.scene.name),
    element("p", {}, "class ", element("a", { href: "#graph" }, detail.scene.cls ?? "?"),
      detail.scene.episode ? ` · episode ${detail.scene.episode}` : ""),
    element("table", {}, element("tr", {}, ["id", "kind", "centre", "radius", "height"].map((h) => element("th", {}, h))),
      detail.primitives.map((p) => element("tr", {}, element("td", {}, p.id), element("td", {}, p.kind),
        element("td", {}, p.centre.map((c) => c.toFixed(3)).join(", ")),
        element("td", {}, p.radius?.toFixed(3) ?? "-"), element("td", {}, p.height?.toFixed(3) ?? "-")))),
    element("h3", {}, "Relations"),
    element("ul", {}, detail.relations.map((r) => element("li", {}, `${r.subject} ${r.relation} ${r.object}`))),
  );
}

async function open(name) {
  try {
    draw(await getJSON(name ? `/views/scenes/${encodeURIComponent(name)}` : "/views/scenes/latest"));
  } catch (error) { showError(document.getElementById("scene-detail"), error); }
}

function setLive(on) {
  const canvas = renderer.domElement;
  if (live) live.close();
  live = null;
  delete canvas.dataset.live;
  if (!on) return;
  live = new EventSource("/views/scenes/live");
  live.addEventListener("open", () => { canvas.dataset.live = "open"; });
  live.addEventListener("scene", (event) => {
    const latest = JSON.parse(event.data);
    if (!current || latest.scene.iri !== current.scene.iri) draw(latest);
  });
  // the browser reconnects by itself (the server ends each stream after 15 s)
  live.addEventListener("error", () => { canvas.dataset.live = "reconnecting"; });
}

export async function start() {
  const box = document.getElementById("scene-canvas");
  renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(box.clientWidth, box.clientHeight);
  box.append(renderer.domElement);
  scene = new THREE.Scene();
  scene.background = new THREE.Color(BACKGROUND);
  camera = new THREE.PerspectiveCamera(45, box.clientWidth / box.clientHeight, 0.01, 100);
  camera.up.set(0, 0, 1); // z up, as the memory's frame
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8899aa, 2.0));
  const sun = new THREE.DirectionalLight(0xffffff, 1.5);
  sun.position.set(1, -2, 3);
  scene.add(sun);
  const grid = new THREE.GridHelper(1, 10, 0xb0b8c0, 0xd5dbe0);
  grid.rotation.x = Math.PI / 2; // into the x-y plane
  scene.add(grid, new THREE.AxesHelper(0.1));
  controls = new OrbitControls(camera, renderer.domElement);
  controls.addEventListener("change", render);
  new ResizeObserver(() => {
    if (!box.clientWidth) return;
    renderer.setSize(box.clientWidth, box.clientHeight);
    camera.aspect = box.clientWidth / box.clientHeight;
    camera.updateProjectionMatrix();
    render();
  }).observe(box);
  const select = document.getElementById("scene-select");
  const page = await getJSON("/views/scenes?limit=500");
  select.replaceChildren(element("option", { value: "" }, "the latest scene"),
    ...page.scenes.map((s) => element("option", { value: s.name }, `${s.name} (${s.cls ?? "?"})`)));
  select.addEventListener("change", () => { location.hash = `scene/${encodeURIComponent(select.value)}`; });
  document.getElementById("scene-relations").addEventListener("change", () => current && draw(current));
  document.getElementById("scene-live").addEventListener("change", (e) => setLive(e.target.checked));
}

export async function show(args) {
  const name = args[0] || "";
  document.getElementById("scene-select").value = name;
  await open(name);
}
