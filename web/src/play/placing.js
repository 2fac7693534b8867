// Ball in hand in the page: where to put the cue ball first, and whether a place is clear of
// the other balls and inside the region the server allows (next.shot.place). The server still
// judges the place; this only keeps the player from sending one it would refuse.
import { insideOutline, regionOutline } from "../three/region.js";

/** Keyboard placement steps (m), without and with Ctrl. */
export const PLACE_STEP = 0.005;
export const FINE_PLACE_STEP = 0.001;

/** The ball that a cue ball at p would overlap ({id, at}), or null. */
export function overlap(table, balls, cue, p) {
  for (const [id, q] of Object.entries(balls)) {
    if (id !== cue && Math.hypot(q[0] - p[0], q[1] - p[1]) < 2 * table.R) return { id, at: q };
  }
  return null;
}

/** Whether p is in region `region` (as drawn from the table's geometry). */
export function inRegion(table, region, p) {
  const outline = regionOutline(table, region);
  return outline ? insideOutline(outline, p) : true;
}

/** p if it is in `region`, else the point of the region nearest it on the way from `inside`
 *  (a point in the region): a drag or a key past the region's edge stops at the edge. */
export function keepInRegion(table, region, inside, p) {
  if (inRegion(table, region, p)) return p;
  let [lo, hi] = [0, 1];
  for (let k = 0; k < 24; k++) {
    const mid = (lo + hi) / 2;
    const q = [inside[0] + (p[0] - inside[0]) * mid, inside[1] + (p[1] - inside[1]) * mid];
    if (inRegion(table, region, q)) lo = mid;
    else hi = mid;
  }
  return [inside[0] + (p[0] - inside[0]) * lo, inside[1] + (p[1] - inside[1]) * lo];
}

/** The region's usual spot: pool's head spot, the middle of snooker's D, else the table's centre. */
export function usualSpot(table, region) {
  if (region === "D") return [table.w / 2, table.baulk_y - table.d_radius / 2];
  if (region === "kitchen") return table.spots.head ?? [table.w / 2, table.head_string_y / 2];
  return [table.w / 2, table.l / 4];
}

/** The free point of `region` nearest `from` (default: the region's usual spot), searched on
 *  rings round it, or null if none is found. */
export function freePlace(table, region, balls, cue, from = usualSpot(table, region)) {
  const ok = (p) => inRegion(table, region, p) && !overlap(table, balls, cue, p);
  for (let ring = 0; ring < 40; ring++) {
    const count = Math.max(1, ring * 8);
    for (let k = 0; k < count; k++) {
      const a = (2 * Math.PI * k) / count;
      const p = [from[0] + ring * 0.5 * table.R * Math.cos(a), from[1] + ring * 0.5 * table.R * Math.sin(a)];
      if (ok(p)) return p;
    }
  }
  return null;
}
