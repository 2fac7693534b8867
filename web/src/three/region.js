// The ball-in-hand region the server allows (next.shot.place), drawn on the cloth: pool's
// kitchen (behind the head string), snooker's D, or the whole bed ("anywhere"). The region's
// name is the server's; its shape comes from the table geometry the server sends (/web/tables).
import * as THREE from "three";

const FILL = 0x9fe3ff;
const LIFT = 0.0008;

/** The region's outline in table coordinates (a convex polygon, counter-clockwise), or null. */
export function regionOutline(table, region) {
  const { w, l, R } = table;
  if (region === "kitchen" && table.head_string_y != null) {
    const y = table.head_string_y;
    return [
      [R, R],
      [w - R, R],
      [w - R, y],
      [R, y],
    ];
  }
  if (region === "D" && table.d_radius != null) {
    const points = [];
    for (let k = 0; k <= 32; k++) {
      const a = Math.PI + (Math.PI * k) / 32; // the half circle on the baulk side
      // Its ends exactly on the baulk line, which belongs to the D.
      const y = k % 32 === 0 ? table.baulk_y : table.baulk_y + table.d_radius * Math.sin(a);
      points.push([w / 2 + table.d_radius * Math.cos(a), y]);
    }
    return points;
  }
  if (region === "anywhere") {
    return [
      [R, R],
      [w - R, R],
      [w - R, l - R],
      [R, l - R],
    ];
  }
  return null;
}

/** Whether table point p lies in the convex counter-clockwise polygon `outline`, edges
 *  included (a point on the region's line is in, as the referee has it). */
export function insideOutline(outline, p) {
  return outline.every(([ax, ay], i) => {
    const [bx, by] = outline[(i + 1) % outline.length];
    return (bx - ax) * (p[1] - ay) - (by - ay) * (p[0] - ax) >= 0;
  });
}

/** A translucent fill and an outline of `outline` on the cloth (world coordinates by `toWorld`). */
export function regionMesh(outline, toWorld) {
  const group = new THREE.Group();
  const corners = outline.map(([x, y]) => toWorld(x, y, LIFT));
  const fan = [];
  for (let i = 1; i < corners.length - 1; i++) fan.push(corners[0], corners[i], corners[i + 1]);
  const fill = new THREE.Mesh(
    new THREE.BufferGeometry().setFromPoints(fan),
    new THREE.MeshBasicMaterial({ color: FILL, transparent: true, opacity: 0.16, side: THREE.DoubleSide, depthWrite: false }),
  );
  const edge = new THREE.LineLoop(new THREE.BufferGeometry().setFromPoints(corners), new THREE.LineBasicMaterial({ color: FILL }));
  group.add(fill, edge);
  return group;
}
