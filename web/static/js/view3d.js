// The 3D view (three.js): curves drawn as tubes, the inflated membrane with
// its patches, a millimetre grid under them; orbit (drag), zoom (wheel or
// pinch), pan (right drag), reset (button or R).

import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { ticks } from "./plot.js";

const LATEX = new THREE.Color("#e9c46a");
const PATCH = new THREE.Color("#d9480f");

export class View3D {
  constructor(canvas, legend) {
    this.canvas = canvas;
    this.legend = legend;
    this.items = new Map();
    // preserveDrawingBuffer: the canvas can be read back (tests, screenshots).
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color("#ffffff");
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.1, 1e6);
    this.camera.up.set(0, 0, 1);
    this.scene.add(new THREE.HemisphereLight("#ffffff", "#8899aa", 2.2));
    this.sun = new THREE.DirectionalLight("#ffffff", 1.6);
    this.scene.add(this.sun);
    this.grid = new THREE.Group();
    this.scene.add(this.grid);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.listenToKeyEvents(canvas); // arrow keys pan when the view has focus
    this.controls.addEventListener("change", () => this.render());
    canvas.addEventListener("keydown", (e) => { if (e.key === "r" || e.key === "R") this.fit(); });
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.canvas;
    if (!w || !h) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  render() {
    this.sun.position.copy(this.camera.position);
    this.renderer.render(this.scene, this.camera);
  }

  /** Replaces (or with `object` null removes) the item `name`. */
  set(name, object, label, colour) {
    const old = this.items.get(name);
    if (old) {
      this.scene.remove(old.object);
      old.object.traverse((o) => { o.geometry?.dispose(); o.material?.dispose?.(); });
      this.items.delete(name);
    }
    if (object) {
      this.scene.add(object);
      this.items.set(name, { object, label, colour });
    }
    this.drawLegend();
  }

  has(name) {
    return this.items.has(name);
  }

  /** A polyline drawn as a tube of radius `radius` (mm). */
  curve(name, points, { colour, label, radius, opacity = 1 }) {
    if (!points || points.length < 2) return this.set(name, null);
    const path = new THREE.CatmullRomCurve3(points.map((p) => new THREE.Vector3(...p)));
    const segments = Math.min(4000, points.length * 3);
    const geometry = new THREE.TubeGeometry(path, segments, radius, 8, false);
    const material = new THREE.MeshStandardMaterial({ color: colour, roughness: 0.5,
      transparent: opacity < 1, opacity });
    this.set(name, new THREE.Mesh(geometry, material), label, colour);
  }

  /**
   * A translucent tube along `points` whose radius at each fraction of its
   * length is `radii` (mm, equally spaced fractions from the first point to
   * the last, linear between): a band of uncertainty around a centreline.
   */
  band(name, points, radii, { colour, label, opacity = 0.25 }) {
    if (!points || points.length < 2 || !radii?.length) return this.set(name, null);
    const path = new THREE.CatmullRomCurve3(points.map((p) => new THREE.Vector3(...p)));
    const segments = Math.min(2000, points.length * 3);
    const radial = 16;
    const geometry = new THREE.TubeGeometry(path, segments, 1, radial, false);
    const at = (u) => {
      const x = u * (radii.length - 1);
      const i = Math.min(Math.floor(x), radii.length - 2);
      return radii.length === 1 ? radii[0] : radii[i] + (x - i) * (radii[i + 1] - radii[i]);
    };
    // TubeGeometry puts ring i's vertices at unit distance from
    // path.getPointAt(i / segments): scale each ring to its radius.
    const position = geometry.attributes.position;
    const centre = new THREE.Vector3();
    const vertex = new THREE.Vector3();
    for (let i = 0; i <= segments; i++) {
      path.getPointAt(i / segments, centre);
      const r = Math.max(at(i / segments), 1e-3);
      for (let j = 0; j <= radial; j++) {
        const k = i * (radial + 1) + j;
        vertex.fromBufferAttribute(position, k).sub(centre).multiplyScalar(r).add(centre);
        position.setXYZ(k, vertex.x, vertex.y, vertex.z);
      }
    }
    geometry.computeVertexNormals();
    const material = new THREE.MeshStandardMaterial({ color: colour, roughness: 0.8,
      transparent: true, opacity, depthWrite: false, side: THREE.DoubleSide });
    this.set(name, new THREE.Mesh(geometry, material), label, colour);
  }

  /** Points as small dots. */
  dots(name, points, { colour, label, size }) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.Float32BufferAttribute(points.flat(), 3));
    const material = new THREE.PointsMaterial({ color: colour, size, sizeAttenuation: true });
    this.set(name, new THREE.Points(geometry, material), label, colour);
  }

  /**
   * The inflated membrane (`surface` of POST /v1/simulate), each node moved
   * by `place`; patched parts in the patch colour.
   */
  surface(name, surface, place, label) {
    const { around, positions_mm: nodes, patch_share: share } = surface;
    const rings = Math.floor((nodes.length - 1) / around);
    const position = new Float32Array(nodes.length * 3);
    const colour = new Float32Array(nodes.length * 3);
    nodes.forEach((p, i) => {
      position.set(place(p), 3 * i);
      const c = LATEX.clone().lerp(PATCH, Math.min(1, share[i] * 1.5));
      colour.set([c.r, c.g, c.b], 3 * i);
    });
    const index = [];
    for (let k = 0; k + 1 < rings; k++) {
      for (let j = 0; j < around; j++) {
        const a = k * around + j, b = k * around + ((j + 1) % around);
        const c = a + around, d = b + around;
        index.push(a, b, d, a, d, c);
      }
    }
    const pole = nodes.length - 1, last = (rings - 1) * around;
    for (let j = 0; j < around; j++) index.push(last + j, last + ((j + 1) % around), pole);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(position, 3));
    geometry.setAttribute("color", new THREE.BufferAttribute(colour, 3));
    geometry.setIndex(index);
    geometry.computeVertexNormals();
    const material = new THREE.MeshStandardMaterial({ vertexColors: true, roughness: 0.6,
      side: THREE.DoubleSide, transparent: true, opacity: 0.55, depthWrite: false });
    this.set(name, new THREE.Mesh(geometry, material), label, "#e9c46a");
  }

  setVisible(name, visible) {
    const item = this.items.get(name);
    if (item) item.object.visible = visible;
    this.render();
  }

  /** The box around everything drawn. */
  bounds() {
    const box = new THREE.Box3();
    for (const { object } of this.items.values()) box.expandByObject(object);
    return box;
  }

  /** Camera and grid fitted to what is drawn. */
  fit() {
    const box = this.bounds();
    if (box.isEmpty()) return this.render();
    const sphere = box.getBoundingSphere(new THREE.Sphere());
    const r = Math.max(sphere.radius, 1);
    const distance = r / Math.sin((this.camera.fov * Math.PI) / 360) * 1.1;
    const direction = new THREE.Vector3(1, -1.4, 0.9).normalize();
    this.camera.position.copy(sphere.center).addScaledVector(direction, distance);
    this.camera.near = distance / 100;
    this.camera.far = distance * 100;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(sphere.center);
    this.controls.update();
    this.drawGrid(box);
    this.render();
  }

  /** A grid under the box at round millimetre steps, its lines labelled. */
  drawGrid(box) {
    this.grid.clear();
    const size = box.getSize(new THREE.Vector3());
    const span = Math.max(size.x, size.y, 1);
    const xs = ticks(box.min.x - span * 0.05, box.max.x + span * 0.05, 6);
    const ys = ticks(box.min.y - span * 0.05, box.max.y + span * 0.05, 6);
    const z = box.min.z - Math.max(size.z, span) * 0.05;
    const vertices = [];
    for (const x of xs) vertices.push(x, ys[0], z, x, ys[ys.length - 1], z);
    for (const y of ys) vertices.push(xs[0], y, z, xs[xs.length - 1], y, z);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.Float32BufferAttribute(vertices, 3));
    this.grid.add(new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: "#c9ced6" })));
    const height = span / 20;
    xs.forEach((x, i) => this.grid.add(label(i === xs.length - 1 ? `x ${x} mm` : `${x}`, [x, ys[0] - height, z], height)));
    ys.forEach((y, i) => this.grid.add(label(i === ys.length - 1 ? `y ${y} mm` : `${y}`, [xs[xs.length - 1] + height, y, z], height)));
    const zTop = box.max.z;
    const axis = new THREE.BufferGeometry();
    axis.setAttribute("position", new THREE.Float32BufferAttribute([xs[0], ys[ys.length - 1], z, xs[0], ys[ys.length - 1], zTop], 3));
    this.grid.add(new THREE.LineSegments(axis, new THREE.LineBasicMaterial({ color: "#8a94a3" })));
    this.grid.add(label(`z ${Math.round(zTop - z)} mm above the grid`, [xs[0], ys[ys.length - 1], zTop + height], height));
  }

  drawLegend() {
    if (!this.legend) return;
    this.legend.replaceChildren(...[...this.items.values()].filter((i) => i.label).map(({ label, colour }) => {
      const li = document.createElement("li");
      const swatch = document.createElement("i");
      swatch.style.background = colour;
      li.append(swatch, label);
      return li;
    }));
  }

  /** Fraction of the canvas's pixels that are not the background. */
  inkFraction() {
    const gl = this.renderer.getContext();
    const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const pixels = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
    let ink = 0;
    for (let i = 0; i < pixels.length; i += 4) if (pixels[i] < 235 || pixels[i + 1] < 235 || pixels[i + 2] < 235) ink++;
    return ink / (w * h);
  }
}

/** A text sprite `height` mm tall. */
function label(text, at, height) {
  const canvas = document.createElement("canvas");
  const context = canvas.getContext("2d");
  context.font = "48px system-ui, sans-serif";
  canvas.width = Math.ceil(context.measureText(text).width) + 8;
  canvas.height = 60;
  context.font = "48px system-ui, sans-serif";
  context.fillStyle = "#5b6575";
  context.fillText(text, 4, 46);
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: texture, depthTest: false }));
  sprite.scale.set((height * canvas.width) / canvas.height, height, 1);
  sprite.position.set(...at);
  return sprite;
}
