// The shooter's aim shown to the opponent and spectators (POST /api/tables/{id}/aim, an `aim`
// message on the table channel): sent at most once per 250 ms, the last aim always sent, so
// the watchers see the cue settle where the shooter left it. The server never plays it.

/** Least time between two aims sent (ms): the server refuses more (rate_limited). */
const AIM_EVERY_MS = 250;

export class AimShare {
  /** send(body) posts one aim; failures (a turn just ended, a dropped link) are dropped. */
  constructor(send) {
    this.send = send;
    this.last = -Infinity;
    this.waiting = null; // the aim to send when the interval allows
    this.timer = null;
    this.inflight = Promise.resolve(); // the last aim sent, until the server has answered
  }

  /** Share aim {heading, power, elevation, a, b} with the cue ball at `place` (or null). */
  offer(aim, place) {
    const round = (x) => Number(x.toFixed(3));
    this.waiting = { heading: round(aim.heading), power: round(aim.power), elevation: aim.elevation, a: round(aim.a), b: round(aim.b), place };
    if (this.timer) return;
    const wait = Math.max(0, this.last + AIM_EVERY_MS - performance.now());
    this.timer = setTimeout(() => this.flush(), wait);
  }

  flush() {
    this.timer = null;
    if (!this.waiting) return;
    this.last = performance.now();
    const body = this.waiting;
    this.waiting = null;
    this.inflight = this.send(body).catch(() => {});
  }

  /** Resolves once no aim is on its way: a shot sent after it cannot overtake it (the aim of
   *  a turn already played would be refused). */
  settled() {
    return this.inflight;
  }

  /** Forget an aim not yet sent (the shot was played, the turn passed). */
  cancel() {
    clearTimeout(this.timer);
    this.timer = null;
    this.waiting = null;
  }
}
