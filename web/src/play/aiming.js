// Where the cue first points, and the bot lining up its shot. The legal first contacts are the
// server's (next.shot.targets); this only finds a line on which the first ball met is one.

/** Largest offset (degrees) tried either side of a target's centre for a clear line. */
const WIDEST = 4;
const OFFSET_STEP = 0.1;
/** The bot's cue swings onto its line in this long, then rests before the stroke (ms). */
const BOT_AIM_MS = 700;
const BOT_PAUSE_MS = 450;

const degrees = (radians) => (radians * 180) / Math.PI;

/** {heading (degrees), clear} from cue ball `cue`: a heading whose first ball is one of
 *  `targets` (clear), the nearest target tried first and a few degrees either side of its
 *  centre if another ball is in the way; if no straight line is clear, the nearest target's
 *  centre (not clear: a cushion first, or a foul); null without targets on the table. */
export function aimAtTarget(view3d, cue, targets) {
  const from = view3d.ballAt(cue);
  if (!from || !targets?.length) return null;
  const near = targets
    .map((id) => view3d.ballAt(id))
    .filter(Boolean)
    .map((p) => ({ p, d: Math.hypot(p[0] - from[0], p[1] - from[1]) }))
    .sort((x, y) => x.d - y.d);
  if (!near.length) return null;
  const legalAlong = (heading) => {
    const h = (heading * Math.PI) / 180;
    return targets.includes(view3d.firstContact(from, [Math.cos(h), Math.sin(h)]).ball);
  };
  for (const { p } of near) {
    const centre = degrees(Math.atan2(p[1] - from[1], p[0] - from[0]));
    for (let off = 0; off <= WIDEST; off += OFFSET_STEP) {
      for (const h of off ? [centre + off, centre - off] : [centre]) if (legalAlong(h)) return { heading: h, clear: true };
    }
  }
  const p = near[0].p;
  return { heading: degrees(Math.atan2(p[1] - from[1], p[0] - from[0])), clear: false };
}

const pause = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/** Show the bot's cue swinging onto the line of its stroke `input`, then a short rest: what a
 *  player watching would see of a person lining up. */
export async function showBotAim(view3d, view, input) {
  const strike = input.strike;
  if (!strike) return;
  if (input.place) view3d.setBalls({ ...view.state.balls, [strike.ball]: input.place });
  const start = strike.heading + 20;
  const aim = { elevation: strike.elevation, a: strike.a, b: strike.b, power: 0.3 };
  const t0 = performance.now();
  await new Promise((resolve) => {
    const step = (now) => {
      const f = Math.min(1, (now - t0) / BOT_AIM_MS);
      const ease = 1 - (1 - f) ** 3;
      view3d.setAim(strike.ball, { ...aim, heading: start + (strike.heading - start) * ease });
      if (f < 1) requestAnimationFrame(step);
      else resolve();
    };
    requestAnimationFrame(step);
  });
  view3d.botAims = (view3d.botAims ?? 0) + 1;
  await pause(BOT_PAUSE_MS);
  view3d.setAim(null, aim);
}
