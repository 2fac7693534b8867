// The table's meshes, built from the server's geometry (GET /web/tables): cloth with pocket
// holes, a cushion along every nose segment with its rounded jaws, the wooden rails, sights,
// and the markings of each game (snooker's baulk line, D and spots; pool's and carom's spots).
import * as THREE from "three";
import { TABLE_COLOURS } from "../lib/looks.js";

/** Width of the rubber cushion behind its nose, and of the wooden rail behind that (m). */
const CUSHION_WIDTH = 0.05;
const RAIL_WIDTH = 0.11;
/** The drawn pocket hole is a little wider than the engine's capture circle. */
const HOLE_SCALE = 1.15;

/**
 * Engine coordinates (x across, y along, z up) to three.js world ones (y up), with the table's
 * centre at the origin: X = x - w/2, Y = z, Z = l/2 - y. A proper rotation, so spins map alike.
 */
export function frame(table) {
  const toWorld = (x, y, z = 0) => new THREE.Vector3(x - table.w / 2, z, table.l / 2 - y);
  const toTable = (v) => [v.x + table.w / 2, table.l / 2 - v.z];
  const vector = (x, y, z) => new THREE.Vector3(x, z, -y);
  return { toWorld, toTable, vector };
}

/** A shape in the table plane (engine x, y), to be laid flat with `layFlat`. */
function shapeOf(points) {
  return new THREE.Shape(points.map(([x, y]) => new THREE.Vector2(x, y)));
}

/** A mesh whose geometry is in engine coordinates (shape x, y; extrusion along z) laid on the table. */
function layFlat(geometry, material, table, z = 0) {
  const mesh = new THREE.Mesh(geometry, material);
  // (x, y, z) -> (x - w/2, z, l/2 - y): rotate -90 degrees about x, then translate.
  mesh.rotation.x = -Math.PI / 2;
  mesh.position.set(-table.w / 2, z, table.l / 2);
  mesh.receiveShadow = true;
  return mesh;
}

/** The table's outer edge: the playing surface with cushions and rails round it. */
function outline(table) {
  const m = CUSHION_WIDTH + RAIL_WIDTH;
  return shapeOf([
    [-m, -m],
    [table.w + m, -m],
    [table.w + m, table.l + m],
    [-m, table.l + m],
  ]);
}

function circlePath(cx, cy, r) {
  const path = new THREE.Path();
  path.absarc(cx, cy, r, 0, Math.PI * 2, true);
  return path;
}

function cloth(table, colours) {
  const shape = outline(table);
  for (const p of table.pockets) shape.holes.push(circlePath(p.center[0], p.center[1], p.radius * HOLE_SCALE));
  const material = new THREE.MeshStandardMaterial({ color: colours.cloth, roughness: 0.95 });
  return layFlat(new THREE.ShapeGeometry(shape, 24), material, table);
}

function pocketCups(table, group) {
  const black = new THREE.MeshBasicMaterial({ color: 0x050505, side: THREE.DoubleSide });
  const { toWorld } = frame(table);
  for (const p of table.pockets) {
    const r = p.radius * HOLE_SCALE;
    const cup = new THREE.Mesh(new THREE.CylinderGeometry(r, r * 0.8, 0.12, 24, 1, true), black);
    cup.position.copy(toWorld(p.center[0], p.center[1], -0.06));
    group.add(cup);
    const bottom = new THREE.Mesh(new THREE.CircleGeometry(r, 24), black);
    bottom.rotation.x = -Math.PI / 2;
    bottom.position.copy(toWorld(p.center[0], p.center[1], -0.1));
    group.add(bottom);
  }
}

function cushions(table, colours, group) {
  const material = new THREE.MeshStandardMaterial({ color: colours.cushion, roughness: 0.9 });
  const height = table.cushion_height + 0.008;
  // Without pockets the rails meet in the corners: their backs are mitred to close them.
  const mitre = table.pockets.length ? 0 : CUSHION_WIDTH;
  for (const c of table.cushions) {
    const [nx, ny] = c.normal;
    const length = Math.hypot(c.p2[0] - c.p1[0], c.p2[1] - c.p1[1]);
    const t = [(c.p2[0] - c.p1[0]) / length, (c.p2[1] - c.p1[1]) / length];
    const back = (p, along) => [p[0] - nx * CUSHION_WIDTH + t[0] * along, p[1] - ny * CUSHION_WIDTH + t[1] * along];
    const shape = shapeOf([c.p1, c.p2, back(c.p2, mitre), back(c.p1, -mitre)]);
    const geometry = new THREE.ExtrudeGeometry(shape, { depth: height, bevelEnabled: false });
    group.add(layFlat(geometry, material, table));
  }
  const { toWorld } = frame(table);
  for (const j of table.jaws) {
    const jaw = new THREE.Mesh(new THREE.CylinderGeometry(j.radius, j.radius, height, 16), material);
    jaw.position.copy(toWorld(j.center[0], j.center[1], height / 2));
    jaw.castShadow = false;
    group.add(jaw);
  }
}

/** The inner edge of the rails: the rectangle behind the cushions, bulging round each pocket
 *  hole (points of the rectangle inside a hole are pushed out along the radius to its rim). */
function railEdge(table) {
  const c = CUSHION_WIDTH;
  const corners = [
    [-c, -c],
    [table.w + c, -c],
    [table.w + c, table.l + c],
    [-c, table.l + c],
  ];
  const points = [];
  const step = 0.004;
  for (let k = 0; k < 4; k++) {
    const [x0, y0] = corners[k];
    const [x1, y1] = corners[(k + 1) % 4];
    const n = Math.ceil(Math.hypot(x1 - x0, y1 - y0) / step);
    for (let i = 0; i < n; i++) {
      let x = x0 + ((x1 - x0) * i) / n;
      let y = y0 + ((y1 - y0) * i) / n;
      for (const p of table.pockets) {
        const r = p.radius * HOLE_SCALE;
        const dx = x - p.center[0];
        const dy = y - p.center[1];
        const d = Math.hypot(dx, dy);
        if (d < r && d > 0) [x, y] = [p.center[0] + (dx / d) * r, p.center[1] + (dy / d) * r];
      }
      points.push(new THREE.Vector2(x, y));
    }
  }
  return new THREE.Path(points);
}

function rails(table, colours, group) {
  const material = new THREE.MeshStandardMaterial({ color: colours.rail, roughness: 0.45, metalness: 0.05 });
  const top = table.cushion_height + 0.012;
  const shape = outline(table);
  shape.holes.push(railEdge(table));
  const geometry = new THREE.ExtrudeGeometry(shape, { depth: top + 0.04, bevelEnabled: false, curveSegments: 4 });
  group.add(layFlat(geometry, material, table, -0.04));
  return top;
}

function flatDisc(radius, colour) {
  const mesh = new THREE.Mesh(new THREE.CircleGeometry(radius, 16), new THREE.MeshBasicMaterial({ color: colour }));
  mesh.rotation.x = -Math.PI / 2;
  return mesh;
}

function sights(table, group, railTop) {
  const { toWorld } = frame(table);
  const mid = CUSHION_WIDTH + RAIL_WIDTH / 2;
  const add = (x, y) => {
    const d = flatDisc(0.006, 0xf1ead2);
    d.position.copy(toWorld(x, y, railTop + 0.0006));
    group.add(d);
  };
  for (let k = 1; k < 8; k++) {
    if (k === 4 && table.pockets.length) continue;
    add(-mid, (table.l * k) / 8);
    add(table.w + mid, (table.l * k) / 8);
  }
  for (let k = 1; k < 4; k++) {
    add((table.w * k) / 4, -mid);
    add((table.w * k) / 4, table.l + mid);
  }
}

function markings(table, group) {
  const { toWorld } = frame(table);
  const white = new THREE.MeshBasicMaterial({ color: 0xe8efe6, transparent: true, opacity: 0.75 });
  const lift = 0.0004;
  for (const p of Object.values(table.spots)) {
    const spot = flatDisc(0.004, 0xe8efe6);
    spot.position.copy(toWorld(p[0], p[1], lift));
    group.add(spot);
  }
  if (table.baulk_y != null) {
    const line = new THREE.Mesh(new THREE.PlaneGeometry(table.w, 0.003), white);
    line.rotation.x = -Math.PI / 2;
    line.position.copy(toWorld(table.w / 2, table.baulk_y, lift));
    group.add(line);
    // The D: the half circle on the baulk side (engine y < baulk_y, world +z).
    const d = new THREE.Mesh(new THREE.RingGeometry(table.d_radius - 0.0015, table.d_radius + 0.0015, 64, 1, Math.PI, Math.PI), white);
    d.rotation.x = -Math.PI / 2;
    d.position.copy(toWorld(table.w / 2, table.baulk_y, lift));
    group.add(d);
  }
}

/** The whole table as one group, with the height of its rails (for the cameras). */
export function makeTable(table, game) {
  const colours = TABLE_COLOURS[game];
  const group = new THREE.Group();
  group.add(cloth(table, colours));
  pocketCups(table, group);
  cushions(table, colours, group);
  const railTop = rails(table, colours, group);
  if (game !== "snooker") sights(table, group, railTop);
  markings(table, group);
  return { group, railTop, extent: { w: table.w + 2 * (CUSHION_WIDTH + RAIL_WIDTH), l: table.l + 2 * (CUSHION_WIDTH + RAIL_WIDTH) } };
}
