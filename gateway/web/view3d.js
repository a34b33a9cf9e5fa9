// The 3D view: the arm built from the standard DH links of /api/model, posed at the measured
// joint angles. `fkOrigins` is plain arithmetic (the page's `flange()` works without WebGL);
// `View3d` draws it with three.js and orbits with a mouse drag, zooms with the wheel.

import * as THREE from './vendor/three.module.min.js';

const DEG = Math.PI / 180;

/** 4x4 row-major matrix product a*b. */
function mul(a, b) {
  const r = new Array(16).fill(0);
  for (let i = 0; i < 4; i++)
    for (let j = 0; j < 4; j++)
      for (let k = 0; k < 4; k++) r[i * 4 + j] += a[i * 4 + k] * b[k * 4 + j];
  return r;
}

/** The DH transform RotZ(theta) TransZ(d) TransX(a) RotX(alpha), row-major. */
function dh(theta, d, a, alpha) {
  const ct = Math.cos(theta), st = Math.sin(theta);
  const ca = Math.cos(alpha), sa = Math.sin(alpha);
  return [
    ct, -st * ca, st * sa, a * ct,
    st, ct * ca, -ct * sa, a * st,
    0, sa, ca, d,
    0, 0, 0, 1,
  ];
}

/**
 * The origins of the base frame and of frames 1..n, [x,y,z] in metres, for joint angles
 * `qDeg` (standard DH: frame i = frame i-1 * RotZ(q_i + offset_i) TransZ(d_i) TransX(a_i)
 * RotX(alpha_i); base z up). The last one is the flange.
 */
export function fkOrigins(links, qDeg) {
  let t = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
  const out = [[0, 0, 0]];
  links.forEach((l, i) => {
    const q = (Number(qDeg[i]) || 0) * DEG + (l.offset_deg || 0) * DEG;
    t = mul(t, dh(q, l.d || 0, l.a || 0, (l.alpha_deg || 0) * DEG));
    out.push([t[3], t[7], t[11]]);
  });
  return out;
}

/**
 * Where to draw each joint: joint i turns about the z axis of frame i-1, at its origin; where
 * that origin is the previous joint's place (a wrist's roll, the flange's roll) or the floor
 * (joint 1), halfway along the link that follows, so that every joint shows on its own.
 */
export function jointPlacesOf(pts) {
  const places = [];
  for (let i = 1; i < pts.length; i++) {
    const o = pts[i - 1];
    const prev = i === 1 ? null : places[i - 2];
    const same = prev && Math.hypot(o[0] - prev[0], o[1] - prev[1], o[2] - prev[2]) < 0.01;
    places.push(i === 1 || same ? o.map((v, k) => (v + pts[i][k]) / 2) : o);
  }
  return places;
}

export function webglAvailable() {
  try {
    const c = document.createElement('canvas');
    return !!(window.WebGLRenderingContext && (c.getContext('webgl2') || c.getContext('webgl')));
  } catch (e) {
    return false;
  }
}

export const JOINT_COLOURS = {
  uncalibrated: 0x9aa0a6,
  ok: 0x2e9d3a,
  near: 0xf08c00,
  error: 0xd62828,
};

export class View3d {
  /** Throws when WebGL cannot be used. */
  constructor(canvas, links) {
    this.canvas = canvas;
    this.links = links;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xf4f6f8);
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 50);
    this.camera.up.set(0, 0, 1);
    this.orbit = { az: -0.9, el: 0.4, r: 2.3, target: new THREE.Vector3(0, 0, 0.45) };

    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8899aa, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(2, -3, 4);
    this.scene.add(sun);
    const grid = new THREE.GridHelper(2, 20, 0xb0b6bc, 0xd5d9dd);
    grid.rotation.x = Math.PI / 2; // the XY plane: the floor, z up
    this.scene.add(grid);
    this.scene.add(new THREE.AxesHelper(0.25));

    const n = links.length;
    this.linkMat = new THREE.MeshStandardMaterial({ color: 0x5b6b7d, metalness: 0.2, roughness: 0.6 });
    this.cylGeo = new THREE.CylinderGeometry(0.035, 0.035, 1, 16);
    this.sphereGeo = new THREE.SphereGeometry(0.06, 20, 14);
    this.segments = [];
    for (let i = 0; i < n; i++) {
      const m = new THREE.Mesh(this.cylGeo, this.linkMat);
      this.scene.add(m);
      this.segments.push(m);
    }
    this.joints = [];
    for (let i = 0; i < n; i++) {
      const m = new THREE.Mesh(this.sphereGeo, new THREE.MeshStandardMaterial({ color: JOINT_COLOURS.uncalibrated }));
      this.scene.add(m);
      this.joints.push(m);
    }
    const base = new THREE.Mesh(
      new THREE.CylinderGeometry(0.12, 0.14, 0.06, 24),
      new THREE.MeshStandardMaterial({ color: 0x39424c }),
    );
    base.rotation.x = Math.PI / 2;
    base.position.set(0, 0, 0.03);
    this.scene.add(base);
    this.flangeMesh = new THREE.Mesh(
      new THREE.BoxGeometry(0.05, 0.05, 0.05),
      new THREE.MeshStandardMaterial({ color: 0x1d4ed8 }),
    );
    this.scene.add(this.flangeMesh);
    // The TCP's frame (the active tool's axes: x red, y green, z blue), where the core reports
    // the TCP; hidden until every axis is calibrated.
    this.tcpAxes = new THREE.AxesHelper(0.12);
    this.tcpAxes.visible = false;
    this.scene.add(this.tcpAxes);

    this.dirty = true;
    this.installOrbit();
    this.resize();
    this.placeCamera();
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.draw();
  }

  /** Draw at the next animation frame, once, when something changed: an animation frame asked
   * for every frame would keep the browser producing frames at the display's rate even for an
   * arm at rest. */
  draw() {
    if (this.drawPending) return;
    this.drawPending = true;
    requestAnimationFrame(() => {
      this.drawPending = false;
      if (this.dirty) {
        this.dirty = false;
        this.renderer.render(this.scene, this.camera);
      }
    });
  }

  resize() {
    const w = this.canvas.clientWidth || 400;
    const h = this.canvas.clientHeight || 300;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
    this.draw();
  }

  placeCamera() {
    const { az, el, r, target } = this.orbit;
    this.camera.position.set(
      target.x + r * Math.cos(el) * Math.cos(az),
      target.y + r * Math.cos(el) * Math.sin(az),
      target.z + r * Math.sin(el),
    );
    this.camera.lookAt(target);
    this.dirty = true;
    this.draw();
  }

  installOrbit() {
    let drag = null;
    this.canvas.addEventListener('pointerdown', (e) => {
      drag = { x: e.clientX, y: e.clientY };
      this.canvas.setPointerCapture(e.pointerId);
    });
    this.canvas.addEventListener('pointermove', (e) => {
      if (!drag) return;
      this.orbit.az -= (e.clientX - drag.x) * 0.01;
      this.orbit.el = Math.max(-1.4, Math.min(1.4, this.orbit.el + (e.clientY - drag.y) * 0.01));
      drag = { x: e.clientX, y: e.clientY };
      this.placeCamera();
    });
    const end = () => { drag = null; };
    this.canvas.addEventListener('pointerup', end);
    this.canvas.addEventListener('pointercancel', end);
    this.canvas.addEventListener('wheel', (e) => {
      e.preventDefault();
      this.orbit.r = Math.max(0.8, Math.min(10, this.orbit.r * Math.exp(e.deltaY * 0.001)));
      this.placeCamera();
    }, { passive: false });
  }

  /** Pose the arm at the frame origins `pts` (from fkOrigins); `colours` per joint; `tcp` the
   * status's `cartesian_state` (null: none), drawn as the TCP's triad. */
  update(pts, colours, tcp) {
    // Drawn again only when something visible changed (0.1 mm, a colour): WebGL may be rendered
    // in software, and a page showing an arm at rest must cost (almost) nothing.
    const tcpKey = tcp ? [...tcp.position, ...tcp.orientation].map((v) => Math.round(v * 1e4)).join(',') : '';
    const key = pts.map((p) => p.map((v) => Math.round(v * 1e4)).join(',')).join(';') + colours.join(',') + tcpKey;
    if (key === this.lastKey) return;
    this.lastKey = key;
    const up = new THREE.Vector3(0, 1, 0);
    const jointPlaces = jointPlacesOf(pts);
    for (let i = 0; i < this.segments.length; i++) {
      const a = new THREE.Vector3(...pts[i]);
      const b = new THREE.Vector3(...pts[i + 1]);
      const seg = this.segments[i];
      const len = a.distanceTo(b);
      seg.visible = len > 1e-4;
      if (seg.visible) {
        seg.position.copy(a).add(b).multiplyScalar(0.5);
        seg.scale.set(1, len, 1);
        seg.quaternion.setFromUnitVectors(up, b.clone().sub(a).normalize());
      }
      this.joints[i].position.set(...jointPlaces[i]);
      this.joints[i].material.color.setHex(JOINT_COLOURS[colours[i]] ?? JOINT_COLOURS.uncalibrated);
    }
    this.flangeMesh.position.set(...pts[pts.length - 1]);
    this.tcpAxes.visible = !!tcp;
    if (tcp) {
      this.tcpAxes.position.set(...tcp.position);
      this.tcpAxes.quaternion.set(...tcp.orientation);
    }
    this.dirty = true;
    this.draw();
  }
}
