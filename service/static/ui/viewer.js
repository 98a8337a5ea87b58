// The 3-D view: three.js, orbit controls, the GLB of a result (GET /jobs/{id}/results?f=glb)
// shown by kind: a registration's moved source over its target, a deformation with its
// handles, an unwrap with a checker texture beside its flat UV layout, an interpolation
// with a time slider, scatter plots of embeddings and layouts with the index under the
// pointer. Geometry arrives binary (GLB), never as JSON lists.

import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";

export const BACKGROUND = 0x20242c;
const HANDLE_COLOR = 0xe8334a;
const GIVEN_COLOR = 0x9aa3b2;

function checkerTexture(n = 8, size = 512) {
  const data = new Uint8Array(size * size * 4);
  const cell = size / n;
  for (let y = 0; y < size; y++) {
    for (let x = 0; x < size; x++) {
      const on = (Math.floor(x / cell) + Math.floor(y / cell)) % 2 === 0;
      const i = (y * size + x) * 4;
      const [r, g, b] = on ? [235, 235, 235] : [60, 110, 200];
      data[i] = r; data[i + 1] = g; data[i + 2] = b; data[i + 3] = 255;
    }
  }
  const t = new THREE.DataTexture(data, size, size, THREE.RGBAFormat);
  t.colorSpace = THREE.SRGBColorSpace;
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.magFilter = THREE.NearestFilter;
  t.generateMipmaps = true;
  t.minFilter = THREE.LinearMipmapLinearFilter;
  t.needsUpdate = true;
  return t;
}

function discTexture() {
  const c = document.createElement("canvas");
  c.width = c.height = 64;
  const g = c.getContext("2d");
  g.fillStyle = "#fff";
  g.beginPath();
  g.arc(32, 32, 30, 0, 2 * Math.PI);
  g.fill();
  const t = new THREE.CanvasTexture(c);
  t.colorSpace = THREE.SRGBColorSpace;
  return t;
}

/** (n, d) rows of a JSON value or decoded typed array, as 3-D positions (z = 0 for 2-D). */
export function positions(value) {
  if (!value) return null;
  if (value.vertices) return positions(value.vertices);
  if (value.data && value.shape) {
    const [n, d = 1] = value.shape;
    const out = new Float32Array(n * 3);
    for (let i = 0; i < n; i++) for (let k = 0; k < Math.min(d, 3); k++) out[i * 3 + k] = Number(value.data[i * d + k]);
    return out;
  }
  if (!Array.isArray(value) || !value.length) return null;
  const rows = Array.isArray(value[0]) ? value : value.map((v) => [v]);
  if (!rows.every((r) => Array.isArray(r) && r.every((x) => typeof x === "number"))) return null;
  const out = new Float32Array(rows.length * 3);
  rows.forEach((r, i) => { for (let k = 0; k < Math.min(r.length, 3); k++) out[i * 3 + k] = r[k]; });
  return out;
}

export class Viewer {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.renderer.setClearColor(BACKGROUND, 1);
    container.prepend(this.renderer.domElement);
    this.renderer.domElement.setAttribute("aria-label", "3-D view of the result");
    this.renderer.domElement.setAttribute("role", "img");
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.001, 1000);
    this.camera.position.set(0, 0, 3);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.controls.addEventListener("change", () => this.requestRender());
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x404050, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(1, 2, 3);
    this.camera.add(sun);
    this.scene.add(this.camera);
    this.root = new THREE.Group();   // the data, turned for the up axis
    this.flat = new THREE.Group();   // beside it, never turned (the UV layout)
    this.scene.add(this.root, this.flat);
    this.layers = [];                // {name, object, color}
    this.pointSize = 8;
    this.up = "y";
    this.planar = false;
    this.disc = discTexture();
    this.checker = checkerTexture();
    this.mixer = null;
    this.action = null;
    this.playing = false;
    this.dirty = true;
    this.frames = 0;
    this.firstFrameMs = null;
    this.firstFrameAt = null;
    this._t0 = null;
    this.raycaster = new THREE.Raycaster();
    this.onHover = null;
    this.labels = null;
    new ResizeObserver(() => this.resize()).observe(container);
    this.renderer.domElement.addEventListener("pointermove", (e) => { this._pointer = e; this.requestRender(); });
    this.renderer.domElement.addEventListener("pointerleave", () => { this._pointer = null; this.onHover?.(null); });
    this.resize();
    const loop = (t) => {
      requestAnimationFrame(loop);
      if (this.playing && this.mixer) {
        const dt = this._last === undefined ? 0 : (t - this._last) / 1000;
        const d = this.action.getClip().duration || 1;
        this.setTime((this.time + dt) % d);
        this.onTime?.(this.time, d);
      }
      this._last = t;
      if (this.dirty) this.render();
    };
    requestAnimationFrame(loop);
  }

  requestRender() { this.dirty = true; }

  resize() {
    const w = this.container.clientWidth || 1, h = this.container.clientHeight || 1;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  render() {
    this.dirty = false;
    this.renderer.render(this.scene, this.camera);
    this.frames += 1;
    if (this._t0 !== null && this.layers.length) {
      this.firstFrameAt = performance.now();  // since the page's navigation began
      this.firstFrameMs = this.firstFrameAt - this._t0;  // from the GLB's arrival
      this._t0 = null;
    }
    if (this._pointer) this.hover(this._pointer);
  }

  clear() {
    for (const g of [this.root, this.flat]) {
      g.traverse((o) => { o.geometry?.dispose?.(); });
      g.clear();
    }
    this.layers = [];
    this.mixer = null;
    this.action = null;
    this.playing = false;
    this.labels = null;
    this.glbLegend = null;
    this.colorBy = null;
    this.uvLayout = null;
    this.requestRender();
  }

  pointsMaterial(color, vertexColors) {
    return new THREE.PointsMaterial({
      size: this.pointSize, sizeAttenuation: false, vertexColors, color: vertexColors ? 0xffffff : color,
      map: this.disc, alphaTest: 0.5, transparent: false,
    });
  }

  addLayer(name, object, color, visible = true) {
    // the object keeps its own name: animation tracks find their targets by it
    object.visible = visible;
    if (typeof color === "number") color = `#${new THREE.Color(color).getHexString()}`;
    this.layers.push({ name, object, color });
    return object;
  }

  /** Points (Float32Array of xyz) as a layer. */
  pointsLayer(name, xyz, color, { visible = true, size = null } = {}) {
    const g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.BufferAttribute(xyz, 3));
    const m = this.pointsMaterial(color, false);
    if (size) { m.size = size; m.userData.fixedSize = true; }
    const p = new THREE.Points(g, m);
    this.root.add(p);
    return this.addLayer(name, p, color, visible);
  }

  /**
   * Shows a result's GLB. ``ctx``: {family, inputs (as sent, when known), outputs (the
   * results document, arrays as typed binary arrays)}.
   */
  async showGLB(buffer, ctx = {}) {
    this._t0 = performance.now();
    const gltf = await new GLTFLoader().parseAsync(buffer, "");
    this.clear();
    this._t0 = this._t0 ?? performance.now();
    const scene = gltf.scene;
    const hasUV = [];
    scene.traverse((o) => {
      if (o.isPoints) {
        const old = o.material;
        const vc = Boolean(o.geometry.attributes.color);
        o.material = this.pointsMaterial(old.color ?? 0xffffff, vc);
        if (vc) o.material.color.set(0xffffff);
        else o.material.color.copy(old.color);
      } else if (o.isMesh) {
        o.material.side = THREE.DoubleSide;
        o.geometry.computeVertexNormals?.();
        if (o.geometry.attributes.uv) hasUV.push(o);
      }
    });
    this.root.add(scene);
    const nodes = scene.children.length === 1 && !scene.children[0].isMesh && !scene.children[0].isPoints
      ? scene.children[0].children : scene.children;
    const json = gltf.parser.json;
    const roles = new Set();
    let glbLegend = null;  // a node's extras.legend: [{label, color: [r, g, b]}]
    this.colorBy = null;
    let suggested = null;  // the writer's point size (nodes' extras.pointSize), in pixels
    for (const node of nodes) {
      let color = null;
      node.traverse((o) => {
        if (color === null && o.material) color = o.material.vertexColors || o.material.map ? null : o.material.color;
      });
      // the glTF node's own name (three.js rewrites spaces in object names) and its role
      const index = gltf.parser.associations.get(node)?.nodes;
      const def = index === undefined ? {} : json.nodes[index];
      const role = def.extras?.role ?? node.userData?.role;
      if (role) roles.add(role);
      const size = def.extras?.pointSize;
      if (Array.isArray(def.extras?.legend)) glbLegend = def.extras.legend;
      if (def.extras?.colorBy) this.colorBy = def.extras.colorBy;
      if (size && role !== "handles") suggested = Math.max(suggested ?? 0, size);
      if (role === "handles") node.traverse((o) => { if (o.isPoints) { o.material.size = 12; o.material.userData.fixedSize = true; } });
      if (role === "uv-layout") { this.flat.add(node); this.uvLayout = node; }
      // an unmoved source is there to compare: hidden at first, so the moved one shows on its target
      this.addLayer(def.name || role || node.name || "result", node, color ? `#${color.getHexString()}` : null,
        role !== "source");
    }
    const family = ctx.family || "";
    if ((family === "registration" || family === "alignment") && ctx.inputs?.source && !roles.has("source")) {
      const src = positions(ctx.inputs.source);
      if (src) this.pointsLayer("source (as given)", src, GIVEN_COLOR, { visible: false });
    }
    if (family === "deformation" && ctx.inputs?.handles?.positions && !roles.has("handles")) {
      const h = positions(ctx.inputs.handles.positions);
      if (h) this.pointsLayer("handles", h, HANDLE_COLOR, { size: Math.max(10, this.pointSize * 2) });
      const given = positions(ctx.inputs.mesh);
      if (given) this.pointsLayer("mesh as given", given, GIVEN_COLOR, { visible: false });
    }
    for (const mesh of hasUV) {
      if (!mesh.material.map) mesh.material = new THREE.MeshStandardMaterial({ map: this.checker,
        side: THREE.DoubleSide, roughness: 0.85, metalness: 0 });
    }
    if (hasUV.length && !roles.has("uv-layout")) this.showUV(hasUV[0]);
    if (gltf.animations.length) {
      this.mixer = new THREE.AnimationMixer(scene);
      this.action = this.mixer.clipAction(gltf.animations[0]);
      this.action.play();
      this.setTime(0);
    }
    // a few points drawn large (at least 8 px: the writer's size suits a stock viewer), a
    // dense cloud small enough to stay legible
    let count = 0;
    this.root.traverse((o) => { if (o.isPoints) count += o.geometry.attributes.position.count; });
    this.setPointSize(count > 200_000 ? 2 : count > 20_000 ? 4 : Math.max(8, Math.round(suggested ?? 0)));
    this.labels = ctx.labels || null;
    this.glbLegend = glbLegend;
    this.planar = this.isPlanar();
    this.applyUp();
    this.fit();
    return { animated: Boolean(this.mixer), uv: hasUV.length > 0, layers: this.layers.map((l) => l.name),
      pointSize: this.pointSize };
  }

  /** A result without GLB (an assignment): the input sets as points, pairs as lines. */
  showSets(ctx) {
    this._t0 = performance.now();
    this.clear();
    const src = positions(ctx.inputs?.source), dst = positions(ctx.inputs?.target);
    if (!src && !dst) return false;
    if (src) this.pointsLayer("source", src, 0xf27319);
    if (dst) this.pointsLayer("target", dst, 0x2673d9);
    const pairs = ctx.pairs;
    if (src && dst && pairs?.data && pairs.shape?.length === 2) {
      const k = pairs.shape[0];
      const xyz = new Float32Array(k * 6);
      for (let i = 0; i < k; i++) {
        const a = Number(pairs.data[2 * i]), b = Number(pairs.data[2 * i + 1]);
        xyz.set(src.subarray(3 * a, 3 * a + 3), 6 * i);
        xyz.set(dst.subarray(3 * b, 3 * b + 3), 6 * i + 3);
      }
      const g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.BufferAttribute(xyz, 3));
      const lines = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: 0xd8dde6 }));
      this.root.add(lines);
      this.addLayer("pairs", lines, "#d8dde6");
    }
    this.planar = this.isPlanar();
    this.applyUp();
    this.fit();
    return true;
  }

  /** The flat UV layout of a textured mesh, built here when the GLB has none. */
  showUV(mesh) {
    const uv = mesh.geometry.attributes.uv;
    const n = uv.count;
    const xyz = new Float32Array(n * 3);
    for (let i = 0; i < n; i++) { xyz[3 * i] = uv.getX(i); xyz[3 * i + 1] = 1 - uv.getY(i); }
    const g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.BufferAttribute(xyz, 3));
    g.setAttribute("uv", uv);
    if (mesh.geometry.index) g.setIndex(mesh.geometry.index);
    const flat = new THREE.Mesh(g, new THREE.MeshBasicMaterial({ map: this.checker, side: THREE.DoubleSide }));
    const wire = new THREE.LineSegments(new THREE.WireframeGeometry(g),
      new THREE.LineBasicMaterial({ color: 0x111111, transparent: true, opacity: 0.35 }));
    const layout = new THREE.Group();
    layout.add(flat, wire);
    this.flat.add(layout);
    this.uvLayout = layout;
    this.addLayer("UV layout", layout, null);
  }

  /** Label -> CSS colour, read from the points' own colours (the first point of each
   * label), for the legend of a scatter coloured by class; null without labels or colours. */
  legend(limit = 64) {
    const c = new THREE.Color();
    if (this.glbLegend) {
      return new Map(this.glbLegend.slice(0, limit).map((e) => [e.label,
        `#${c.setRGB(e.color[0], e.color[1], e.color[2], THREE.LinearSRGBColorSpace).getHexString()}`]));
    }
    if (!this.labels) return null;
    let colors = null;
    this.root.traverse((o) => {
      if (!colors && o.isPoints && o.geometry.attributes.color?.count === this.labels.length) colors = o.geometry.attributes.color;
    });
    if (!colors) return null;
    const out = new Map();
    for (let i = 0; i < this.labels.length && out.size < limit; i++) {
      if (out.has(this.labels[i])) continue;
      c.setRGB(colors.getX(i), colors.getY(i), colors.getZ(i), THREE.LinearSRGBColorSpace);
      out.set(this.labels[i], `#${c.getHexString()}`);
    }
    return out;
  }

  /** Whether the data lie in the plane z = 0 (2-D layouts and embeddings). */
  isPlanar() {
    const box = new THREE.Box3().setFromObject(this.root);
    if (box.isEmpty()) return false;
    const size = box.getSize(new THREE.Vector3());
    return size.z <= 1e-9 * Math.max(size.x, size.y, 1e-30);
  }

  setUp(axis) { this.up = axis; this.applyUp(); this.fit(); }

  applyUp() {
    this.root.rotation.set(this.up === "z" && !this.planar ? -Math.PI / 2 : 0, 0, 0);
    this.root.updateMatrixWorld(true);
    if (this.uvLayout) {  // the UV layout beside the mesh, as tall as it
      const L = this.uvLayout;
      L.scale.set(1, 1, 1);
      L.position.set(0, 0, 0);
      L.rotation.set(0, 0, 0);
      L.updateMatrixWorld(true);
      const own = new THREE.Box3().setFromObject(L);
      const ownSize = own.getSize(new THREE.Vector3());
      const box = new THREE.Box3().setFromObject(this.root);
      const size = box.getSize(new THREE.Vector3());
      const s = Math.max(size.y, size.x, 1e-9) / Math.max(ownSize.x, ownSize.y, 1e-12);
      L.scale.set(s, s, 1);
      L.position.set(box.max.x + 0.15 * Math.max(size.x, size.y) - own.min.x * s,
        box.min.y - own.min.y * s, (box.min.z + box.max.z) / 2 - own.min.z);
    }
    this.requestRender();
  }

  setPointSize(px) {
    this.pointSize = px;
    for (const g of [this.root, this.flat]) {
      g.traverse((o) => {
        if (o.isPoints && !o.material.userData.fixedSize) o.material.size = px;
      });
    }
    this.requestRender();
  }

  setVisible(name, visible) {
    const layer = this.layers.find((l) => l.name === name);
    if (layer) layer.object.visible = visible;
    this.requestRender();
  }

  setTime(t) {
    if (!this.mixer) return;
    // the clip repeats: its very end would wrap to the first frame, so stop just short of it
    const d = this.duration;
    this.time = Math.min(Math.max(t, 0), d * (1 - 1e-6));
    this.mixer.setTime(this.time);
    this.requestRender();
  }

  get duration() { return this.action ? this.action.getClip().duration : 0; }

  fit() {
    const box = new THREE.Box3();
    for (const g of [this.root, this.flat]) {
      const b = new THREE.Box3().setFromObject(g);
      if (!b.isEmpty()) box.union(b);
    }
    if (box.isEmpty()) { this.requestRender(); return; }
    const sphere = box.getBoundingSphere(new THREE.Sphere());
    const r = Math.max(sphere.radius, 1e-6);
    const d = r / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2)) * 1.05;
    const c = sphere.center;
    this.camera.up.set(0, 1, 0);
    if (this.planar || this.uvLayout) this.camera.position.set(c.x, c.y, c.z + d);
    else this.camera.position.set(c.x + d * 0.45, c.y + d * 0.35, c.z + d * 0.82);
    this.camera.near = d / 1000;
    this.camera.far = d * 100;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(c);
    this.controls.update();
    this.requestRender();
  }

  hover(e) {
    if (!this.onHover) return;
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((e.clientX - rect.left) / rect.width) * 2 - 1,
      -((e.clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    const dist = this.camera.position.distanceTo(this.controls.target);
    const perPixel = 2 * dist * Math.tan(THREE.MathUtils.degToRad(this.camera.fov / 2)) / rect.height;
    this.raycaster.params.Points.threshold = perPixel * Math.max(this.pointSize, 4) / 2;
    const targets = [];
    this.root.traverseVisible((o) => { if (o.isPoints || o.isMesh) targets.push(o); });
    const hit = this.raycaster.intersectObjects(targets, false)[0];
    if (!hit) { this.onHover(null); return; }
    let index = hit.index;
    if (hit.face) {  // a mesh: the nearest corner of the face hit
      const pos = hit.object.geometry.attributes.position;
      const local = hit.object.worldToLocal(hit.point.clone());
      index = [hit.face.a, hit.face.b, hit.face.c].reduce((best, i) =>
        new THREE.Vector3().fromBufferAttribute(pos, i).distanceTo(local)
          < new THREE.Vector3().fromBufferAttribute(pos, best).distanceTo(local) ? i : best);
    }
    const layer = this.layers.find((l) => { let inside = false; l.object.traverse((o) => { if (o === hit.object) inside = true; }); return inside; });
    this.onHover({ index, layer: layer?.name, x: e.clientX - rect.left, y: e.clientY - rect.top,
      label: this.labels && index < this.labels.length ? this.labels[index] : undefined });
  }
}
