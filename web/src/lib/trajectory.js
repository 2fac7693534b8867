// Exact ball motion from the server's trajectory segments, with no physics of our own.
//
// A segment is the array [t, state, rx, ry, vx, vy, ax, ay, wx, wy, wz, dwx, dwy, dwz]
// (docs/protocol.md). Within it, with tau = time - t until the next segment's t:
//   position         = r + v tau + a tau^2 / 2
//   velocity         = v + a tau
//   angular velocity = w + dw tau
// Coordinates are the engine's: x across the table, y along it, z up; metres, seconds, rad/s.

const T = 0;
const STATE = 1;

/** The index of the last segment begun by time t (0 before the first). */
export function segmentIndex(segments, t) {
  let lo = 0;
  let hi = segments.length - 1;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (segments[mid][T] <= t) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

/** Seconds into segment s at time t; a resting or pocketed ball does not move on. */
function tauOf(s, t) {
  const state = s[STATE];
  if (state === "stationary" || state === "pocketed") return 0;
  return Math.max(0, t - s[T]);
}

/** [x, y] of a ball at time t. */
export function positionAt(segments, t) {
  const s = segments[segmentIndex(segments, t)];
  const tau = tauOf(s, t);
  return [s[2] + s[4] * tau + 0.5 * s[6] * tau * tau, s[3] + s[5] * tau + 0.5 * s[7] * tau * tau];
}

/** [vx, vy] at time t. */
export function velocityAt(segments, t) {
  const s = segments[segmentIndex(segments, t)];
  const tau = tauOf(s, t);
  return [s[4] + s[6] * tau, s[5] + s[7] * tau];
}

/** [wx, wy, wz] at time t (rad/s); zero once pocketed. */
export function spinAt(segments, t) {
  const s = segments[segmentIndex(segments, t)];
  if (s[STATE] === "pocketed") return [0, 0, 0];
  const tau = s[STATE] === "stationary" ? 0 : Math.max(0, t - s[T]);
  return [s[8] + s[11] * tau, s[9] + s[12] * tau, s[10] + s[13] * tau];
}

/** When the ball fell in a pocket (Infinity if it stays on the table). */
export function pocketedAt(segments) {
  const last = segments[segments.length - 1];
  return last[STATE] === "pocketed" ? last[T] : Infinity;
}

/** Longest rotation step (s): midpoint steps this short keep a ball within a fraction of a
 *  degree of its exact orientation even at break speeds. */
export const MAX_ROTATION_STEP = 1 / 240;

/**
 * The rotation a ball turns through between t0 and t1, as a unit quaternion [x, y, z, w] in the
 * engine's frame: the midpoint spin of each step (steps split at segment starts) times its length.
 */
export function rotationBetween(segments, t0, t1) {
  let q = [0, 0, 0, 1];
  let t = t0;
  while (t < t1) {
    const i = segmentIndex(segments, t);
    const next = i + 1 < segments.length ? segments[i + 1][T] : Infinity;
    const end = Math.min(t1, next, t + MAX_ROTATION_STEP);
    q = multiply(axisAngle(spinAt(segments, (t + end) / 2), end - t), q);
    t = end;
  }
  return q;
}

/** The quaternion of turning at angular velocity w for dt seconds. */
export function axisAngle(w, dt) {
  const speed = Math.hypot(w[0], w[1], w[2]);
  const angle = speed * dt;
  if (angle < 1e-12) return [0, 0, 0, 1];
  const s = Math.sin(angle / 2) / speed;
  return [w[0] * s, w[1] * s, w[2] * s, Math.cos(angle / 2)];
}

/** Hamilton product a*b of quaternions [x, y, z, w]: the rotation b, then a. */
export function multiply(a, b) {
  const [ax, ay, az, aw] = a;
  const [bx, by, bz, bw] = b;
  return [
    aw * bx + ax * bw + ay * bz - az * by,
    aw * by - ax * bz + ay * bw + az * bx,
    aw * bz + ax * by - ay * bx + az * bw,
    aw * bw - ax * bx - ay * by - az * bz,
  ];
}

/** Half the window (s) around an event in which the speeds before and after it are read: wider
 *  than the rounding of the segments' start times on the wire, far shorter than any motion. */
const EVENT_EPS = 1e-5;

/**
 * How hard event `event` ({t, type, balls}) of a shot struck, in m/s, from its balls' segments
 * (`balls`: {id: segments}): for a strike, the cue ball's speed just after; for ball on ball,
 * the two balls' relative speed just before; for a cushion, a jaw or a pocket, the ball's speed
 * just before. (The sounds' loudness.)
 */
export function eventSpeed(balls, event) {
  const [first, second] = event.balls;
  if (event.type === "strike") return Math.hypot(...velocityAt(balls[first], event.t + EVENT_EPS));
  const v = velocityAt(balls[first], event.t - EVENT_EPS);
  const w = second && balls[second] ? velocityAt(balls[second], event.t - EVENT_EPS) : [0, 0];
  return Math.hypot(v[0] - w[0], v[1] - w[1]);
}
