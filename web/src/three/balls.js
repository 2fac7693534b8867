// Ball meshes: a sphere with a painted equirectangular texture (colour, stripe, number discs).
import * as THREE from "three";
import { ballLook } from "../lib/looks.js";

const W = 256;
const H = 128;

/** Paint a spherical cap of angular radius rho centred on (lat0 = 0, lon0) onto the canvas. */
function cap(ctx, lon0, lat0, rho, colour) {
  ctx.fillStyle = colour;
  for (let row = 0; row < H; row++) {
    const lat = Math.PI / 2 - ((row + 0.5) / H) * Math.PI;
    // cos d = sin lat sin lat0 + cos lat cos lat0 cos(dlon) <= cos rho
    const c = (Math.cos(rho) - Math.sin(lat) * Math.sin(lat0)) / (Math.cos(lat) * Math.cos(lat0));
    if (c > 1) continue;
    const half = c <= -1 ? Math.PI : Math.acos(c);
    const x0 = ((lon0 - half) / (2 * Math.PI)) * W;
    const width = ((2 * half) / (2 * Math.PI)) * W;
    for (const shift of [-W, 0, W]) ctx.fillRect(x0 + shift, row, width, 1);
  }
}

/** The canvas texture of one ball; three.js maps u = 0.25 to the sphere's +z, 0.75 to -z. */
function paint(look) {
  const canvas = document.createElement("canvas");
  canvas.width = W;
  canvas.height = H;
  const ctx = canvas.getContext("2d");
  ctx.fillStyle = look.stripe ? "#f6f3e8" : look.colour;
  ctx.fillRect(0, 0, W, H);
  if (look.stripe) {
    ctx.fillStyle = look.colour;
    ctx.fillRect(0, H * 0.3, W, H * 0.4);
  }
  if (look.number) {
    for (const u of [0.25, 0.75]) {
      cap(ctx, u * 2 * Math.PI, 0, 0.42, "#f6f3e8");
      ctx.fillStyle = "#111";
      ctx.font = `bold ${look.number.length > 1 ? 20 : 24}px sans-serif`;
      ctx.textAlign = "center";
      ctx.textBaseline = "middle";
      ctx.fillText(look.number, u * W, H / 2 + 1);
    }
  }
  if (look.dots) {
    for (const [lon, lat] of [[0, 0], [0.5, 0], [0.25, 0], [0.75, 0], [0, 1.2], [0.5, -1.2]]) {
      cap(ctx, lon * 2 * Math.PI, lat, 0.12, look.dots);
    }
  }
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  texture.anisotropy = 4;
  return texture;
}

/** The sphere's number disc (+z) turned to face up, so numbers read from the top view. */
const NUMBER_UP = new THREE.Quaternion().setFromAxisAngle(new THREE.Vector3(1, 0, 0), -Math.PI / 2);

/** One mesh per ball id, sharing one sphere geometry. */
export function makeBalls(game, ids, R) {
  const geometry = new THREE.SphereGeometry(R, 32, 20);
  const meshes = new Map();
  for (const id of ids) {
    const material = new THREE.MeshStandardMaterial({ map: paint(ballLook(game, id)), roughness: 0.18, metalness: 0.0 });
    const mesh = new THREE.Mesh(geometry, material);
    mesh.castShadow = true;
    mesh.quaternion.copy(NUMBER_UP);
    mesh.name = id;
    meshes.set(id, mesh);
  }
  return meshes;
}
