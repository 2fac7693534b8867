// Plays a shot's trajectory on a TableScene at the display's frame rate: every frame evaluates
// each ball's polynomial segment at the shot's clock and turns the ball by the spin it had
// meanwhile. A pocketed ball sinks into its pocket's hole and disappears. Each event the clock
// passes while playing is handed to `onEvent` (the sounds).
import * as THREE from "three";
import { eventSpeed, pocketedAt, positionAt, rotationBetween } from "../lib/trajectory.js";

/** How long a pocketed ball takes to drop out of sight (s of shot time). */
const DROP_TIME = 0.18;

export class Animation {
  /**
   * view: the TableScene; trajectory: {duration, events, balls: {id: [segment, ...]}};
   * onDone: called once when the shot has played to its end (not when stopped);
   * onEvent(type, speed): each event as the clock reaches it while playing, with how hard it
   * struck (m/s, lib/trajectory.js eventSpeed).
   */
  constructor(view, trajectory, { speed = 1, onDone = () => {}, onEvent = () => {} } = {}) {
    this.view = view;
    this.trajectory = trajectory;
    this.speed = speed;
    this.onDone = onDone;
    this.onEvent = onEvent;
    this.nextEvent = 0; // the first event the clock has not yet reached
    this.time = 0;
    this.paused = false;
    this.last = null;
    this.frameTimes = []; // intervals between frames (ms): the frame rate achieved
    this.pockets = new Map();
    const byName = new Map(view.table.pockets.map((p) => [p.name, p.center]));
    for (const e of trajectory.events) {
      if (e.type === "ball_pocket" && byName.has(e.pocket)) this.pockets.set(e.balls[0], byName.get(e.pocket));
    }
    // Orientation of every ball at shot time 0, to start from again when seeking backwards.
    this.start = new Map([...view.balls].map(([id, mesh]) => [id, mesh.quaternion.clone()]));
    this.hook = (now) => this.frame(now);
  }

  play() {
    this.view.drawTimes = [];
    this.view.setBalls(this.positions(0));
    this.view.animating += 1;
    this.view.setScale(this.view.scale);
    this.view.frameHooks.push(this.hook);
    this.view.invalidate();
    return this;
  }

  stop() {
    const hooks = this.view.frameHooks;
    const i = hooks.indexOf(this.hook);
    if (i < 0) return;
    hooks.splice(i, 1);
    this.view.animating -= 1;
    if (!this.view.animating) this.view.setScale(1);
    this.view.invalidate();
  }

  positions(t) {
    const out = {};
    for (const [id, segments] of Object.entries(this.trajectory.balls)) {
      if (t < pocketedAt(segments) + DROP_TIME) out[id] = positionAt(segments, t);
    }
    return out;
  }

  frame(now) {
    if (this.last !== null) this.frameTimes.push(now - this.last);
    else this.firstFrameAt = now; // when the motion was first drawn (performance.now() time)
    const dt = this.last === null || this.paused ? 0 : ((now - this.last) / 1000) * this.speed;
    this.last = now;
    this.seek(Math.min(this.trajectory.duration, this.time + dt));
    const { events, balls } = this.trajectory;
    while (this.nextEvent < events.length && events[this.nextEvent].t <= this.time) {
      const e = events[this.nextEvent++];
      this.onEvent(e.type, eventSpeed(balls, e));
    }
    if (this.time >= this.trajectory.duration) {
      this.stop();
      this.onDone();
    }
  }

  /** Show the table at shot time t (forwards from the current time, or again from 0). */
  seek(t) {
    const { view } = this;
    const from = t >= this.time ? this.time : 0;
    if (t < this.time) {
      const next = this.trajectory.events.findIndex((e) => e.t > t); // back: silent until then
      this.nextEvent = next < 0 ? this.trajectory.events.length : next;
    }
    const R = view.table.R;
    for (const [id, segments] of Object.entries(this.trajectory.balls)) {
      const mesh = view.balls.get(id);
      if (!mesh) continue;
      if (from === 0 && t < this.time) mesh.quaternion.copy(this.start.get(id));
      const [qx, qy, qz, qw] = rotationBetween(segments, from, t);
      // The engine's (x, y, z) is three's (x, z, -y): the same rotation, axes renamed.
      mesh.quaternion.premultiply(new THREE.Quaternion(qx, qz, -qy, qw));
      const fell = pocketedAt(segments);
      let [x, y] = positionAt(segments, t);
      let z = R;
      if (t >= fell) {
        const k = Math.min(1, (t - fell) / DROP_TIME);
        const centre = this.pockets.get(id) ?? [x, y];
        x += (centre[0] - x) * k;
        y += (centre[1] - y) * k;
        z = R - 3 * R * k;
        mesh.visible = k < 1;
      } else {
        mesh.visible = true;
      }
      mesh.position.copy(view.frame.toWorld(x, y, z));
    }
    this.time = t;
  }
}
