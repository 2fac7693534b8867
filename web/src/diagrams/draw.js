// A top view of (part of) the table on a canvas: the engine's metres (x across the table, y
// along it) to pixels, the table's long axis across the screen. Nothing here is physics: the
// server answers every point drawn.

export const CLOTH = "#14522f";
const RAIL = "#6b3f1f";
/** The balls' colours by name: the families' cue and object ball, the recordings' 1, 2, 3. */
export const BALL_COLOURS = { cue: "#f4f1e8", object: "#d23a2a", 1: "#f4f1e8", 2: "#e8c840", 3: "#d23a2a" };
/** One colour per shot of a family. */
export const SHOT_COLOURS = ["#ffd166", "#06d6a0", "#4cc9f0", "#f72585", "#b5e48c", "#ff9f1c", "#cdb4db"];

/** The box {x0, y0, x1, y1} around every point, grown by `pad` metres. */
export function bounds(points, pad) {
  const xs = points.map((p) => p[0]);
  const ys = points.map((p) => p[1]);
  return { x0: Math.min(...xs) - pad, x1: Math.max(...xs) + pad, y0: Math.min(...ys) - pad, y1: Math.max(...ys) + pad };
}

export class View {
  /** Fit `box` into the canvas (its height set from the box's shape, within [minH, maxH]). */
  constructor(canvas, box, { minH = 160, maxH = 520 } = {}) {
    const across = box.y1 - box.y0;
    const down = box.x1 - box.x0;
    canvas.height = Math.round(Math.min(maxH, Math.max(minH, (canvas.width * down) / across)));
    this.ctx = canvas.getContext("2d");
    this.box = box;
    this.s = Math.min(canvas.width / across, canvas.height / down);
    this.ox = (canvas.width - across * this.s) / 2;
    this.oy = (canvas.height - down * this.s) / 2;
    this.ctx.fillStyle = CLOTH;
    this.ctx.fillRect(0, 0, canvas.width, canvas.height);
  }

  px(p) {
    return [this.ox + (p[1] - this.box.y0) * this.s, this.oy + (p[0] - this.box.x0) * this.s];
  }

  line(points, colour, width = 1.5, dash = []) {
    if (points.length < 2) return;
    const c = this.ctx;
    c.save();
    c.strokeStyle = colour;
    c.lineWidth = width;
    c.setLineDash(dash);
    c.beginPath();
    points.forEach((p, i) => (i ? c.lineTo(...this.px(p)) : c.moveTo(...this.px(p))));
    c.stroke();
    c.restore();
  }

  ball(p, R, colour) {
    const c = this.ctx;
    const [u, v] = this.px(p);
    c.beginPath();
    c.arc(u, v, Math.max(2, R * this.s), 0, 2 * Math.PI);
    c.fillStyle = colour;
    c.fill();
    c.strokeStyle = "#000";
    c.lineWidth = 0.8;
    c.stroke();
  }

  /** The cushion lines (ball-centre limits are R inside them) of a W x L table. */
  rails(W, L) {
    this.line([[0, 0], [W, 0], [W, L], [0, L], [0, 0]], RAIL, 4);
  }
}
