// The 3D view of one table: renderer, lights, table, balls, cue, aim line and ghost ball, and
// the two cameras (aim view behind the cue ball, top view). It draws only when asked to
// (`invalidate`) or while an animation runs, so an idle table costs nothing.
import * as THREE from "three";
import { makeBalls } from "./balls.js";
import { regionMesh, regionOutline } from "./region.js";
import { frame, makeTable } from "./table.js";

const CUE_LENGTH = 1.45;
const CUE_TIP = 0.0065;
const CUE_BUTT = 0.015;
/** Gap between tip and ball at zero power, and the extra draw-back at full power (m). */
const CUE_GAP = 0.01;
const CUE_DRAW = 0.22;
/** Frame interval (ms) above which the resolution is lowered, and the lowest scale. */
const SLOW_FRAME_MS = 40;
const MIN_SCALE = 0.4;
/** Renderers that run WebGL on the CPU. */
const SOFTWARE = /swiftshader|llvmpipe|softpipe|software|basic render/i;
/** The ghost ball's colour: no marking, a legal first contact, a foul. */
const GHOST = { plain: 0xffffff, legal: 0x7dff9a, foul: 0xff5a4a };

/** Whether WebGL here is drawn by the CPU (SwiftShader, llvmpipe, ...), by the renderer's name. */
export function softwareRenderer() {
  const gl = document.createElement("canvas").getContext("webgl2");
  if (!gl) return false;
  const info = gl.getExtension("WEBGL_debug_renderer_info");
  const name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
  gl.getExtension("WEBGL_lose_context")?.loseContext();
  return SOFTWARE.test(name);
}

/** Cheaper stand-ins for the physically based materials, for a software renderer: Phong where
 *  the surface shines (balls, rails, cue), Lambert elsewhere (cloth, cushions). */
function simplerMaterials(root) {
  const swapped = new Map();
  root.traverse((object) => {
    const m = object.material;
    if (!m?.isMeshStandardMaterial) return;
    if (!swapped.has(m)) {
      const { color, map } = m;
      const simple = m.roughness < 0.5 ? new THREE.MeshPhongMaterial({ color, map, shininess: 80 * (1 - m.roughness) ** 2 }) : new THREE.MeshLambertMaterial({ color, map });
      swapped.set(m, simple);
      m.dispose();
    }
    object.material = swapped.get(m);
  });
}

function makeCue() {
  const group = new THREE.Group();
  const wood = new THREE.MeshStandardMaterial({ color: 0xc9a26b, roughness: 0.5 });
  const butt = new THREE.MeshStandardMaterial({ color: 0x2b1a12, roughness: 0.4 });
  const ferrule = new THREE.MeshStandardMaterial({ color: 0xf2efe6, roughness: 0.6 });
  const tip = new THREE.MeshStandardMaterial({ color: 0x3a5db0, roughness: 0.9 });
  // Built along +y from the tip at the origin; the group is then turned to the shot.
  const parts = [
    [0.004, CUE_TIP, CUE_TIP, tip],
    [0.02, CUE_TIP, CUE_TIP * 1.02, ferrule],
    [CUE_LENGTH * 0.62, CUE_TIP * 1.02, CUE_BUTT * 0.8, wood],
    [CUE_LENGTH * 0.38 - 0.024, CUE_BUTT * 0.8, CUE_BUTT, butt],
  ];
  let y = 0;
  for (const [length, r0, r1, material] of parts) {
    const mesh = new THREE.Mesh(new THREE.CylinderGeometry(r1, r0, length, 16), material);
    mesh.position.y = y + length / 2;
    mesh.castShadow = true;
    group.add(mesh);
    y += length;
  }
  return group;
}

export class TableScene {
  constructor(canvas, table, game) {
    this.canvas = canvas;
    this.table = table;
    this.game = game;
    this.frame = frame(table);
    // On a software renderer every pixel is drawn by the CPU: no multisampling, one pixel per
    // CSS pixel, no shadow map (a soft disc under each ball instead), simpler shading.
    this.software = softwareRenderer();
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: !this.software, preserveDrawingBuffer: true });
    this.pixelRatio = this.software ? 1 : Math.min(window.devicePixelRatio || 1, 2);
    this.scale = 1; // lowered by `adapt` on a device too slow for the full resolution
    this.renderer.setPixelRatio(this.pixelRatio);
    this.renderer.shadowMap.enabled = !this.software;
    this.renderer.shadowMap.type = THREE.PCFShadowMap;
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x15171c);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.02, 30);
    this.mode = "aim";
    this.aimDistance = 0.9;
    this.balls = new Map();
    this.animating = 0;
    this.pending = false;
    this.frameHooks = [];
    this.drawTimes = [];
    this.addLights();
    const built = makeTable(table, game);
    this.extent = built.extent;
    this.scene.add(built.group);
    this.cue = makeCue();
    this.scene.add(this.cue);
    this.addAimMarks();
    if (this.software) simplerMaterials(this.scene);
    this.heading = 90;
    this.aim = { heading: 90, elevation: 0, a: 0, b: 0, power: 0 };
    this.targets = null; // the balls the server lists as legal first contacts (null: unmarked)
    this.contact = null; // the aim line's first ball {ball, legal}, or null
    this.region = null;
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  addLights() {
    this.scene.add(new THREE.HemisphereLight(0xfff6e8, 0x202020, 1.4));
    const key = new THREE.DirectionalLight(0xffffff, 1.6);
    key.position.set(0.3, 3, 0.6);
    key.castShadow = true;
    key.shadow.mapSize.set(1024, 1024);
    const s = Math.max(this.table.w, this.table.l) * 0.65;
    Object.assign(key.shadow.camera, { left: -s, right: s, top: s, bottom: -s, near: 0.5, far: 5 });
    key.shadow.bias = -0.0005;
    this.scene.add(key);
    // Two lamps over the table, for the highlights on the balls.
    for (const z of [-this.table.l / 4, this.table.l / 4]) {
      const lamp = new THREE.PointLight(0xfff1dc, 1.2, 4, 1.5);
      lamp.position.set(0, 1.1, z);
      this.scene.add(lamp);
    }
  }

  addAimMarks() {
    const material = new THREE.LineDashedMaterial({ color: 0xffffff, dashSize: 0.02, gapSize: 0.012, transparent: true, opacity: 0.8 });
    this.aimLine = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]), material);
    this.objectLine = new THREE.Line(
      new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]),
      new THREE.LineBasicMaterial({ color: 0xffe27a, transparent: true, opacity: 0.8 }),
    );
    const R = this.table.R;
    this.ghost = new THREE.Mesh(
      new THREE.SphereGeometry(R, 24, 12),
      new THREE.MeshBasicMaterial({ color: 0xffffff, transparent: true, opacity: 0.28, depthWrite: false }),
    );
    for (const m of [this.aimLine, this.objectLine, this.ghost]) this.scene.add(m);
  }

  /** Put the balls where `balls` ({id: [x, y]}) says; balls not listed are hidden. */
  setBalls(balls) {
    const missing = Object.keys(balls).filter((id) => !this.balls.has(id));
    if (missing.length) {
      for (const [id, mesh] of makeBalls(this.game, missing, this.table.R)) {
        this.balls.set(id, mesh);
        this.scene.add(mesh);
        if (this.software) {
          simplerMaterials(mesh);
          this.addBlob(mesh);
        }
      }
    }
    for (const [id, mesh] of this.balls) {
      const p = balls[id];
      mesh.visible = Boolean(p);
      if (p) mesh.position.copy(this.frame.toWorld(p[0], p[1], this.table.R));
    }
    this.invalidate();
  }

  /** A soft dark disc on the cloth under `ball`, in place of its shadow (placed in `draw`). */
  addBlob(ball) {
    this.blobs ??= [];
    this.blobTexture ??= blobTexture();
    const material = new THREE.MeshBasicMaterial({ map: this.blobTexture, transparent: true, depthWrite: false });
    const blob = new THREE.Mesh(new THREE.PlaneGeometry(3 * this.table.R, 3 * this.table.R), material);
    blob.rotation.x = -Math.PI / 2;
    this.scene.add(blob);
    this.blobs.push([ball, blob]);
  }

  placeBlobs() {
    const R = this.table.R;
    for (const [ball, blob] of this.blobs ?? []) {
      blob.visible = ball.visible && ball.position.y > 0;
      blob.position.set(ball.position.x - 0.15 * R, ball.position.y - R + 0.001, ball.position.z - 0.3 * R);
    }
  }

  /** Ring pocket `name` (a called pocket), or no pocket (null). */
  markPocket(name) {
    const pocket = this.table.pockets.find((p) => p.name === name);
    if (!this.pocketMark) {
      const material = new THREE.MeshBasicMaterial({ color: 0xe8b04a, transparent: true, opacity: 0.9, depthTest: false });
      this.pocketMark = new THREE.Mesh(new THREE.RingGeometry(1, 1.25, 40), material);
      this.pocketMark.rotation.x = -Math.PI / 2;
      this.pocketMark.renderOrder = 1; // over the cushions that hide part of it
      this.scene.add(this.pocketMark);
    }
    this.pocketMark.visible = Boolean(pocket);
    if (pocket) {
      this.pocketMark.scale.setScalar(pocket.radius);
      this.pocketMark.position.copy(this.frame.toWorld(pocket.center[0], pocket.center[1], 0.004));
    }
    this.invalidate();
  }

  /** The table position [x, y] of a ball, or null if it is not on the table. */
  ballAt(id) {
    const mesh = this.balls.get(id);
    return mesh && mesh.visible ? this.frame.toTable(mesh.position) : null;
  }

  /** Where each ball on the table is drawn: {id: [x, y]} (the browser tests read it). */
  drawnBalls() {
    const out = {};
    for (const id of this.balls.keys()) {
      const p = this.ballAt(id);
      if (p) out[id] = p;
    }
    return out;
  }

  /** Draw ball-in-hand region `name` ("kitchen", "D", "anywhere"; null: none) on the cloth. */
  showRegion(name) {
    if (this.region) this.scene.remove(this.region);
    const outline = name ? regionOutline(this.table, name) : null;
    this.region = outline ? regionMesh(outline, this.frame.toWorld) : null;
    this.regionName = outline ? name : null;
    if (this.region) this.scene.add(this.region);
    this.invalidate();
  }

  /** Mark the aim's first ball legal or a foul by the server's list `targets` (null: unmarked). */
  setTargets(targets) {
    this.targets = targets;
    this.placeAimMarks();
    this.invalidate();
  }

  /** Show the cue, aim line and ghost ball for cue ball `cueId` (null hides them). */
  setAim(cueId, aim) {
    this.cueId = cueId;
    Object.assign(this.aim, aim);
    this.placeAimMarks();
    this.invalidate();
  }

  placeAimMarks() {
    const cuePos = this.cueId ? this.ballAt(this.cueId) : null;
    const show = Boolean(cuePos) && !this.animating;
    for (const m of [this.cue, this.aimLine, this.objectLine, this.ghost]) m.visible = show;
    this.contact = null;
    if (!show) return;
    const { heading, elevation, a, b, power } = this.aim;
    const R = this.table.R;
    const h = (heading * Math.PI) / 180;
    const d = [Math.cos(h), Math.sin(h)];
    const hit = this.firstContact(cuePos, d);
    const { toWorld } = this.frame;
    const y = 0.002;
    this.aimLine.geometry.setFromPoints([toWorld(cuePos[0], cuePos[1], y), toWorld(hit.at[0], hit.at[1], y)]);
    this.aimLine.computeLineDistances();
    this.ghost.position.copy(toWorld(hit.at[0], hit.at[1], R));
    this.ghost.visible = Boolean(hit.ball);
    this.contact = hit.ball ? { ball: hit.ball, legal: this.targets ? this.targets.includes(hit.ball) : null } : null;
    const look = this.contact?.legal === true ? "legal" : this.contact?.legal === false ? "foul" : "plain";
    this.ghost.material.color.setHex(GHOST[look]);
    this.ghost.material.opacity = look === "plain" ? 0.28 : 0.5;
    this.objectLine.visible = Boolean(hit.ball);
    if (hit.ball) {
      const o = this.ballAt(hit.ball);
      const n = [o[0] - hit.at[0], o[1] - hit.at[1]];
      const len = Math.hypot(n[0], n[1]) || 1;
      const far = [o[0] + (n[0] / len) * 0.3, o[1] + (n[1] / len) * 0.3];
      this.objectLine.geometry.setFromPoints([toWorld(o[0], o[1], y), toWorld(far[0], far[1], y)]);
    }
    // The cue: along the shot, raised by the elevation, its tip at the offset (a, b) on the ball.
    const forward = this.frame.vector(d[0], d[1], 0);
    const right = this.frame.vector(d[1], -d[0], 0);
    const up = new THREE.Vector3(0, 1, 0);
    const e = (elevation * Math.PI) / 180;
    const axis = forward.clone().multiplyScalar(Math.cos(e)).addScaledVector(up, -Math.sin(e)).normalize();
    const centre = toWorld(cuePos[0], cuePos[1], R);
    const contact = centre
      .clone()
      .addScaledVector(right, a * R)
      .addScaledVector(up, b * R)
      .addScaledVector(forward, -Math.sqrt(Math.max(0, 1 - a * a - b * b)) * R);
    const tip = contact.addScaledVector(axis, -(CUE_GAP + CUE_DRAW * power));
    this.cue.position.copy(tip);
    this.cue.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), axis.clone().negate());
  }

  /** Where the cue ball, sent from p along unit d, first touches a ball or a cushion (no physics:
   *  straight-line geometry, for the aim line only). */
  firstContact(p, d) {
    const R = this.table.R;
    let best = Infinity;
    let ball = null;
    for (const [id, mesh] of this.balls) {
      if (id === this.cueId || !mesh.visible) continue;
      const q = this.frame.toTable(mesh.position);
      const f = [q[0] - p[0], q[1] - p[1]];
      const along = f[0] * d[0] + f[1] * d[1];
      const across2 = f[0] * f[0] + f[1] * f[1] - along * along;
      const reach = 4 * R * R - across2;
      if (along <= 0 || reach < 0) continue;
      const s = along - Math.sqrt(reach);
      if (s < best) {
        best = s;
        ball = id;
      }
    }
    const { w, l } = this.table;
    let wall = Infinity;
    for (const [pc, dc, lo, hi] of [
      [p[0], d[0], R, w - R],
      [p[1], d[1], R, l - R],
    ]) {
      if (dc > 1e-9) wall = Math.min(wall, (hi - pc) / dc);
      else if (dc < -1e-9) wall = Math.min(wall, (lo - pc) / dc);
    }
    if (wall < best) {
      best = wall;
      ball = null;
    }
    best = Math.max(0, best);
    return { at: [p[0] + d[0] * best, p[1] + d[1] * best], ball };
  }

  setMode(mode) {
    this.mode = mode;
    this.invalidate();
  }

  placeCamera() {
    const cam = this.camera;
    const aspect = cam.aspect;
    const follow = this.cueId ?? this.cameraBall;
    const cuePos = follow ? this.ballAt(follow) : null;
    if (this.mode === "aim" && cuePos && (!this.animating || this.shownMode !== "aim")) {
      const h = (this.aim.heading * Math.PI) / 180;
      const d = this.frame.vector(Math.cos(h), Math.sin(h), 0);
      const ball = this.frame.toWorld(cuePos[0], cuePos[1], this.table.R);
      const dist = this.aimDistance;
      cam.up.set(0, 1, 0);
      cam.position.copy(ball).addScaledVector(d, -dist);
      // Behind a rail the camera rises by how far it is past the cushion, to see over it.
      const [x, y] = this.frame.toTable(cam.position);
      const past = Math.max(0, -x, x - this.table.w, -y, y - this.table.l);
      cam.position.y += dist * 0.38 + past * 0.9;
      cam.lookAt(ball.clone().addScaledVector(d, dist * 0.6));
      this.shownMode = "aim";
      return;
    }
    if (this.animating && this.shownMode === "aim") return; // keep the pre-shot view
    // Top view: the long side along the screen's longer side.
    const landscape = aspect >= 1;
    const across = landscape ? this.extent.l : this.extent.w;
    const along = landscape ? this.extent.w : this.extent.l;
    const fov = (cam.fov * Math.PI) / 180;
    const height = Math.max(along / 2 / Math.tan(fov / 2), across / 2 / (Math.tan(fov / 2) * aspect)) * 1.04;
    cam.position.set(0, height, 0);
    cam.up.set(landscape ? -1 : 0, 0, landscape ? 0 : -1);
    cam.lookAt(0, 0, 0);
    this.shownMode = "top";
  }

  resize() {
    const { clientWidth, clientHeight } = this.canvas;
    if (!clientWidth || !clientHeight) return;
    this.renderer.setSize(clientWidth, clientHeight, false);
    this.camera.aspect = clientWidth / clientHeight;
    this.camera.updateProjectionMatrix();
    this.invalidate();
  }

  /** Ask for one redraw on the next animation frame. */
  invalidate() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame((now) => this.draw(now));
  }

  draw(now) {
    this.pending = false;
    const started = performance.now();
    const animating = this.animating > 0;
    for (const hook of this.frameHooks) hook(now);
    this.placeAimMarks();
    this.placeCamera();
    this.placeBlobs();
    this.renderer.render(this.scene, this.camera);
    // The main thread's cost of an animation frame (evaluation, scene update, WebGL calls).
    if (animating) {
      this.drawTimes.push(performance.now() - started);
      this.adapt(now);
    }
    this.lastFrame = animating ? now : null;
    if (this.animating) this.invalidate();
  }

  /** While animating, render fewer pixels when frames come slower than SLOW_FRAME_MS (a weak
   *  GPU, or software rendering): each step draws 0.75 as many pixels per side, down to MIN_SCALE. */
  adapt(now) {
    if (this.lastFrame == null) return;
    const recent = (this.recent ??= []);
    recent.push(now - this.lastFrame);
    if (recent.length < 8) return;
    const median = [...recent].sort((a, b) => a - b)[4];
    recent.length = 0;
    if (median > SLOW_FRAME_MS && this.scale > MIN_SCALE) {
      this.scale = Math.max(MIN_SCALE, this.scale * 0.75);
      this.setScale(this.scale);
    }
  }

  /** Render at `scale` of the full resolution (animations start at the scale last learnt; a
   *  still table is drawn once, at full resolution). */
  setScale(scale) {
    this.renderer.setPixelRatio(this.pixelRatio * scale);
    this.resize();
  }

  /** The page coordinates [x, y] at which table point p (at ball height) is drawn. */
  screenOf(p) {
    const v = this.frame.toWorld(p[0], p[1], this.table.R).project(this.camera);
    const rect = this.canvas.getBoundingClientRect();
    return [rect.left + ((v.x + 1) / 2) * rect.width, rect.top + ((1 - v.y) / 2) * rect.height];
  }

  /** The table point [x, y] under a pointer event, or null off the cloth plane. */
  pointerToTable(event) {
    const rect = this.canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((event.clientX - rect.left) / rect.width) * 2 - 1, -((event.clientY - rect.top) / rect.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, this.camera);
    const plane = new THREE.Plane(new THREE.Vector3(0, 1, 0), -this.table.R);
    const hit = new THREE.Vector3();
    return ray.ray.intersectPlane(plane, hit) ? this.frame.toTable(hit) : null;
  }
}

/** A radial fade from translucent black to nothing: the blob shadow's texture. */
function blobTexture() {
  const canvas = document.createElement("canvas");
  canvas.width = canvas.height = 64;
  const ctx = canvas.getContext("2d");
  const g = ctx.createRadialGradient(32, 32, 4, 32, 32, 32);
  g.addColorStop(0, "rgba(0, 0, 0, 0.55)");
  g.addColorStop(1, "rgba(0, 0, 0, 0)");
  ctx.fillStyle = g;
  ctx.fillRect(0, 0, 64, 64);
  return new THREE.CanvasTexture(canvas);
}
